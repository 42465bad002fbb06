"""The numeric CSV every sweep and motion log is read from and written to."""
from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Dict, Sequence, Union

import numpy as np

from ..errors import DataError


def read_text(path: Union[str, Path]) -> str:
    """A text file's contents; a file that is not UTF-8 or cannot be read is a ``DataError``."""
    try:
        return Path(path).read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise DataError(f"{path}: not UTF-8 text (byte 0x{exc.object[exc.start]:02x} at offset "
                        f"{exc.start})") from None


def read_table_csv(path: Union[str, Path], required: Sequence[str],
                   keep_extra: bool = False) -> Dict[str, np.ndarray]:
    """Read a numeric CSV whose header names (at least) the ``required`` columns.

    Returns the columns by lower-case name: the required ones and, with ``keep_extra``, all
    others. Blank lines are skipped; a missing column or a non-numeric cell raises ``DataError``
    naming the file and line. Finiteness and lengths are for the caller to judge.
    """
    try:
        rows = list(csv.reader(io.StringIO(read_text(path))))
    except csv.Error as exc:
        raise DataError(f"{path}: not a readable CSV ({exc})") from None
    if not rows:
        raise DataError(f"{path}: empty file")
    header = [h.strip().lower() for h in rows[0]]
    repeated = sorted({h for h in header if h and header.count(h) > 1})
    if repeated:
        raise DataError(f"{path}: column {repeated[0]!r} appears more than once in the header")
    missing = [c for c in required if c not in header]
    if missing:
        hint = "; it looks ';'-separated: fricgen reads ','-separated CSV with '.' decimals" \
            if any(";" in h for h in header) else ""
        raise DataError(f"{path}: missing column {', '.join(repr(c) for c in missing)} "
                        f"(header is {','.join(header)[:80]}){hint}")
    wanted = [k for k, h in enumerate(header) if keep_extra or h in required]
    data = []
    for n, row in enumerate(rows[1:], start=2):
        if len(row) != len(header) and any(c.strip() for c in row):
            raise DataError(f"{path}: line {n}: {len(row)} cells, the header names {len(header)}")
        if not any(c.strip() for c in row):
            continue
        try:
            data.append([float(row[k]) for k in wanted])
        except ValueError:
            raise DataError(f"{path}: line {n}: non-numeric or missing cell in "
                            f"{','.join(row)[:80]!r}") from None
    table = np.array(data, dtype=float).reshape(len(data), len(wanted))
    return {header[k]: table[:, j] for j, k in enumerate(wanted)}


def table_csv_text(columns: Dict[str, np.ndarray]) -> str:
    """CSV text of named columns (in the given order), floats written to round-trip."""
    names = list(columns)
    lines = [",".join(names)]
    lines += [",".join(repr(float(c)) for c in row)
              for row in zip(*(np.asarray(columns[k]).tolist() for k in names))]
    return "\n".join(lines) + "\n"
