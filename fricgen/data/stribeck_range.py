"""The Stribeck range of a sweep: vs_max, hence v_sat = SAT_FACTOR vs_max and the rows that
give B (section 2), chosen by K-fold cross-validation of the force in newtons.

Each candidate vs_max of a log-spaced grid over the data's speeds runs the steps of ``prepare``
on the training folds, with a cheap stand-in for the grey-box fit: B and the anchor F0 from the
rows beyond v_sat (``identify_viscous``), then [F1] with a fixed dictionary of Stribeck
velocities of every shape up to vs_max (the grey-box's bound) and non-negative amplitudes
(a linear fit), saturated at v_sat as [F3] is. A v_sat inside the Stribeck drop bends the
line that gives B, a vs_max below a Stribeck velocity cannot follow the drop, and a v_sat far
beyond it leaves few rows for B: each shows up as held-out error. A v_sat beyond which the
force falls (B < 0 in a training fold) is no linear region and is not scored: viscous friction
dissipates, and a falling line would push the axis wherever the model extrapolates it. Of the
candidates within one standard error (of the paired row differences) of the best, the smallest
vs_max is chosen.

One more candidate has no linear high-speed region: B is fitted with the rest ([F1] with the
dictionary up to a third of the fastest speed, plus B v) and v_sat is the fastest speed. It is
chosen when it beats the best vs_max by more than JOINT_MARGIN standard errors, or when no
vs_max leaves enough rows beyond v_sat; it never refuses data that span speeds.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np
from scipy.optimize import nnls

from ..errors import DataError
from ..friction import SHAPES
from ..units import LINEAR
from .sweep import MIN_ROWS, Sweep
from .viscous import MIN_HIGH_SPEED_ROWS, SAT_FACTOR, bin_equal_counts, identify_viscous

#: Candidate values of vs_max in the grid (log-spaced).
CANDIDATES = 10
#: Folds of the cross-validation (``speed_folds``, by default).
FOLDS = 5
#: Stribeck velocities of each shape in the proxy's dictionary (log-spaced up to vs_max).
DICTIONARY = 8
#: The joint candidate (no linear region) must beat the best vs_max by more than this many
#: standard errors: its B trades off against broad sources, so a tail of the Stribeck drop
#: that bends the high-speed line must cost the linear candidates clearly (set on sweeps of
#: seeds 200-219: 2 and 3 standard errors chose alike).
JOINT_MARGIN = 2.0
#: A dictionary column no larger than this has underflowed and is left out of the fit.
NEGLIGIBLE = 1e-290
#: Rows beyond which each fold is averaged into bins before the proxy's fits (``binned_by_fold``):
#: a log of under a minute at 1 kHz is scored row by row, a long one costs no more than that.
MAX_PROXY_ROWS = 50_000
#: The smallest candidate puts this fraction of the rows within [0, v_sat]; the largest
#: leaves this fraction (and at least 2 MIN_HIGH_SPEED_ROWS) beyond it.
EDGE_FRACTION = 0.1


class FallingForce(DataError):
    """A candidate v_sat beyond which the force falls (B < 0): no linear region there."""


@dataclass(frozen=True)
class StribeckRange:
    """The chosen vs_max and how it was chosen (``choose_vs_max``).

    Parameters
    ----------
    vs_max : float
        The chosen v_smax (m/s).
    curve : tuple of (float, float)
        (vs_max in m/s, held-out RMS error in N) of each candidate scored.
    folds : int
        The number of cross-validation folds.
    joint_rmse : float
        Held-out RMS error (N) of fitting B with the Stribeck sources instead.
    linear_region : bool
        False when no candidate left enough rows beyond v_sat; then ``viscous`` and ``f_sat`` hold
        the B fitted with the rest (N s/m) and the force at v_sat (N).
    viscous, f_sat : float, optional
        See ``linear_region``.
    falling : bool
        Whether the force falls beyond every candidate v_sat that left rows for B (the data end
        within the Stribeck drop).

    Examples
    --------
    >>> from fricgen.data import StribeckRange
    >>> StribeckRange(0.02, ((0.02, 0.3),), folds=5, joint_rmse=0.4).linear_region
    True
    """

    vs_max: float
    curve: Tuple[Tuple[float, float], ...]
    folds: int
    joint_rmse: float
    linear_region: bool = True
    viscous: Optional[float] = None
    f_sat: Optional[float] = None
    falling: bool = False

    def describe(self, units=LINEAR) -> str:
        """One line for the fit report, in ``units``."""
        force, speed = units.force, units.speed
        points = ", ".join(f"{v:.3g} ({e:.3g} {force})" for i, (v, e) in enumerate(self.curve)
                           if i % 2 == 0 or v == self.vs_max)      # every other, and the choice
        joint = f"B fitted with the Stribeck sources ({self.joint_rmse:.3g} {force})"
        if self.linear_region:
            return f"{self.vs_max:.3g} {speed} chosen by {self.folds}-fold CV over {points}; {joint}"
        if self.falling:
            return (f"{self.vs_max:.3g} {speed}: the force still falls at the fastest speeds, beyond "
                    f"every candidate v_sat: no linear region; {joint}; v_sat is the fastest speed")
        if not points:
            return (f"{self.vs_max:.3g} {speed}: too few rows to fit B to the fastest ones alone; "
                    f"{joint}; v_sat is the fastest speed")
        return (f"{self.vs_max:.3g} {speed}: no linear high-speed region; {joint} beats every vs_max "
                f"by {self.folds}-fold CV: {points}; v_sat is the fastest speed")


def speed_folds(v: np.ndarray, folds: int = FOLDS) -> np.ndarray:
    """The rows sorted by speed dealt to ``folds`` folds in turn (every fold spans the range):
    ``fricgen.fit.base.interleaved_folds`` without a Generator, which the fit layer passes."""
    fold = np.empty(v.size, dtype=int)
    fold[np.argsort(v, kind="stable")] = np.arange(v.size) % folds
    return fold


def candidate_grid(v: np.ndarray, n: int = CANDIDATES) -> np.ndarray:
    """Log-spaced vs_max values from the speed below which EDGE_FRACTION of the rows lie (at
    least MIN_ROWS) to the speed beyond which as many lie (at least 2 MIN_HIGH_SPEED_ROWS), both
    / SAT_FACTOR; empty when that leaves no range."""
    speeds = np.sort(v[v > 0])
    fast = max(2 * MIN_HIGH_SPEED_ROWS, int(EDGE_FRACTION * speeds.size))
    slow = max(MIN_ROWS, int(EDGE_FRACTION * speeds.size))     # prepare needs MIN_ROWS below
    if speeds.size <= fast + slow:
        return np.empty(0)
    lo = speeds[slow] / SAT_FACTOR
    hi = speeds[-fast - 1] / SAT_FACTOR
    if not (lo > 0 and hi > lo):
        return np.empty(0)
    return np.geomspace(lo, hi, n)


def _dictionary(v: np.ndarray, stribeck: np.ndarray) -> np.ndarray:
    """[1, g(v, v_k) for every shape g and every v_k]: [F1] with fixed Stribeck velocities."""
    return np.column_stack([np.ones_like(v)] + [g(v, s) for g in SHAPES.values() for s in stribeck])


def _nonnegative_fit(A: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Least squares with every coefficient >= 0 (the columns scaled to a unit maximum). A
    column that has underflowed (a Stribeck velocity far below every speed: at most NEGLIGIBLE)
    gets the coefficient 0: scaling it up would overflow."""
    scale = np.abs(A).max(axis=0)
    dead = scale <= NEGLIGIBLE
    scale[dead] = 1.0
    coef = np.zeros(A.shape[1])
    coef[~dead] = nnls(A[:, ~dead] / scale[~dead], f)[0] / scale[~dead]
    return coef


def _proxy(v: np.ndarray, f: np.ndarray, vs_max: Optional[float]):
    """The cheap stand-in for ``prepare`` plus a grey-box fit, trained on (v, f): B and F0 from
    the rows beyond v_sat, then [F1] with DICTIONARY Stribeck velocities of every shape up to
    vs_max (the grey-box's bound) and non-negative amplitudes, fitted to the rows within [0,
    v_sat] and the anchor (v_sat, F0 + B v_sat). ``vs_max`` None: no linear region; v_sat is
    the fastest speed and B is fitted with the rest. Returns the force as a function of speed
    ([F3]: saturated at v_sat) and B."""
    if vs_max is None:
        v_sat = float(v.max())
        stribeck = np.geomspace(v_sat / SAT_FACTOR / 50, v_sat / SAT_FACTOR, DICTIONARY)
        coef = _nonnegative_fit(np.column_stack([v, _dictionary(v, stribeck)]), f)
        B, coef = float(coef[0]), coef[1:]
    else:
        v_sat = SAT_FACTOR * vs_max
        high = v > v_sat
        B, f0, _ = identify_viscous(Sweep(v[high], f[high]))
        if B < 0:
            raise FallingForce("the force falls beyond v_sat: no linear region there")
        if (~high).sum() < 2:
            raise DataError("too few rows within [0, v_sat]")
        stribeck = np.geomspace(vs_max / 50, vs_max, DICTIONARY)
        x = np.append(v[~high], v_sat)
        coef = _nonnegative_fit(_dictionary(x, stribeck), np.append(f[~high] - B * v[~high], f0))
    return (lambda u: _dictionary(np.minimum(u, v_sat), stribeck) @ coef + B * u), B


def _held_out(v, f, folds, vs_max) -> np.ndarray:
    """The proxy's held-out error (N) at every row, each fold predicted by the others."""
    held_out = np.empty_like(f)
    for k in np.unique(folds):
        out = folds == k
        held_out[out] = _proxy(v[~out], f[~out], vs_max)[0](v[out]) - f[out]
    return held_out


def _within_one_se(squared: np.ndarray, reference: int, k: float = 1.0) -> np.ndarray:
    """Whether each candidate's mean held-out squared error (candidates x rows) exceeds the
    ``reference`` one's by at most ``k`` standard errors of the paired row differences, and by
    at most ``k`` standard errors of the reference's own mean."""
    with np.errstate(over="ignore", invalid="ignore"):      # a candidate that blows up: inf
        diff = squared - squared[reference]
        se = k * diff.std(axis=1, ddof=1) / np.sqrt(diff.shape[1])
        own = k * squared[reference].std(ddof=1) / np.sqrt(squared.shape[1])
    # and within the reference's own standard error: a candidate that blows up on one fold has
    # so wide a paired spread that it would pass the first test alone
    return (diff.mean(axis=1) <= se) & (diff.mean(axis=1) <= own)


def binned_by_fold(v, f, folds, rows: int = MAX_PROXY_ROWS):
    """(v, f, folds) with each fold's rows averaged into at most ``rows`` / n_folds bins of
    consecutive speeds (``bin_equal_counts``): the proxy's cost stays flat on long logs, and no
    bin mixes folds."""
    if v.size <= rows:
        return v, f, folds
    labels = np.unique(folds)
    parts = [bin_equal_counts(Sweep(v[folds == k], f[folds == k]), max(rows // labels.size, MIN_ROWS))
             for k in labels]
    return (np.concatenate([p.v for p in parts]), np.concatenate([p.f for p in parts]),
            np.concatenate([np.full(len(p), k) for p, k in zip(parts, labels)]))


def choose_vs_max(folded: Sweep, folds: Optional[np.ndarray] = None) -> StribeckRange:
    """vs_max of a folded sweep by cross-validation: each candidate v_sat = 3 vs_max splits the rows
    into a Stribeck part and a linear high-speed part ([F3] saturates beyond v_sat); the
    smallest candidate within one standard error of the best held-out error wins.

    Parameters
    ----------
    folded : Sweep
        The sweep folded onto v >= 0 (``Sweep.folded``).
    folds : array_like of int, optional
        The fold of each row (default: interleaved by speed).

    Returns
    -------
    StribeckRange

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.data import choose_vs_max
    >>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
    >>> chosen = choose_vs_max(sweep.folded())
    >>> chosen.linear_region, round(chosen.vs_max, 2)          # Table 1: v_smax = 0.02
    (True, 0.02)
    """
    folds = speed_folds(folded.v) if folds is None else np.asarray(folds)
    v, f, folds = binned_by_fold(folded.v, folded.f, folds)     # a long log: bins per fold
    n_folds = len(np.unique(folds))
    scored, squared, falling = [], [], 0
    for vs_max in candidate_grid(v):
        try:
            error = _held_out(v, f, folds, vs_max)
        except FallingForce:
            falling += 1
            continue
        except DataError:
            continue
        with np.errstate(over="ignore"):
            square = error ** 2
        if not np.all(np.isfinite(square)):      # a fold the proxy cannot fit: no candidate
            continue
        scored.append((float(vs_max), float(np.sqrt(np.mean(square)))))
        squared.append(square)
    joint = _held_out(v, f, folds, None) ** 2
    joint_rmse = float(np.sqrt(joint.mean()))
    if scored:
        squared = np.array(squared)
        best = int(np.argmin(squared.mean(axis=1)))
        chosen = int(np.flatnonzero(_within_one_se(squared, best)).min())
        if not np.all(np.isfinite(joint)) or \
                _within_one_se(np.array([squared[best], joint]), 1, JOINT_MARGIN)[0]:
            return StribeckRange(scored[chosen][0], tuple(scored), n_folds, joint_rmse)
    curve, B = _proxy(v, f, None)
    top = float(v.max())
    return StribeckRange(top / SAT_FACTOR, tuple(scored), n_folds, joint_rmse, False, B,
                         float(curve(np.array([top]))[0]), falling > 0 and not scored)
