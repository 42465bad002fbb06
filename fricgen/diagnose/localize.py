"""Where the residual lives: the share of it each signal's binned means explain."""
from __future__ import annotations

import math
from typing import List

import numpy as np

from .residual import ResidualProblem


def _binned_share(r: np.ndarray, labels: np.ndarray, n_eff: float) -> float:
    """Fraction of sum(r^2) the group means explain, adjusted for the number of groups."""
    groups = np.unique(labels)
    total = float(np.sum(r ** 2))
    between = sum(float(np.sum(labels == g)) * float(np.mean(r[labels == g])) ** 2 for g in groups)
    share = between / total if total > 0 else 0.0
    k = groups.size
    return max(0.0, 1.0 - (1.0 - share) * (n_eff - 1.0) / max(n_eff - k, 1.0))


def _quantile_labels(values: np.ndarray, bins: int = 10) -> np.ndarray:
    edges = np.quantile(values, np.linspace(0, 1, bins + 1)[1:-1])
    return np.searchsorted(edges, values)


def localize(problem: ResidualProblem) -> List[dict]:
    """Where the residual lives: for each axis, the share of sum(r^2) its binned means explain
    (adjusted for the number of bins), with a one-line detail. Axes marked "friction level"
    bin r sgn(v), the residual as a change of the friction magnitude."""
    rows = np.arange(problem.rows.size)
    idx = problem.rows
    r = problem.target
    n_eff = problem.independent(problem.rows.size)
    v = problem.v_smooth[idx]
    x = problem.x_smooth[idx]
    a = problem.at_rows(problem.signals.a, rows)
    t = problem.signals.t[idx]
    level = r * np.sign(v)
    out = []

    def add(axis, values, labels, detail):
        out.append({"axis": axis, "share": _binned_share(values, labels, n_eff), "detail": detail,
                    "groups": int(np.unique(labels).size)})

    def extreme(values, labels, coord, name, unit, moving=False):
        """The group whose mean is largest in size; ``moving``: odd labels are v > 0."""
        groups = np.unique(labels)
        means = np.array([values[labels == g].mean() for g in groups])
        k = int(np.argmax(np.abs(means)))
        inside = coord[labels == groups[k]]
        direction = f" moving {'+' if groups[k] % 2 else '-'}" if moving else ""
        return (f"largest mean {means[k]:+.3g} N at {name} in [{inside.min():.3g}, "
                f"{inside.max():.3g}] {unit}{direction}")

    pos, neg = r[v > 0], r[v < 0]
    add("constant", r, np.zeros(r.size, dtype=int), f"mean {r.mean():+.3g} N everywhere")
    add("direction of motion", r, (v > 0).astype(int),
        f"mean {pos.mean() if pos.size else 0:+.3g} N for v > 0, {neg.mean() if neg.size else 0:+.3g} N for v < 0")
    for axis, values, coord, name, unit in (("velocity", r, v, "v", "m/s"),
                                             ("speed, friction level", level, np.abs(v), "|v|", "m/s"),
                                             ("position", r, x, "x", "m")):
        lab = _quantile_labels(coord)
        add(axis, values, lab, extreme(values, lab, coord, name, unit))
    lab = 2 * _quantile_labels(x) + (v > 0)                     # a bump acting against motion
    add("position and direction", r, lab, extreme(r, lab, x, "x", "m", moving=True))
    ks, bank = problem.ripple_bank()
    G = np.einsum("kni,knj->kij", bank, bank)
    b = np.einsum("kni,n->ki", bank, r)
    coef = np.linalg.solve(G + 1e-12 * np.eye(2), b[..., None])[..., 0]
    gain = np.einsum("ki,ki->k", coef, b)
    j = int(np.argmax(gain))
    share = float(gain[j] / np.sum(r ** 2))
    out.append({"axis": "position, periodic",
                "share": max(0.0, 1.0 - (1.0 - share) * (n_eff - 1.0) / max(n_eff - 3.0, 1.0)),
                "detail": f"period {2 * np.pi / ks[j] * 1e3:.3g} mm, amplitude "
                          f"{math.hypot(*coef[j]):.3g} N", "groups": 3})
    add("acceleration", r, _quantile_labels(a), f"slope {np.dot(a, r) / np.dot(a, a):+.3g} N per m/s^2")
    current = problem.at_rows(problem.signals.i, rows)
    lab = _quantile_labels(current)
    add("current", r, lab, extreme(r, lab, current, "i", "A"))
    growth = a * np.sign(v)            # d|v|/dt: > 0 while speeding up
    add("speeding up or slowing down, friction level", level, _quantile_labels(growth),
        f"mean {level[growth > 0].mean():+.3g} N while speeding up, "
        f"{level[growth < 0].mean():+.3g} N while slowing down")
    lab = np.minimum((10 * (t - t[0]) / (np.ptp(t) + 1e-12)).astype(int), 9)
    add("time", r, lab, f"mean {r[lab == 0].mean():+.3g} N in the first tenth of the log, "
                        f"{r[lab == lab.max()].mean():+.3g} N in the last")
    add("time, friction level", level, lab,
        f"friction {level[lab == 0].mean():+.3g} N off in the first tenth of the log, "
        f"{level[lab == lab.max()].mean():+.3g} N in the last")
    return sorted(out, key=lambda d: -d["share"])


#: Axes within this share of the best one explain the residual as well: of those, the simplest
#: (fewest groups) is named, so a constant load reads "constant", not a ranking of slopes.
SIMPLEST_WITHIN = 0.02


def where(localization: List[dict]) -> str:
    """The simplest axis among those that explain most of the residual, as one phrase."""
    best = localization[0]["share"]
    if best < 0.05:
        return "nowhere beyond noise (no axis explains 5 % of the residual)"
    top = min((a for a in localization if a["share"] >= best - SIMPLEST_WITHIN),
              key=lambda a: (a["groups"], -a["share"]))
    return f"{top['axis']}: {top['detail']} ({top['share']:.0%} of the residual)"
