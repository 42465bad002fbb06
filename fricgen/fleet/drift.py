"""The drift table: a parameter p of an axis has drifted when its change from the axis's reference
result (the previous log by timestamp, or the first) exceeds both ``sigmas`` combined standard
errors and a practical threshold, ``min_change`` of the reference value:

    |p_new - p_ref| > sigmas * sqrt(se_new^2 + se_ref^2)   and   |p_new - p_ref| > min_change |p_ref|

Only the Coulomb levels, the static peaks and B (``MONITORED``) are tested; v_s is reported.
"""
from __future__ import annotations

import math
from typing import List, Sequence

from .identification import DIRECTIONS, PARAMETERS

#: Default multiple of the combined standard errors a change must exceed.
SIGMAS = 3.0
#: Default practical threshold: the fraction of the reference value a change must exceed. The
#: standard errors of the monitoring law hold the noise of unchanged axes (``law``), so this
#: only keeps the changes too small to act on from the list when a long log measures them.
MIN_CHANGE = 0.02
#: The parameters the drift test watches, per direction (``pos``, ``neg``).
MONITORED = ("coulomb", "static", "viscous")
#: The reference a new result is compared with.
BASELINES = ("previous", "first")


def _change(new: dict, ref: dict, name: str, sigmas: float, min_change: float):
    """(change, change / combined se, flagged) of parameter ``name``."""
    a, b = new.get(name, math.nan), ref.get(name, math.nan)
    se = math.hypot(new.get(name + "_se", math.nan), ref.get(name + "_se", math.nan))
    change = a - b
    if not (math.isfinite(change) and math.isfinite(se)):
        return change, math.nan, False
    z = abs(change) / se if se > 0 else math.inf
    return change, z, bool(z > sigmas and abs(change) > min_change * abs(b))


def drift_table(records: Sequence[dict], sigmas: float = SIGMAS, min_change: float = MIN_CHANGE,
                baseline: str = "previous") -> List[dict]:
    """One row per result, in order of axis and timestamp: the result, its reference (the
    axis's previous, or first, good result), the change of each parameter and its size in
    combined standard errors, and ``flagged`` with the parameters that drifted (see the module).

    Parameters
    ----------
    records : sequence of dict
        The results (``identify``).
    sigmas : float
        The multiple of the combined standard errors a change must exceed.
    min_change : float
        The fraction of the reference value a change must exceed.
    baseline : {"previous", "first"}
        The reference of each result.

    Returns
    -------
    list of dict

    Examples
    --------
    >>> from fricgen.fleet import drift_table
    >>> base = {"axis": "x1", "status": "ok", "key": "a", "timestamp": "1"}
    >>> old = {**base, "coulomb_pos": 10.0, "coulomb_pos_se": 0.1}
    >>> new = {**base, "key": "b", "timestamp": "2", "coulomb_pos": 12.0, "coulomb_pos_se": 0.1}
    >>> rows = drift_table([old, new])
    >>> rows[1]["flagged"], rows[1]["drifted"], round(rows[1]["coulomb_pos_z"], 1)
    (True, 'coulomb_pos', 14.1)
    """
    if baseline not in BASELINES:
        raise ValueError(f"baseline must be one of {list(BASELINES)}, got {baseline!r}")
    rows, good = [], {}
    for r in sorted(records, key=lambda r: (r["axis"], r["timestamp"], r["key"])):
        row = {k: v for k, v in r.items() if k not in ("version", "stored")}
        earlier = good.get(r["axis"], [])
        ref = (earlier[-1] if baseline == "previous" else earlier[0]) if earlier else None
        row["reference"] = ref["timestamp"] if ref else ""
        drifted = []
        for p in PARAMETERS:
            for d in DIRECTIONS:
                name = f"{p}_{d}"
                if ref is None or r["status"] != "ok":
                    row[f"{name}_change"] = row[f"{name}_z"] = math.nan
                    continue
                change, z, flag = _change(r, ref, name, sigmas, min_change)
                row[f"{name}_change"], row[f"{name}_z"] = change, z
                if flag and p in MONITORED:
                    drifted.append(name)
        row["flagged"] = bool(drifted)
        row["drifted"] = " ".join(drifted)
        if r["status"] == "ok":
            good.setdefault(r["axis"], []).append(r)
        rows.append(row)
    return rows


def latest(rows: Sequence[dict]) -> List[dict]:
    """Each axis's newest row (``drift_table`` orders them)."""
    newest = {}
    for row in rows:
        newest[row["axis"]] = row
    return list(newest.values())
