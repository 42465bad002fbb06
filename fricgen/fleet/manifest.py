"""The fleet's manifest: one CSV row per log, naming its axis, the log and its timestamp, and
optionally the axis's mass and force constant."""
from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path
from typing import List, Optional

from ..errors import DataError

#: The manifest's columns: required, then optional.
MANIFEST_REQUIRED = ("axis", "log", "timestamp")
MANIFEST_OPTIONAL = ("mass", "force_constant")


@dataclass(frozen=True)
class Entry:
    """One row of the manifest.

    Parameters
    ----------
    axis : str
        The axis id.
    log : str
        The log's path (resolved against the manifest's folder).
    timestamp : str
        When the log was taken, as text ordered as written (ISO 8601 sorts).
    mass, force_constant : float, optional
        The axis's mass (kg) and force constant (N/A), when known.

    Examples
    --------
    >>> from fricgen.fleet import Entry
    >>> Entry("x1", "logs/x1.csv", "2026-01-01T00:00").mass is None
    True
    """

    axis: str
    log: str
    timestamp: str
    mass: Optional[float] = None
    force_constant: Optional[float] = None


def read_manifest(path) -> List[Entry]:
    """The manifest CSV's rows (header: axis, log, timestamp[, mass][, force_constant]); log
    paths relative to the manifest's folder. ``DataError`` naming the row otherwise.

    Parameters
    ----------
    path : str or pathlib.Path
        The manifest CSV.

    Returns
    -------
    list of Entry

    Examples
    --------
    >>> from fricgen.fleet import read_manifest
    >>> _ = (tmp / "fleet.csv").write_text("axis,log,timestamp,mass\\nx1,x1.csv,2026-01-01,4.5\\n")
    >>> [(e.axis, e.mass) for e in read_manifest(tmp / "fleet.csv")]
    [('x1', 4.5)]
    """
    path = Path(path)
    text = path.read_text(encoding="utf-8-sig")
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        raise DataError(f"{path}: empty manifest, need a header {','.join(MANIFEST_REQUIRED)}")
    header = [h.strip().lower() for h in rows[0]]
    missing = [c for c in MANIFEST_REQUIRED if c not in header]
    if missing:
        raise DataError(f"{path}: manifest misses column {missing[0]!r} (header is "
                        f"{','.join(rows[0])[:80]})")
    entries = []
    for n, row in enumerate(rows[1:], start=2):
        if not any(cell.strip() for cell in row):
            continue
        if len(row) != len(header):
            raise DataError(f"{path}: line {n} has {len(row)} cells, the header {len(header)}")
        cells = {h: c.strip() for h, c in zip(header, row)}
        for c in MANIFEST_REQUIRED:
            if not cells[c]:
                raise DataError(f"{path}: line {n}: empty {c}")
        numbers = {}
        for c in MANIFEST_OPTIONAL:
            text_value = cells.get(c, "")
            if text_value:
                try:
                    value = float(text_value)
                except ValueError:
                    value = math.nan
                if not (math.isfinite(value) and value > 0):
                    raise DataError(f"{path}: line {n}: {c} must be a number > 0, got {text_value[:40]!r}")
                numbers[c] = value
        entries.append(Entry(cells["axis"], str(path.parent / cells["log"]), cells["timestamp"],
                             **numbers))
    if not entries:
        raise DataError(f"{path}: the manifest lists no log")
    return entries
