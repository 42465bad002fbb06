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
standard error, and the encoder resolves the pre-sliding distance in DAMPING_COUNTS counts or
more, else 0 and the report says why: its rate dz/dt comes from the position's steps, and a
distance of a few counts makes it a staircase whose edges read as damping (5 counts gave
sigma1 4.9 times the truth with a standard error of 8 %).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..data.inverse_dynamics import position_quantum
from ..data.smoothing import smooth
from ..effects.fitting import FIT_FOLDS, block_grams, one_standard_error_choice
from ..effects.presliding import LEAST_LEVEL, Bristles, bristle_states
from ..errors import DataError

#: Pre-sliding distances tried per decade, and the grid's ends: a quarter of the position's
#: step (or of its noise, for a continuous position) to a tenth of the travel.
POINTS_PER_DECADE = 12
LEAST_DISTANCE_STEPS = 0.25
LARGEST_DISTANCE_TRAVEL = 0.1
#: The windows (samples, odd) of the cubic smoothing of the position that drives the bristles,
#: the one of least residual taken: an encoder that dithers by a count or more at rest would
#: drive them through |v| > 0 on every toggle and relax them (their dissipation grows with the
#: distance travelled), where the true contact holds its deflection.
POSITION_WINDOWS = (15, 31, 63)
#: A row's bristles have settled when their force is within this share of the static level.
SETTLED_SHARE = 0.02
#: A static curve whose level drops by less than this share from rest has no Stribeck velocity:
#: its damping does not fade.
NO_DROP = 0.05
#: The speeds v_d tried for the damping's fading, times the static curve's Stribeck velocity
#: (``fading_speed``), refined by a parabola in log v_d; and a damping that does not fade.
FADING_FACTORS = tuple(2.0 ** (k / 2) for k in range(-6, 7))
#: The stiffness is kept when its standard error (of log sigma0) is at most this: a third of it.
STIFFNESS_SE_MAX = 1.0 / 3.0
#: sigma1 is kept when above this many standard errors, and where the encoder resolves the
#: pre-sliding distance in this many counts (the slow-speeds guide's ten).
DAMPING_SIGMAS = 2.0
DAMPING_COUNTS = 10


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
    position_window: int        # the smoothing of the position that drives the bristles
    rms_static: float           # residual RMS with the static curve (the stiffest grid point)
    rms_dynamic: float          # ... with the bristles
    reason: str                 # '' when kept, else why not
    damping_reason: str = ""    # why sigma1 is left at 0 where the bristles are kept, else ''



def _levels(model, points: int = 1025) -> list:
    """(speeds, g) of each direction's curve on ``points`` speeds of [0, v_sat]."""
    return [(u, d.stribeck(u)) for d in model.directions for u in [d.v_sat * np.linspace(0.0, 1.0, points)]]


def fading_speed(model) -> Optional[float]:
    """v_d of the damping: where the static curve's velocity-weakening drop g(v) - min g has
    fallen to 1/e of its value at rest (the Stribeck velocity of [F1]'s shapes), averaged over
    the directions; None for a curve that drops by less than NO_DROP of its level at rest."""
    speeds = []
    for u, g in _levels(model):
        drop = g - g.min()
        if not drop[0] > NO_DROP * g[0]:
            return None
        speeds.append(float(u[np.argmax(drop <= drop[0] / np.e)]))
    return float(np.mean(speeds))


def falling_level(model):
    """g(v) made non-increasing in |v| per direction (its upper envelope from faster speeds):
    LuGre's velocity-weakening level never rises with speed, and a static fit that does near
    rest has read the bristles' build-up after each start as less friction; the first pass of
    ``train --dynamic`` drives the bristles with this level until the static curve is fitted
    again on the settled rows. Returns a function of v (arrays)."""
    tables = [(u, np.maximum.accumulate(g[::-1])[::-1]) for u, g in _levels(model)]
    negative = tables[-1]

    def level(v):
        v = np.asarray(v, dtype=float)
        speed = np.abs(v)
        positive = np.interp(speed, *tables[0])
        return positive if len(tables) == 1 else np.where(v < 0, np.interp(speed, *negative), positive)
    return level


def static_level(model) -> float:
    """The largest level g of the static curve over its speeds: the scale of pre-sliding
    distances g / sigma0 (``DataError`` for a curve without friction)."""
    level = max(float(np.max(g)) for _, g in _levels(model, 65))
    if not level > 0:
        raise DataError("the static curve has no friction: no bristles to identify")
    return level


def settled_rows(x, model, bristles: Bristles, dt: float, window: int, position_window: int,
                 share: float = SETTLED_SHARE) -> np.ndarray:
    """The rows of a log where the bristles have settled: sigma0 z within ``share`` of the
    static level g(v) sgn(v) at the velocity smoothed by ``window`` (the rows a static curve
    describes); False at rest and while the bristles build up after a reversal or a start. The
    bristles are driven by the position smoothed by ``position_window`` (``POSITION_WINDOWS``)."""
    x = np.asarray(x, dtype=float)
    v = np.diff(smooth(x, position_window)) / dt
    static = static_level(model)
    z = bristle_states(v, np.maximum(model.stribeck(v), LEAST_LEVEL * static), bristles.stiffness, dt)
    v_s = smooth(x, window, deriv=1, delta=dt)[1:]
    target = np.sign(v_s) * model.stribeck(v_s)
    ok = (v_s != 0) & (np.abs(bristles.stiffness * z - target) <= share * np.abs(target))
    return np.concatenate([[False], ok])


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
                        window: int = 31, folds: int = FIT_FOLDS,
                        falling: bool = False) -> PreslidingFit:
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
    folds : int
        Contiguous blocks of the jackknife and the cross-validation.
    falling : bool
        Drive the bristles with ``falling_level`` instead of the curve's own g.
    """
    t, x, force = (np.asarray(a, dtype=float) for a in (t, x, force))
    if not (t.size == x.size == force.size) or t.size < 4 * window:
        raise DataError(f"pre-sliding needs t, x and force of one length, at least {4 * window} rows")
    dt = float(np.median(np.diff(t)))
    counts = position_quantum(x)
    static = static_level(model)
    g = falling_level(model) if falling else model.stribeck
    v = np.diff(x) / dt
    viscous = model.viscous_force(v)
    quantum = counts or float(np.std(np.diff(x, 2)) / np.sqrt(6.0))
    travel = float(np.ptp(x))
    lo, hi = LEAST_DISTANCE_STEPS * max(quantum, 1e-12), LARGEST_DISTANCE_TRAVEL * travel
    if not hi > 4 * lo:
        raise DataError("the log moves too little to tell a pre-sliding distance")
    distances = np.logspace(np.log10(lo), np.log10(hi),
                            int(np.ceil(POINTS_PER_DECADE * np.log10(hi / lo))) + 1)
    base = smooth(force, window)[1:] - mass * smooth(x, window, deriv=2, delta=dt)[1:] \
        - smooth(np.concatenate([[0.0], viscous]), window)[1:]
    speed = smooth(x, window, deriv=1, delta=dt)[1:]
    fading = fading_speed(model)

    def grams_at(s0, fades, motion):
        """Per block Gram matrices of [sigma1 column for each v_d of ``fades``, 1] and the target,
        the bristles driven by ``motion`` (velocity, level)."""
        z = bristle_states(*motion, s0, dt)
        dz = np.diff(np.concatenate([[0.0], z])) / dt
        target = base - smooth(np.concatenate([[0.0], s0 * z]), window)[1:]
        out = []
        for vd in fades:
            weight = 1.0 if vd is None else np.exp(-(speed / vd) ** 2)
            columns = [smooth(np.concatenate([[0.0], weight * dz]), window)[1:]]
            if offset_free:
                columns.append(np.ones(v.size))
            design = np.column_stack(columns)[window:-window]
            out.append(block_grams(design, target[window:-window], folds))
        return out

    candidates = []
    for w in POSITION_WINDOWS:                   # the encoder's dither averaged out, or not
        u = np.diff(smooth(x, w)) / dt
        motion = (u, np.maximum(g(u), LEAST_LEVEL * static))
        grams = [grams_at(static / d, [fading], motion)[0] for d in distances]
        candidates.append((_profile(grams, folds), grams, motion))
    best_window = min(range(len(candidates)), key=lambda c: float(np.min(candidates[c][0][0][0])))
    (rss, coef, held_out), grams, motion = candidates[best_window]
    best, best_by_fold = _vertex(np.log(distances), rss[0]), \
        [_vertex(np.log(distances), rss[1 + j]) for j in range(folds)]
    k = int(np.argmin(rss[0]))
    jack = np.array(best_by_fold)
    log_se = _jackknife_se(jack)
    stiffness = static / float(np.exp(best))
    # the damping and the speed it fades at, at that stiffness
    fades = [None] if fading is None else [fading * f for f in FADING_FACTORS] + [None]
    fade_rss = _profile(grams_at(stiffness, fades, motion), folds, held_out=False)[0][0]
    if fading is not None and int(np.argmin(fade_rss)) < len(FADING_FACTORS):   # refined
        fades = [float(np.exp(_vertex(np.log(fades[:-1]), fade_rss[:-1])))]
    else:
        fades = [fades[int(np.argmin(fade_rss))]]
    fade_rss, fade_coef, _ = _profile(grams_at(stiffness, fades, motion), folds, held_out=False)
    f_best = 0
    damping = float(fade_coef[0][f_best][0])
    damping_se = _jackknife_se(np.array([fade_coef[1 + j][f_best][0] for j in range(folds)]))
    n = sum(g[3] for g in grams[0])
    rms_static, rms_dynamic = float(np.sqrt(rss[0][0] / n)), float(np.sqrt(fade_rss[0][f_best] / n))
    rows = _presliding_rows(x, motion[0], static / stiffness)
    errors = np.array([held_out[0], [held_out_at(grams, j, int(np.argmin(rss[1 + j]))) for j in range(folds)]])
    reason = ""
    if k == 0 or k == distances.size - 1:
        reason = ("the best pre-sliding distance is at the end of the range tried "
                  f"({np.exp(best):.3g}): the log does not resolve pre-sliding")
    elif log_se > STIFFNESS_SE_MAX:
        reason = (f"the stiffness is not determined ({stiffness:.3g} +- {stiffness * log_se:.2g}): "
                  "log small reversals, slowly, that the encoder resolves")
    elif one_standard_error_choice(errors) == 1:
        reason = ("the bristles do not lower the held-out error beyond its spread: the log holds "
                  "no pre-sliding the encoder resolves (log small reversals or a slow force ramp at rest)")
    bristles, damping_reason = None, ""
    if not reason:
        steps = static / stiffness / counts if counts else np.inf
        if steps < DAMPING_COUNTS:
            damping_reason = (f"the encoder resolves the pre-sliding distance in {steps:.3g} counts, "
                              f"fewer than the {DAMPING_COUNTS} its rate needs")
        elif not damping > DAMPING_SIGMAS * damping_se:
            damping_reason = f"not above {DAMPING_SIGMAS:g} standard errors"
        keep = not damping_reason
        bristles = Bristles(stiffness=stiffness, damping=damping if keep else 0.0,
                            damping_speed=fades[f_best] if keep else None)
    return PreslidingFit(bristles=bristles, stiffness=stiffness, stiffness_se=stiffness * log_se,
                         damping=damping, damping_se=damping_se, presliding_rows=rows,
                         position_window=POSITION_WINDOWS[best_window],
                         rms_static=rms_static, rms_dynamic=rms_dynamic, reason=reason,
                         damping_reason=damping_reason)


def _jackknife_se(replicates: np.ndarray) -> float:
    """The blocked jackknife's standard error from the estimates without each block."""
    folds = replicates.size
    return float(np.sqrt((folds - 1) / folds * np.sum((replicates - replicates.mean()) ** 2)))


def _solve(g, b):
    return np.linalg.lstsq(g, b, rcond=None)[0]


def _profile(grams, folds, held_out: bool = True):
    """Per grid point: the RSS and coefficients of all rows (index 0) and without each block
    (1..folds); the held-out mean squares of the first (stiffest) point per block."""
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
    return rss, coef, [[held_out_at(grams, j, 0) for j in range(folds)]] if held_out else None


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
