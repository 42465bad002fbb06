"""The fleet's results: OUT holds ``results/KEY.json``, one per log, written atomically as soon as
it is done, KEY the log's content hash with the axis and the options, so a rerun skips finished
work."""
from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import Dict, Sequence

from .._io import write_atomic
from ..errors import DataError
from .manifest import Entry

#: The version of a stored result's fields: a result of another version is computed again.
RESULT_VERSION = 3


def result_key(entry: Entry, options: Sequence[str]) -> str:
    """The key of a log's result: the SHA-256 of its content, with the axis and the training
    options (a log that changes, or is trained otherwise, is a new result).

    Parameters
    ----------
    entry : Entry
        The manifest row (its log is read).
    options : sequence of str
        ``train``'s options.

    Returns
    -------
    str

    Examples
    --------
    >>> from fricgen.fleet import Entry, result_key
    >>> _ = (tmp / "a.csv").write_text("t,x,i\\n")
    >>> one = result_key(Entry("x1", str(tmp / "a.csv"), "1"), [])
    >>> one == result_key(Entry("x1", str(tmp / "a.csv"), "2"), []), one == result_key(
    ...     Entry("x1", str(tmp / "a.csv"), "1"), ["--smooth", "5"])
    (True, False)
    """
    digest = hashlib.sha256()
    with open(entry.log, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    settings = json.dumps([RESULT_VERSION, entry.axis, entry.mass, entry.force_constant,
                           list(options)])
    return digest.hexdigest()[:32] + "-" + hashlib.sha256(settings.encode()).hexdigest()[:8]


def results_dir(out) -> Path:
    return Path(out) / "results"


def check_out(out) -> Path:
    """OUT and OUT/results created and writable (a file written and removed there), else
    ``DataError`` in one line."""
    folder = results_dir(out)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / f".probe-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        raise DataError(f"{out}: cannot write results there ({exc.strerror or exc})") from None
    return folder


def load_results(out) -> Dict[str, dict]:
    """Every stored result of OUT by key (files of another version, or unreadable, skipped)."""
    found = {}
    for path in sorted(results_dir(out).glob("*.json")):
        try:
            record = json.loads(path.read_text())
        except (OSError, ValueError):
            continue
        if isinstance(record, dict) and record.get("version") == RESULT_VERSION:
            found[path.stem] = record
    return found


def store(out, record: dict) -> None:
    """Write one result atomically (a temporary file renamed over OUT/results/KEY.json)."""
    write_atomic(results_dir(out) / f"{record['key']}.json", json.dumps(record, allow_nan=True))
