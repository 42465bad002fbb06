"""Where simulation and measurement disagree, which effects are missing, and the gap after.

From a measured log (t, x, v, i), a friction model (eq. 3), the nominal mass m and force
constant phi, the force residual of eq. (18) of section 6,

    r = phi i - m dv/dt - F(v) - sum(effects already in the model),

is smoothed (Savitzky-Golay, polynomial order 2) and sampled on decimated rows where the axis
moves (|v| above the noise and the window clear of reversals and sticking, where friction is
undetermined). The last ``holdout`` fraction of the log is never used for fitting. Effects are
selected by size (``Diagnoser``): sets of named effects are fitted jointly on the first part
and ranked by an information criterion, and a set one effect larger than the chosen one is
taken only if the held-out test of ``decision`` rejects "it explains nothing" at level
``alpha``, it changes the force by at least ``min_size`` of the friction force and the held-out
gap shrinks by at least ``min_gain``. The gap is the RMS velocity error of simulations
restarted from the measured state every ``horizon`` seconds and driven by the measured
current, on the held-out part, against the measured velocity smoothed as the residual is: the
velocity sensor's noise is not something a model can close; left in, it would set a floor under
the gap that hides what an effect removes.
"""
from __future__ import annotations

import copy
import itertools
import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np
from scipy.ndimage import minimum_filter1d
from scipy.signal import savgol_coeffs, savgol_filter

from .._validate import positive
from ..data import MotionLog
from ..data.motionlog import check_varies
from ..effects import (EFFECTS, PLAUSIBLE_FACTOR, TABLES, Effect, Signals, model_effects,
                       with_effects)
from ..errors import DataError
from ..metrics import least_squares_errors, rmse
from ..model import FrictionModel
from ..sim.axis import AxisState, MotorAxis
from ..sim.effect_law import EffectLaw
from .decision import held_out_p_value

#: Fewest moving rows the fit part must keep after masking.
MIN_ROWS = 100
#: Most rows the residual is sampled at: long logs are decimated further, so that time and
#: memory stop growing with the log's length beyond about MAX_ROWS windows.
MAX_ROWS = 8_000


class ResidualProblem:
    """The smoothed force residual on decimated moving rows, and the smoothing that made it."""

    def __init__(self, log: MotionLog, model: FrictionModel, mass: float, force_constant: float,
                 window: int, holdout: float, effects: Sequence[Effect] = ()):
        self.mass, self.force_constant = mass, force_constant
        check_varies(log.i, "current i", "A")
        ts = log.sample_time
        self.sample_time = ts
        self.signals = Signals(model, t=log.t, x=log.x, v=log.v, a=np.gradient(log.v, ts), i=log.i,
                               sample_time=ts, tabulate=True)
        self.effects = list(effects)
        n = len(log)
        self.window = window
        self.coeffs = savgol_coeffs(window, 2, use="dot")
        self.offsets = np.arange(window) - window // 2
        self.raw = self.raw_residual(self.effects)
        v_s = savgol_filter(log.v, window, 2)
        noise = log.v - v_s
        self.sigma_v = float(1.4826 * np.median(np.abs(noise - np.median(noise))))
        self.v_min = max(4.0 * self.sigma_v, 1e-3)
        moving = minimum_filter1d(np.abs(v_s), window) > self.v_min
        moving[: window] = moving[-window:] = False
        self.moving = moving
        # a third of a window apart, or further apart on long logs: at most MAX_ROWS rows
        self.decimation = max(1, window // 3, -(-int(moving.sum()) // MAX_ROWS))
        self.rows = np.flatnonzero(moving & (np.arange(n) % self.decimation == 0))
        self.split = int(round((1.0 - holdout) * n))
        self.fit_rows = np.flatnonzero(self.rows < self.split)
        self.test_rows = np.flatnonzero(self.rows >= self.split)
        if self.fit_rows.size < MIN_ROWS or self.test_rows.size < MIN_ROWS // 3:
            d = self.decimation
            raise DataError(f"log has too few moving samples (|v| > {self.v_min:.3g} m/s away from "
                            f"reversals): {self.fit_rows.size * d} in the first {1 - holdout:.0%} and "
                            f"{self.test_rows.size * d} in the rest, need {MIN_ROWS * d} and "
                            f"{MIN_ROWS // 3 * d}: a longer log, or one that moves more")
        self.target = self.at_rows(self.raw[:, None], np.arange(self.rows.size))[:, 0]
        self._check_scale()
        self.v_smooth, self.x_smooth = v_s, savgol_filter(log.x, window, 2)
        # the simulations are driven by the current smoothed as the residual is, so that the
        # gap measures the model rather than the current sensor's noise integrated by 1/m
        self.i_smooth = savgol_filter(log.i, window, 2)
        self._cache: dict = {}          # shared by the copies of with_target

    def _check_scale(self) -> None:
        """Refuse inputs whose units or signs cannot be right: on the moving rows, phi i must
        follow m dv/dt + F(v) (plus a constant) with a slope of the same sign and within
        ``PLAUSIBLE_FACTOR`` of 1, else no effect of the vocabulary is what is missing; and
        regressed on m dv/dt and F(v) apart, the slope of F(v) may not be ``PART_OFF`` away
        from 1 nor that of m dv/dt above ``PART_OFF``."""
        every = np.arange(self.rows.size)
        sig = self.signals
        model_force = self.at_rows(self.mass * sig.a + sig.friction, every)
        motor_force = self.at_rows(self.force_constant * sig.i, every)
        coef, *_ = np.linalg.lstsq(np.column_stack([model_force, np.ones(every.size)]), motor_force,
                                   rcond=None)
        slope = float(coef[0])
        if slope <= 0:
            raise DataError("phi i works against m dv/dt + F(v) where the axis moves (slope "
                            f"{slope:.3g}): is the sign of the current or of the force constant inverted?")
        # the parts on their own (friction can hide a mass far off, and a mass and a force
        # constant both off by the same factor leave phi i = m dv/dt + F(v) a factor off in F):
        # phi i = k m dv/dt + b F(v) + c
        X = np.column_stack([self.at_rows(self.mass * sig.a, every),
                             self.at_rows(sig.friction, every), np.ones(every.size)])
        coef, se = least_squares_errors(X, motor_force, self._independent(every.size))
        (k, b), (se_k, se_b) = coef[:2], se[:2]

        def far_off(value, se, both_ways=True):
            return value - 3.0 * se > PART_OFF or (both_ways and value + 3.0 * se < 1.0 / PART_OFF)
        implied = (f"its accelerations ask for {k * self.mass:.3g} kg against the {self.mass:.3g} kg "
                   "given")
        if not 1.0 / PLAUSIBLE_FACTOR <= slope <= PLAUSIBLE_FACTOR:
            raise DataError(f"phi i is {slope:.3g} x m dv/dt + F(v) where the axis moves, beyond the "
                            f"factor {PLAUSIBLE_FACTOR:g} ({implied}): check the force constant, the "
                            "mass, the units of i, x, v and that the model is this axis'")
        # only a mass too small: the noise of dv/dt pulls k towards 0 (errors in variables), so
        # a small k is no proof, and a mass far too large fails the check of the whole above
        if far_off(k, se_k, both_ways=False):
            raise DataError(f"the log accelerates as if the mass were {k:.3g} x the mass given "
                            f"({implied}), beyond the factor {PART_OFF:g}: check the mass, its unit "
                            "and the force constant")
        if far_off(b, se_b):
            raise DataError(f"phi i holds {b:.3g} x the model's friction where the axis moves, beyond "
                            f"the factor {PART_OFF:g}: check the force constant and the mass (both "
                            "off by the same factor?) and that the model is this axis'")

    def with_target(self, target: np.ndarray) -> "ResidualProblem":
        """A shallow copy whose residual ``target`` (at the rows) is ``target``."""
        other = copy.copy(self)
        other.target = target
        return other

    def _independent(self, rows: int) -> float:
        """Independent samples among ``rows`` decimated rows (one per smoothing window)."""
        return rows * min(self.decimation, self.window) / self.window

    @property
    def n_effective(self) -> float:
        """Independent samples among the fit rows."""
        return self._independent(self.fit_rows.size)

    def raw_residual(self, effects: Sequence[Effect]) -> np.ndarray:
        """phi i - m a - F(v) - sum of the effects' forces, per sample (unsmoothed)."""
        sig = self.signals
        r = self.force_constant * sig.i - self.mass * sig.a - sig.friction
        for e in effects:
            r = r - e.force(sig)
        return r

    def at_rows(self, raw, rows) -> np.ndarray:
        """Smooth a full-rate signal (N,) or (N, k) with the residual's filter at ``rows``.

        ``raw`` may also be a function of sample indices (an (n, window) array) that returns
        the signal there: then only the samples the filter reads are computed."""
        idx = self.rows[np.asarray(rows)][:, None] + self.offsets
        windows = np.asarray(raw(idx) if callable(raw) else np.asarray(raw, dtype=float)[idx],
                             dtype=float)
        if windows.ndim == 2:
            return windows @ self.coeffs
        return np.einsum("nwk,w->nk", windows, self.coeffs)

    def predict(self, effect: Effect, rows) -> np.ndarray:
        """An effect's smoothed force at ``rows``."""
        return self.at_rows(effect.force(self.signals), rows)

    def ripple_bank(self):
        """Smoothed sin/cos regressors of position for a grid of wavenumbers (cached)."""
        if "ripple" not in self._cache:
            x = self.signals.x
            span = float(np.ptp(x[self.rows]))
            speed = float(np.median(np.abs(self.v_smooth[self.rows])))
            p_min = max(span / 100.0, 0.5 * speed * self.window * self.sample_time)
            p_max = span / 2.0
            step = 2 * np.pi / (4.0 * span)
            ks = np.arange(2 * np.pi / p_max, 2 * np.pi / p_min + step, step)
            X = x[self.rows[:, None] + self.offsets]
            bank = np.empty((ks.size, self.rows.size, 2))
            turn = np.exp(1j * step * X)           # exp(i k X) for the next k: one product
            for j, k in enumerate(ks):
                z = np.exp(1j * k * X) if j % 32 == 0 else z * turn     # exact every 32 steps
                w = z @ self.coeffs
                bank[j, :, 0], bank[j, :, 1] = w.imag, w.real
            self._cache["ripple"] = (ks, bank)
        return self._cache["ripple"]


def cross_validated_mse(problem: ResidualProblem, cls, folds: int) -> float:
    """Blocked K-fold cross-validation of one candidate over the fit rows."""
    blocks = np.array_split(problem.fit_rows, folds)
    err = 0.0
    for j, block in enumerate(blocks):
        train = np.concatenate([b for k, b in enumerate(blocks) if k != j])
        effect = cls.fit(problem, train)
        err += float(np.sum((problem.target[block] - problem.predict(effect, block)) ** 2))
    return err / problem.fit_rows.size


# ----------------------------------------------------------------------------- localization


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
    n_eff = problem.rows.size * min(problem.decimation, problem.window) / problem.window
    v = problem.v_smooth[idx]
    x = problem.x_smooth[idx]
    a = problem.at_rows(problem.signals.a, rows)
    t = problem.signals.t[idx]
    level = r * np.sign(v)
    out = []

    def add(axis, values, labels, detail):
        out.append({"axis": axis, "share": _binned_share(values, labels, n_eff), "detail": detail})

    def extreme(values, labels, coord, name, unit):
        groups = np.unique(labels)
        means = np.array([values[labels == g].mean() for g in groups])
        k = int(np.argmax(np.abs(means)))
        inside = coord[labels == groups[k]]
        return f"largest mean {means[k]:+.3g} N at {name} in [{inside.min():.3g}, {inside.max():.3g}] {unit}"

    pos, neg = r[v > 0], r[v < 0]
    add("direction of motion", r, (v > 0).astype(int),
        f"mean {pos.mean() if pos.size else 0:+.3g} N for v > 0, {neg.mean() if neg.size else 0:+.3g} N for v < 0")
    for axis, values, coord, name, unit in (("velocity", r, v, "v", "m/s"),
                                             ("speed, friction level", level, np.abs(v), "|v|", "m/s"),
                                             ("position", r, x, "x", "m")):
        lab = _quantile_labels(coord)
        add(axis, values, lab, extreme(values, lab, coord, name, unit))
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
                          f"{math.hypot(*coef[j]):.3g} N"})
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


# ----------------------------------------------------------------------------- simulation


def resimulate(problem: ResidualProblem, effects: Sequence[Effect], start: int, horizon: int,
               substeps: int = 10) -> np.ndarray:
    """Velocity of simulations restarted from the (smoothed) measured state every ``horizon``
    samples from ``start`` on, driven by the measured current (smoothed; NaN before ``start``): the axis
    of eq. (18) under the model's friction and ``effects``, in Karnopp steps."""
    sig = problem.signals
    n = sig.t.size
    law = EffectLaw(sig.model, effects, mass=problem.mass, force_constant=problem.force_constant)
    starts = np.arange(start, n - 1, horizon)
    s0 = None
    if law.lag_tau > 0:
        s0 = Signals(sig.model, v=problem.v_smooth, sample_time=problem.sample_time).lagged_speed(law.lag_tau)[starts]
    axis = MotorAxis(law)
    state = AxisState.of(problem.x_smooth[starts], problem.v_smooth[starts], sig.t[starts], s0)
    out = np.full(n, np.nan)
    for j in range(horizon):
        k = np.minimum(starts + j, n - 1)
        state = axis.karnopp(state, problem.i_smooth[k], problem.sample_time, substeps)
        k1 = starts + j + 1
        ok = k1 < n
        out[k1[ok]] = state.v[ok]
    return out


def moving_segments(problem: ResidualProblem, start: int, horizon: int) -> np.ndarray:
    """Samples of the restarted simulations whose segment, from its restart on, stays in the
    moving part of the log (stick and break-away are not what a friction curve identifies)."""
    n = problem.moving.size
    broken = np.concatenate([[0], np.cumsum(~problem.moving)])    # broken[k] = count before k
    k = np.arange(n)
    seg_start = start + ((k - start - 1) // horizon) * horizon      # restart of k's segment
    ok = (k > start) & (broken[k + 1] - broken[np.clip(seg_start, 0, n)] == 0)
    return ok


# ----------------------------------------------------------------------------- the estimator


@dataclass
class Candidate:
    """One candidate of one selection step: its cross-validated residual on the fit part."""
    effect: str
    mse: float


@dataclass
class Step:
    """One effect considered in the forward selection, fitted jointly with those chosen before,
    and the decision about it. ``p_value``: of the held-out test (``decision``); ``share``: the
    fraction of the held-out residual's sum of squares it removes; ``size``: the RMS of its
    own force there (in the joint fit), relative to the RMS friction force; ``gap_before``/``gap_after``:
    the held-out gap without and with it; ``reason``: why it was refused ('' if added)."""
    effect: str
    fitted: Optional[Effect]
    joint: List[Effect]
    p_value: float
    n_effective: float
    share: float
    size: float
    gap_before: float
    gap_after: float
    added: bool
    reason: str
    candidates: List[Candidate]

    @property
    def beside(self) -> List[str]:
        """The effects fitted jointly with this one: the context of its decision."""
        return [e.name for e in self.joint if e is not self.fitted]

    @property
    def label(self) -> str:
        """The effect, and for a refused one the effects it was fitted with: 'e (with a, b)'."""
        return self.effect if self.added or not self.beside else f"{self.effect} (with {', '.join(self.beside)})"

    @property
    def gain(self) -> float:
        """Relative reduction of the held-out gap, 1 - after / before."""
        return 1.0 - self.gap_after / self.gap_before if self.gap_before > 0 else 0.0

    def summary(self) -> dict:
        return {"effect": self.effect, "parameters": self.fitted.parameters() if self.fitted else {},
                "p_value": self.p_value, "share": self.share, "size": self.size, "gap_before": self.gap_before,
                "gap_after": self.gap_after, "held_out_gain": self.gain,
                "named": self.effect in EFFECTS}


#: A table is tried before the named effects when its cross-validated reduction of the
#: residual's mean square is more than this many times the best named effect's.
TABLE_PREFERENCE = 2.0
#: Most backfitting sweeps of a joint fit, and the relative fall of its mean square below
#: which a sweep ends it (slow pairs such as a drift beside an extra source need many).
BACKFIT_SWEEPS = 8
BACKFIT_TOLERANCE = 1e-3
#: Sets of named effects kept at each size to grow the next size from (beam search).
BEAM = 5
#: Named sets tried per step (best first by the joint criterion).
MAX_TRIES = 4
#: A mass this many times off the one the log's accelerations ask for, or friction this many
#: times the model's, is a wrong input (a unit), refused before the diagnosis; up to
#: ``PLAUSIBLE_FACTOR`` it is an inertia mismatch, a force-constant mismatch or an extra source.
PART_OFF = 10.0
#: Batches of the held-out samples for the standard error of a gap (``_closest``).
GAP_BATCHES = 10
#: Largest --max-effects.
MAX_EFFECTS = 8
#: Effects whose size over the whole log understates them, judged below ``min_size`` by the
#: held-out gap alone, which must then shrink by ``UNDERSTATED_GAIN`` rather than ``min_gain``:
#: those whose force lives in short stretches (the lag: at the reversals), and a mass or force
#: constant at least ``MISMATCH_RELEVANT`` off the nominal one (a mass half the nominal one on
#: a slow log changes the force by 2 % of the friction, and detunes any controller built on it).
SHORT_LIVED = ("frictional_lag",)
MISMATCH_RELEVANT = 0.1
UNDERSTATED_GAIN = 0.25


class Diagnoser:
    """Name the effects a friction model misses in a measured log, and add them.

    Selection by size, one effect more per step. At step k the sets of k named effects are grown
    from the ``BEAM`` best sets of k - 1 (the chosen one first): each set is fitted jointly
    (backfitting, with the parameters the forces are linear in solved together after each
    sweep, ``_joint_linear``) on the fit part and ranked by Akaike's criterion with the
    effective sample size (``_score``). So a step may also replace an earlier choice: a
    one-sided asymmetry chosen for what is a load plus a level change gives way to the two when
    the pair fits better. The best set (then the next, up to ``MAX_TRIES``) is taken only if,
    against the chosen set,

    1. the held-out test (``decision.held_out_p_value``) gives p < ``alpha``, and
    2. the fitted values are what the names say (``Effect.implausible``: no mass five times off),
    3. it is practically relevant: the force it changes on the held-out part is at least
       ``min_size`` of the RMS friction force (a friction model fitted to a sweep is off by
       about a percent; such bias is real structure, significant on long logs, but not a
       missing effect; for a lag or a mass or force constant ``MISMATCH_RELEVANT`` off, see
       ``UNDERSTATED_GAIN``), and
    4. the held-out gap shrinks by at least ``min_gain`` (relative): never an effect that makes
       the simulation worse.

    Only a set refused for its size or gap lets the next be tried. Once one passes, the others
    up to ``MAX_TRIES`` are checked as well, and of those that pass and whose held-out gap is
    within one standard error of the smallest, the best by the score per unit of mass is taken
    (``_closest``): the fit part can rank a drift below what it extrapolates to. When no set
    one larger is taken, the sets two larger that contain the chosen one are tried the same way
    (effects that fit the held-out part only together: a drift and a force-constant error,
    either alone fitted on the first part, extrapolate worse than nothing); each newcomer of a
    set must change the force by ``min_size`` on its own. When no named set is taken, the tables of
    ``fricgen.effects.tables`` (no physical name) are ranked by blocked
    cross-validation and added to the chosen set in the same way; they go first when the best
    table's gain is more than ``TABLE_PREFERENCE`` times the best named one's (structure no
    named form follows). Selection stops at ``max_effects`` or when nothing is added.

    Parameters: ``window`` smoothing window (s), ``holdout`` fraction of the log kept for the
    test and the gap, ``horizon`` restart interval of the simulations (s), ``folds`` of the
    blocked cross-validation, ``alpha`` level of each test, ``min_size`` and ``min_gain`` (see
    above), ``max_effects``, ``candidates`` effect names to consider (default:
    all), ``tables`` whether tables may be offered, ``substeps`` per sample.
    """

    def __init__(self, window: float = 0.021, holdout: float = 0.3, horizon: float = 0.02,
                 folds: int = 5, alpha: float = 0.01, min_size: float = 0.02, min_gain: float = 0.1,
                 max_effects: int = 3,
                 candidates: Optional[Sequence[str]] = None, tables: bool = True, substeps: int = 10):
        self.window, self.holdout, self.horizon = window, holdout, horizon
        self.folds, self.alpha, self.min_size, self.min_gain = folds, alpha, min_size, min_gain
        self.max_effects, self.candidates, self.tables, self.substeps = max_effects, candidates, tables, substeps

    def _validate(self):
        if not 0.05 <= self.holdout <= 0.6:
            raise ValueError(f"holdout must be in [0.05, 0.6], got {self.holdout}")
        if self.folds < 2:
            raise ValueError(f"folds must be >= 2, got {self.folds}")
        if not self.window > 0:
            raise ValueError(f"window must be > 0, got {self.window}")
        if not self.horizon > 0:
            raise ValueError(f"horizon must be > 0, got {self.horizon}")
        if not 0 < self.alpha < 1:
            raise ValueError(f"alpha must be in (0, 1), got {self.alpha}")
        if not 0 <= self.min_size < 1:
            raise ValueError(f"min_size must be in [0, 1), got {self.min_size}")
        if not 0 <= self.min_gain < 1:
            raise ValueError(f"min_gain must be in [0, 1), got {self.min_gain}")
        if (isinstance(self.max_effects, bool) or not isinstance(self.max_effects, int)
                or not 1 <= self.max_effects <= MAX_EFFECTS):
            raise ValueError(f"max_effects must be an integer in [1, {MAX_EFFECTS}], got {self.max_effects!r}")
        names = list(EFFECTS) if self.candidates is None else list(self.candidates)
        for name in names:
            if name not in EFFECTS:
                raise ValueError(f"candidates: unknown effect {name!r}; known: {', '.join(EFFECTS)}")
        return names

    # -- pieces of one step

    def _residual_problem(self, p: ResidualProblem, effects: Sequence[Effect], skip=None) -> ResidualProblem:
        """``p`` whose target is the residual after ``effects`` (but ``skip``)."""
        target = p.target.copy()
        every = np.arange(p.rows.size)
        for e in effects:
            if e is not skip:
                target -= p.predict(e, every)
        return p.with_target(target)

    def _joint_fit(self, p: ResidualProblem, chosen: List[Effect], cls) -> List[Effect]:
        """``cls`` fitted to the residual after ``chosen``, then every effect refitted to the
        residual after all the others (backfitting), on the fit rows, until a sweep lowers the
        mean square by less than ``BACKFIT_TOLERANCE`` (at most ``BACKFIT_SWEEPS`` sweeps)."""
        effects = list(chosen) + [cls.fit(self._residual_problem(p, chosen), p.fit_rows)]
        if len(effects) == 1:
            return effects
        effects = self._joint_linear(p, effects)
        mse = self._mse(p, effects)
        for _ in range(BACKFIT_SWEEPS):
            swept = list(effects)
            for j in range(len(swept)):
                others = self._residual_problem(p, swept, skip=swept[j])
                swept[j] = type(swept[j]).fit(others, p.fit_rows)
            swept = self._joint_linear(p, swept)
            new = self._mse(p, swept)
            if not new < mse:
                break
            converged = new > (1.0 - BACKFIT_TOLERANCE) * mse
            effects, mse = swept, new
            if converged:
                break
        return effects

    def _joint_linear(self, p: ResidualProblem, effects: List[Effect]) -> List[Effect]:
        """The parameters the effects' forces are linear in (``Effect.linear``), solved jointly
        by least squares on the fit rows with the others held, for each combination of the
        effects' ``variants`` (the asymmetry's side): backfitting alone converges slowly between
        effects as alike as a force-constant error and a friction drift."""
        sig, rows = p.signals, p.fit_rows
        if not any(e.linear(sig)[1].size for e in effects):
            return effects
        best, best_mse = effects, self._mse(p, effects)
        for combo in itertools.product(*(e.variants() for e in effects)):
            parts = [e.linear(sig) for e in combo]
            regressors = np.column_stack([R for R, _ in parts])
            fixed = sum((e.force(sig) - R @ c for e, (R, c) in zip(combo, parts)), np.zeros(sig.t.size))
            target = p.target[rows] - p.at_rows(fixed, rows)
            coef, *_ = np.linalg.lstsq(p.at_rows(regressors, rows), target, rcond=None)
            ends = np.cumsum([c.size for _, c in parts])
            solved = [e.with_coefficients(c) for e, c in zip(combo, np.split(coef, ends[:-1]))]
            mse = self._mse(p, solved)
            if mse <= best_mse:
                best, best_mse = solved, mse
        return best

    @staticmethod
    def _mse(p: ResidualProblem, effects: Sequence[Effect]) -> float:
        """Mean square of the residual after ``effects`` on the fit rows."""
        r = p.target[p.fit_rows] - sum((p.predict(e, p.fit_rows) for e in effects),
                                       np.zeros(p.fit_rows.size))
        return float(np.mean(r ** 2))

    def _score(self, p: ResidualProblem, effects: Sequence[Effect], per_mass: bool = False) -> float:
        """Akaike's criterion of a joint fit on the fit rows, with the effective sample size;
        ``per_mass``: of the residual in acceleration, the force residual over the set's mass
        (eq. 18), as the held-out gap sees it. A mass three times the nominal one and a force
        constant a third of the nominal one with the friction cut to a third move the axis
        alike, but the second's force residual is a third as large."""
        mse = max(self._mse(p, effects), 1e-300)
        if per_mass:
            mse /= (p.mass + sum(e.mass_delta for e in (*p.effects, *effects))) ** 2
        return p.n_effective * math.log(mse) + 2.0 * sum(e.n_params for e in effects)

    def _gap(self, p: ResidualProblem, effects) -> Tuple[float, np.ndarray]:
        v_sim = resimulate(p, list(effects), p.split, self.horizon_samples_, self.substeps)
        return rmse(self._held_errors(v_sim), 0.0), v_sim

    def _held_errors(self, v_sim: np.ndarray) -> np.ndarray:
        """The simulated minus the smoothed measured velocity on the held-out samples (finite ones)."""
        held = self.held_
        e = v_sim[held] - self.problem_.v_smooth[held]
        return e[np.isfinite(e)]

    def _consider(self, p, base, chosen, gap_now, ranked, classes, joint=None) -> Step:
        """Fit the ranked candidate jointly with ``chosen`` (or take the set ``joint``), test the
        change on the held-out rows and check the gap."""
        name = ranked[0].effect
        if joint is None:
            joint = self._joint_fit(p, chosen, classes[name])
        test = p.test_rows
        before = p.target[test] - sum((p.predict(e, test) for e in chosen), np.zeros(test.size))
        after = p.target[test] - sum((p.predict(e, test) for e in joint), np.zeros(test.size))
        p_value, n_eff = held_out_p_value(before, after)
        ss_before = float(np.sum(before ** 2))
        share = 1.0 - float(np.sum(after ** 2)) / ss_before if ss_before > 0 else 0.0
        friction = rmse(p.signals.friction[p.rows[test]], 0.0)
        size = rmse(before - after, 0.0) / friction if friction > 0 else math.inf   # the force it changes
        step = Step(name, joint[-1], joint, p_value, n_eff, share, size, gap_now, math.nan, False, "", ranked)
        if p_value >= self.alpha:
            step.reason = f"not significant on the held-out part (p = {p_value:.2g} >= {self.alpha:g})"
            return step
        why = next((e.implausible() for e in joint if e.implausible()), "")
        if why:
            step.reason = why if len(joint) == 1 else f"in the set {', '.join(e.name for e in joint)}: {why}"
            return step
        had = {e.name for e in chosen}
        newcomers = [e for e in joint if e.name not in had]
        gain = self.min_gain
        if size < self.min_size:
            step.reason = (f"too small to matter ({size:.1%} of the friction force, below "
                           f"{self.min_size:.0%})")
            if not all(e.name in SHORT_LIVED or e.mismatch() >= MISMATCH_RELEVANT for e in newcomers):
                return step
            gain = UNDERSTATED_GAIN
        if len(newcomers) > 1:          # each effect a set names must matter on its own
            own = {e.name: rmse(p.predict(e, test), 0.0) / friction for e in newcomers}
            small = min(own, key=own.get)
            if own[small] < self.min_size:
                step.reason = (f"{small} is too small to matter in the set ({own[small]:.1%} of "
                               f"the friction force, below {self.min_size:.0%})")
                return step
        step.gap_after, v_sim = self._gap(p, base + joint)
        if not step.gap_after <= (1.0 - gain) * gap_now:
            step.reason = ((step.reason + ", and the held-out gap" if step.reason else
                            "the held-out gap") + f" does not shrink by {gain:.0%} "
                           f"({gap_now:.3g} -> {step.gap_after:.3g} m/s)")
            return step
        step.reason = ""
        step.added = True
        self._v_sim = v_sim
        return step

    def _extensions(self, p, beam, names, used) -> List[Tuple[float, List[Effect]]]:
        """Every set of one more named effect grown from a set of the beam, fitted jointly, best
        first by ``_score``; each distinct set once, its effects in the order they entered."""
        seen, out = set(), []
        for path in beam:
            have = {e.name for e in path}
            for name in names:
                key = frozenset(have | {name})
                if name in used or name in have or key in seen:
                    continue
                seen.add(key)
                joint = self._joint_fit(p, path, EFFECTS[name])
                out.append((self._score(p, joint), joint))
        return sorted(out, key=lambda t: t[0])

    def _try(self, p, base, chosen, gap_now, ranked, grown, tables) -> Optional[Step]:
        """Consider the candidates of one kind in turn: ``grown`` named sets (from
        ``_extensions``, best first) or, if None, the ``ranked`` tables added to ``chosen``.
        Only a significant candidate refused for its size or gap lets the next be tried; once
        a named set passes, the other sets up to ``MAX_TRIES`` are checked too and ``_closest``
        chooses among those that pass."""
        options = ([(k, None) for k in range(len(ranked))] if grown is None else
                   [(0, path) for _, path in grown[:MAX_TRIES]])
        had = {e.name for e in chosen}
        step, passed = None, []
        for k, joint in options:
            if joint is None:
                step = self._consider(p, base, chosen, gap_now, ranked[k:], tables)
            else:
                newcomer = [e for e in joint if e.name not in had][-1]
                step = self._consider(p, base, chosen, gap_now, ranked, None, joint=joint)
                step.effect, step.fitted = newcomer.name, newcomer
            self.steps_.append(step)
            if step.added:
                passed.append((step, self._v_sim))
                if joint is None:
                    break
            elif step.p_value >= self.alpha and not passed:
                return step
        if not passed:
            return step
        step, self._v_sim = self._closest(passed)
        self._replace(step, chosen)
        return step

    def _closest(self, passed: List[Tuple[Step, np.ndarray]]) -> Tuple[Step, np.ndarray]:
        """Of the sets that pass the checks (with their simulations), the best by ``_score``
        per unit of mass among those whose held-out gap is within one standard error of the
        smallest: the first part of a log can rank a set below one that extrapolates worse (a
        drift is small there), and where the held-out part cannot tell sets apart the score
        decides, in the units the gap sees. The others are marked refused, saying why."""
        best, v_best = min(passed, key=lambda sv: sv[0].gap_after)
        limit = best.gap_after + self._gap_standard_error(v_best)
        p = self.problem_
        pick = min((sv for sv in passed if sv[0].gap_after <= limit),
                   key=lambda sv: self._score(p, sv[0].joint, per_mass=True))
        names = ", ".join(e.name for e in pick[0].joint)
        for s, _ in passed:
            if s is not pick[0]:
                s.added = False
                s.reason = (f"passes, but the set {names} fits the first part better (per unit of "
                            f"mass) and is as close to the held-out part (within one standard error)"
                            if s.gap_after <= limit else
                            f"passes, but the set {names} leaves a smaller held-out gap "
                            f"({pick[0].gap_after:.3g} m/s against {s.gap_after:.3g})")
        return pick

    def _gap_standard_error(self, v_sim: np.ndarray) -> float:
        """Standard error of a held-out gap, from the mean squared error of ``GAP_BATCHES``
        consecutive batches of the held-out samples (their errors are correlated in time)."""
        e2 = self._held_errors(v_sim) ** 2
        if e2.size < 2 * GAP_BATCHES or not e2.mean() > 0:
            return 0.0
        means = np.array([b.mean() for b in np.array_split(e2, GAP_BATCHES)])
        return float(means.std(ddof=1) / math.sqrt(GAP_BATCHES) / (2.0 * math.sqrt(e2.mean())))

    def _replace(self, step: Step, chosen: List[Effect]) -> None:
        """Book a set that is not ``chosen`` plus one effect: each of its other newcomers gets a
        step of its own (same test), each effect it drops is marked replaced."""
        new = {e.name for e in step.joint}
        old = {e.name for e in chosen}
        for e in step.joint:
            if e.name not in old and e is not step.fitted:
                twin = copy.copy(step)
                twin.effect, twin.fitted = e.name, e
                self.steps_.insert(len(self.steps_) - 1, twin)
        gone = old - new
        for s in self.steps_:
            if s.added and s.effect in gone:
                s.added = False
                s.reason = (f"replaced: the set {', '.join(e.name for e in step.joint)} fits "
                            "better and passes the held-out checks")

    def _rank(self, q: ResidualProblem, classes) -> List[Candidate]:
        ranked = [Candidate(name, cross_validated_mse(q, cls, self.folds)) for name, cls in classes.items()]
        return sorted(ranked, key=lambda c: c.mse)

    def _prepare(self, log: MotionLog, model: FrictionModel, mass: float, force_constant: float):
        """The residual problem of the log under the model's own effects, and the held-out gap
        of the model as it is (``gap_before_``)."""
        mass = positive("mass", mass, DataError)
        force_constant = positive("force constant", force_constant, DataError)
        ts = log.sample_time
        w = max(5, int(round(self.window / ts)) | 1)
        # the model's own effects as they apply to this log: a carried mass or force constant
        # is the axis' own, a drift starts with the log
        base = [e.for_log(mass, force_constant, float(log.t[0])) for e in model_effects(model)]
        p = ResidualProblem(log, model, mass, force_constant, w, self.holdout, base)
        self.problem_ = p
        self.horizon_samples_ = max(1, int(round(self.horizon / ts)))
        self.held_ = moving_segments(p, p.split, self.horizon_samples_)
        self.gap_before_, self.v_sim_before_ = self._gap(p, base)
        return p, base

    def held_out_gap(self, log: MotionLog, model: FrictionModel, mass: float,
                     force_constant: float) -> float:
        """The held-out gap of the model as it is on ``log`` (``gap_before_`` of ``fit``,
        without the selection): e.g. of a log whose current is corrected by known effects."""
        self._validate()
        self._prepare(log, model, mass, force_constant)
        return self.gap_before_

    # -- the selection

    def fit(self, log: MotionLog, model: FrictionModel, mass: float, force_constant: float) -> "Diagnoser":
        names = self._validate()
        p, base = self._prepare(log, model, mass, force_constant)
        ts = log.sample_time
        self._v_sim = self.v_sim_before_
        used = {e.name for e in base}
        chosen: List[Effect] = []
        beam: List[List[Effect]] = [[]]
        self.steps_: List[Step] = []
        gap_now = self.gap_before_
        while len(chosen) < self.max_effects:
            q = self._residual_problem(p, chosen)
            taken = used | {e.name for e in chosen}
            tables = {n: c for n, c in TABLES.items() if n not in taken} if self.tables else {}
            named = {n: EFFECTS[n] for n in names if n not in taken}
            ranked_named = self._rank(q, named) if named else []
            ranked_tables = self._rank(q, tables) if tables else []
            mse_none = float(np.mean(q.target[p.fit_rows] ** 2))
            sets = self._extensions(p, beam, names, used) if named else []
            # the named side's gain: the best single effect's, or a better set's (one that
            # replaces an earlier choice), whose fit-part mean square is not cross-validated
            best_set = min((self._mse(p, path) for _, path in sets[:1]), default=math.inf)
            best_named = min([c.mse for c in ranked_named[:1]] + [best_set])
            gain_named = mse_none - best_named if named else 0.0
            gain_table = mse_none - ranked_tables[0].mse if ranked_tables else 0.0
            trials = [(ranked_named, sets), (ranked_tables, None)]
            if ranked_tables and gain_table > TABLE_PREFERENCE * max(gain_named, 0.0):
                trials.reverse()       # a table explains far more than any named effect
            step = None
            for ranked, grown in trials:
                step = self._try(p, base, chosen, gap_now, ranked, grown, tables)
                if step is not None and step.added:
                    break
            if (step is None or not step.added) and named and len(chosen) + 2 <= self.max_effects:
                # two at once: effects that only together fit the held-out part (a drift and
                # a force-constant error: either alone, fitted on the first part, extrapolates
                # worse than nothing)
                have = {e.name for e in chosen}
                pairs = self._extensions(p, [path for _, path in sets[:BEAM]
                                             if have <= {e.name for e in path}], names, used)
                if pairs:
                    step = self._try(p, base, chosen, gap_now, ranked_named, pairs, tables)
                    sets = pairs if step.added else sets       # the next beam: sets of its size
            if step is None or not step.added:
                break
            chosen, gap_now = step.joint, step.gap_after
            beam = [chosen] + [path for _, path in sets[:BEAM]
                               if {e.name for e in path} != {e.name for e in chosen}][:BEAM - 1]
        self.effects_ = [s for s in self.steps_ if s.added]
        self._chain_gaps()
        # the joint refits change the parameters of earlier effects: report the final ones
        final = {e.name: e for e in chosen}
        for s in self.effects_:
            s.fitted = final[s.effect]
        chosen = [s.fitted for s in self.effects_]       # in the order they were added
        self.added_ = chosen
        self.effect_ = self.effects_[0].effect if self.effects_ else "none"
        self.p_value_ = self.steps_[0].p_value if self.steps_ else 1.0
        self.model_ = with_effects(model, chosen)
        self.localization_ = localize(p)
        self.where_ = self._where(self.localization_)
        final = self._residual_problem(p, chosen)
        self.localization_after_ = localize(final)
        self.where_after_ = self._where(self.localization_after_)
        self.v_sim_after_ = self._v_sim
        self.gap_after_ = gap_now
        self.gap_metric_ = (f"rms velocity error (m/s) of simulations restarted from the measured "
                            f"state every {self.horizon_samples_ * ts:.3g} s and driven by the measured "
                            f"current, against the measured velocity smoothed as the residual is, on "
                            f"the held-out last {self.holdout:.0%} of the log while moving")
        test = p.test_rows
        self.force_gap_before_ = rmse(p.target[test], 0.0)
        self.force_gap_after_ = rmse(final.target[test], 0.0)
        self.residual_after_ = p.raw_residual(base + chosen)
        return self

    def _chain_gaps(self) -> None:
        """Each added step's gap before is the gap after the effects added before it (effects
        that entered together share theirs): a step that replaced an earlier choice was decided
        against that choice, which the final list no longer holds."""
        before, last = self.gap_before_, None
        for s in self.effects_:
            if last is not None and s.joint is not last.joint:
                before = last.gap_after
            s.gap_before, last = before, s

    @staticmethod
    def _where(localization) -> str:
        top = localization[0]
        if top["share"] < 0.05:
            return "nowhere beyond noise (no axis explains 5 % of the residual)"
        return f"{top['axis']}: {top['detail']} ({top['share']:.0%} of the residual)"

    @property
    def fitted_(self) -> Optional[Effect]:
        """The first effect added (None if none)."""
        return self.added_[0] if self.added_ else None

    def parameters(self) -> Dict[str, object]:
        """The parameters of the first effect added ({} if none)."""
        return {} if self.fitted_ is None else self.fitted_.parameters()

    def refused(self) -> List[Step]:
        return [s for s in self.steps_ if not s.added]

    def summary(self) -> dict:
        """The ``--json`` object."""
        return {"effect": self.effect_, "p_value": self.p_value_, "parameters": self.parameters(),
                "effects": [s.summary() for s in self.effects_],
                "refused": [{"effect": s.effect, "beside": s.beside, "p_value": s.p_value,
                             "reason": s.reason} for s in self.refused()],
                "where": self.where_, "where_after": self.where_after_,
                "gap_before": self.gap_before_, "gap_after": self.gap_after_,
                "gap_metric": self.gap_metric_, "alpha": self.alpha, "min_size": self.min_size,
                "min_gain": self.min_gain,
                "candidates": [{"effect": c.effect, "cv_rms": math.sqrt(c.mse)}
                               for c in (self.steps_[0].candidates if self.steps_ else [])]}


def diagnose(log: MotionLog, model: FrictionModel, mass: float, force_constant: float, **kwargs) -> Diagnoser:
    """``Diagnoser(**kwargs).fit(log, model, mass, force_constant)``."""
    return Diagnoser(**kwargs).fit(log, model, mass, force_constant)
