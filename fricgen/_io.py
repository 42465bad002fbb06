"""Files in and out: atomic writes, the numeric CSV reader and writer, the shipped resources."""
from __future__ import annotations

import csv
import io
import os
import tempfile
from pathlib import Path
from typing import Dict, Sequence, Union

import numpy as np

from .errors import DataError

#: Shipped resource folders: where a wheel installs them inside the package, and where a source
#: checkout keeps them (relative to the repository's top).
RESOURCES = {"templates": "templates", "c_runtime": "c_runtime",
             "firmware_sources": "examples/firmware"}


def resource_dir(kind: str) -> Path:
    """The folder of the shipped ``templates``, ``c_runtime`` or ``firmware_sources`` files.

    A wheel installs them inside the package (``fricgen/templates``); a source checkout keeps
    them at the top of the repository, beside ``fricgen/``.
    """
    if kind not in RESOURCES:
        raise ValueError(f"kind must be one of {sorted(RESOURCES)}, got {kind!r}")
    package = Path(__file__).resolve().parent
    for path in (package / kind, package.parent / RESOURCES[kind]):
        if path.is_dir():
            return path
    raise FileNotFoundError(f"fricgen {kind} folder not found beside {package} (broken install?)")


def write_atomic(path: Union[str, Path], text: Union[str, bytes]) -> Path:
    """Write ``text`` (str, or bytes for binary files) to ``path`` through a temporary file in
    the same folder and a rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb" if isinstance(text, bytes) else "w") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def write_all_atomic(folder: Union[str, Path], files: Dict[str, Union[str, bytes]]) -> Dict[str, Path]:
    """Write several files (all content already rendered) into ``folder``, each atomically."""
    return {name: write_atomic(Path(folder) / name, text) for name, text in files.items()}


def read_table_csv(path: Union[str, Path], required: Sequence[str],
                   keep_extra: bool = False) -> Dict[str, np.ndarray]:
    """Read a numeric CSV whose header names (at least) the ``required`` columns.

    Returns the columns by lower-case name: the required ones and, with ``keep_extra``, all
    others. Blank lines are skipped; a missing column or a non-numeric cell raises ``DataError``
    naming the file and line. Finiteness and lengths are for the caller to judge.
    """
    rows = list(csv.reader(io.StringIO(Path(path).read_text())))
    if not rows:
        raise DataError(f"{path}: empty file")
    header = [h.strip().lower() for h in rows[0]]
    missing = [c for c in required if c not in header]
    if missing:
        raise DataError(f"{path}: missing column {', '.join(repr(c) for c in missing)} "
                        f"(header is {','.join(header)[:80]})")
    wanted = [k for k, h in enumerate(header) if keep_extra or h in required]
    data = []
    for n, row in enumerate(rows[1:], start=2):
        if not any(c.strip() for c in row):
            continue
        try:
            data.append([float(row[k]) for k in wanted])
        except (ValueError, IndexError):
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
