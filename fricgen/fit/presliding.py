"""The LuGre bristles of a log (``effects.presliding``): stiffness sigma0 and damping sigma1 on
the static curve a model already holds, or nothing where the log does not determine them.

Which log identifies them: one with pre-sliding, motion smaller than the pre-sliding distance
g(0) / sigma0 after a reversal (small position reversals around a point, or a dwell under a
slow force ramp), logged with an encoder that resolves that distance. A log of large moves
only bounds the distance from above; its reversals pass too fast through pre-sliding to tell a
stiffness.

The force of a log reads, with the mass m and the constant force c of the static fit's inverse
dynamics [C1],

    f - m a - B v - sigma0 z(sigma0) = c + sigma1 dz/dt,

z the exact update driven by the logged position's increments (what the encoder resolves
integrates without drift). Every side is smoothed by one Savitzky-Golay window (the static
fit's); c and sigma1 are linear (least squares), sigma0 is profiled over a grid of pre-sliding
distances d = g(0) / sigma0 from a quarter of an encoder count to a tenth of the travel, refined
by a parabola in log d. Per contiguous block of the rows (10) the Gram matrices give, without
another pass: the blocked jackknife standard errors of log sigma0 and of sigma1, and the blocked
cross-validation of the bristles against the stiffest grid point (the static curve): the bristles
are kept when their held-out error is lower by more than one standard error (Breiman's rule,
as every choice of fricgen's fits). sigma1 is kept when it is positive and above twice its
standard error, else 0 and the report says so.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..data.inverse_dynamics import position_quantum, smooth
from ..effects.fitting import FIT_FOLDS, block_grams, one_standard_error_choice
from ..effects.presliding import Bristles, STATIC_SIDE, bristle_states
from ..errors import DataError

#: Pre-sliding distances tried per decade, and the grid's ends: a quarter of the position's
#: step (or of its noise, for a continuous position) to a tenth of the travel.
POINTS_PER_DECADE = 12
LEAST_DISTANCE_STEPS = 0.25
LARGEST_DISTANCE_TRAVEL = 0.1
#: sigma1 is kept when above this many standard errors.
DAMPING_SIGMAS = 2.0


@dataclass(frozen=True)
class PreslidingFit:
    """The bristles a log determines (``bristles`` None where it does not: ``reason`` says
    why), with the standard errors, the pre-sliding rows and the residuals."""

    bristles: Optional[Bristles]
    stiffness: float            # the profile's best sigma0, kept or not
    stiffness_se: float         # its standard error (blocked jackknife, through log sigma0)
    damping: float              # sigma1 at that sigma0 (before the DAMPING_SIGMAS test)
    damping_se: float
    presliding_rows: int        # rows after a reversal within the pre-sliding distance
    rms_static: float           # residual RMS with the static curve (the stiffest grid point)
    rms_dynamic: float          # ... with the bristles
    reason: str                 # '' when kept, else why not

    @property
    def damping_determined(self) -> bool:
        return self.bristles is not None and self.bristles.damping > 0


def _presliding_rows(x: np.ndarray, v: np.ndarray, distance: float) -> int:
    """Samples after a reversal (a sign change of the moving velocity) whose position is within
    ``distance`` of the position at the reversal."""
    moving = np.flatnonzero(v != 0)
    if moving.size < 2:
        return 0
    turn = np.zeros(v.size, bool)
    turn[moving[1:][np.sign(v[moving[1:]]) != np.sign(v[moving[:-1]])]] = True
    anchor = np.maximum.accumulate(np.where(turn, np.arange(v.size), 0))
    return int(np.sum((anchor > 0) & (np.abs(x[1:] - x[anchor]) < distance)))


def identify_presliding(t, x, force, model, mass: float, offset_free: bool = True,
                        window: int = 31, folds: int = FIT_FOLDS) -> PreslidingFit:
    """sigma0 and sigma1 of ``model``'s static curve from a log (see the module).

    Parameters
    ----------
    t, x, force : array_like
        Time (s, uniform), position (m or rad) and drive force (N or Nm) of the log.
    model : FrictionModel
        The static curve (``stribeck`` gives g, each direction's B the viscous force).
    mass : float
        m of [C1] (the static fit's, or given).
    offset_free : bool
        Fit the constant force c (else 0).
    window : int
        The Savitzky-Golay window, samples (odd).
    """
    t, x, force = (np.asarray(a, dtype=float) for a in (t, x, force))
    if not (t.size == x.size == force.size) or t.size < 4 * window:
        raise DataError(f"pre-sliding needs t, x and force of one length, at least {4 * window} rows")
    dt = float(np.median(np.diff(t)))
    v = np.diff(x) / dt                                       # held over each sample
    level = np.maximum(model.stribeck(np.where(v == 0, 0.0, v)), 0.0)
    static = 0.5 * float(model.stribeck(0.0) + model.stribeck(-STATIC_SIDE))
    if not static > 0:
        raise DataError("the static curve has no friction at rest: no bristles to identify")
    level = np.maximum(level, 1e-6 * static)
    viscous = model.force(v) - np.sign(v) * model.stribeck(v)
    quantum = position_quantum(x) or float(np.std(np.diff(x, 2)) / np.sqrt(6.0))
    travel = float(np.ptp(x))
    lo, hi = LEAST_DISTANCE_STEPS * max(quantum, 1e-12), LARGEST_DISTANCE_TRAVEL * travel
    if not hi > 4 * lo:
        raise DataError("the log moves too little to tell a pre-sliding distance")
    distances = np.logspace(np.log10(lo), np.log10(hi),
                            int(np.ceil(POINTS_PER_DECADE * np.log10(hi / lo))) + 1)
    base = smooth(force, window)[1:] - mass * smooth(x, window, deriv=2, delta=dt)[1:] \
        - smooth(np.concatenate([[0.0], viscous]), window)[1:]
    grams = []
    for d in distances:
        s0 = static / d
        z = bristle_states(v, level, s0, dt)
        dz = np.diff(np.concatenate([[0.0], z])) / dt
        target = base - smooth(np.concatenate([[0.0], s0 * z]), window)[1:]
        columns = [smooth(np.concatenate([[0.0], dz]), window)[1:]]
        if offset_free:
            columns.append(np.ones(v.size))
        design = np.column_stack(columns)[window:-window]
        grams.append(block_grams(design, target[window:-window], folds))
    rss, coef, held_out = _profile(grams, folds)
    best, best_by_fold = _vertex(np.log(distances), rss[0]), \
        [_vertex(np.log(distances), rss[1 + j]) for j in range(folds)]
    k = int(np.argmin(rss[0]))
    jack = np.array(best_by_fold)
    log_se = float(np.sqrt((folds - 1) / folds * np.sum((jack - jack.mean()) ** 2)))
    damping = float(coef[0][k][0])
    damping_jack = np.array([coef[1 + j][int(np.argmin(rss[1 + j]))][0] for j in range(folds)])
    damping_se = float(np.sqrt((folds - 1) / folds * np.sum((damping_jack - damping_jack.mean()) ** 2)))
    stiffness = static / float(np.exp(best))
    n = sum(g[3] for g in grams[0])
    rms_static, rms_dynamic = float(np.sqrt(rss[0][0] / n)), float(np.sqrt(rss[0][k] / n))
    rows = _presliding_rows(x, v, static / stiffness)
    errors = np.array([held_out[0], [held_out_at(grams, j, int(np.argmin(rss[1 + j]))) for j in range(folds)]])
    reason = ""
    if k == 0 or k == distances.size - 1:
        reason = ("the best pre-sliding distance is at the end of the range tried "
                  f"({np.exp(best):.3g}): the log does not resolve pre-sliding")
    elif one_standard_error_choice(errors) == 1:
        reason = ("the bristles do not lower the held-out error beyond its spread: the log holds "
                  "no pre-sliding the encoder resolves (log small reversals or a slow force ramp at rest)")
    bristles = None
    if not reason:
        keep = damping > DAMPING_SIGMAS * damping_se
        bristles = Bristles(stiffness=stiffness, damping=damping if keep else 0.0)
    return PreslidingFit(bristles=bristles, stiffness=stiffness, stiffness_se=stiffness * log_se,
                         damping=damping, damping_se=damping_se, presliding_rows=rows,
                         rms_static=rms_static, rms_dynamic=rms_dynamic, reason=reason)


def _solve(g, b):
    return np.linalg.lstsq(g, b, rcond=None)[0]


def _profile(grams, folds):
    """Per grid point: the RSS and coefficients of all rows (index 0) and without each block
    (1..folds); the held-out mean squares of the stiffest point per block."""
    rss = np.empty((folds + 1, len(grams)))
    coef = [[None] * len(grams) for _ in range(folds + 1)]
    for i, blocks in enumerate(grams):
        g_all, b_all, yy_all = (sum(g[k] for g in blocks) for k in range(3))
        for j in range(folds + 1):
            g, b, yy = (g_all, b_all, yy_all) if j == 0 else \
                (g_all - blocks[j - 1][0], b_all - blocks[j - 1][1], yy_all - blocks[j - 1][2])
            c = _solve(g, b)
            coef[j][i] = c
            rss[j, i] = yy - 2 * c @ b + c @ g @ c
    held_out = [[held_out_at(grams, j, 0) for j in range(folds)]]
    return rss, coef, held_out


def held_out_at(grams, j: int, i: int) -> float:
    """The mean square on block j of the fit without it, at grid point i."""
    blocks = grams[i]
    g_all, b_all = (sum(g[k] for g in blocks) for k in range(2))
    g, b, yy, n = blocks[j]
    c = _solve(g_all - g, b_all - b)
    return float((yy - 2 * c @ b + c @ g @ c) / n)


def _vertex(log_d: np.ndarray, rss: np.ndarray) -> float:
    """The minimum of ``rss`` over the grid ``log_d``, refined by the parabola through the best
    point and its neighbours (the best point itself at an end)."""
    k = int(np.argmin(rss))
    if k == 0 or k == rss.size - 1:
        return float(log_d[k])
    y0, y1, y2 = rss[k - 1:k + 2]
    curvature = y0 - 2 * y1 + y2
    if curvature <= 0:
        return float(log_d[k])
    step = log_d[k + 1] - log_d[k]
    return float(log_d[k] + 0.5 * step * (y0 - y2) / curvature)
