"""Where simulation and measurement disagree, which named effect is missing, and the gap after.

From a measured log (t, x, v, i), a friction model (eq. 3), the nominal mass m and force
constant phi, the force residual of eq. (18) of section 6,

    r = phi i - m dv/dt - F(v) - sum(effects already in the model),

is smoothed (Savitzky-Golay, polynomial order 2) and sampled on decimated rows where the axis
moves (|v| above the noise and the window clear of reversals and sticking, where friction is
undetermined). Every candidate of ``fricgen.effects`` is fitted to the residual through the
same smoothing; candidates are compared by blocked cross-validation on the first part of the
log (the last ``holdout`` fraction is never used for fitting), and the cross-validated error
gain over "none", in log-likelihood units of the effective sample count, less a fixed penalty,
is the score. "none" wins unless an effect clears the penalty. The gap is the RMS velocity
error of simulations restarted from the measured state every ``horizon`` seconds and driven
by the measured current, on the held-out part, before and after adding the effect.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence

import numpy as np
from scipy.ndimage import minimum_filter1d
from scipy.signal import savgol_coeffs, savgol_filter

from .._validate import positive
from ..data import MotionLog
from ..effects import EFFECTS, Effect, Signals, model_effects, with_effects
from ..errors import DataError
from ..metrics import rmse
from ..model import FrictionModel
from ..sim.axis import AxisState, MotorAxis
from ..sim.effect_law import EffectLaw

#: Fewest moving rows the fit part must keep after masking.
MIN_ROWS = 100
#: Most rows the residual is sampled at: long logs are decimated further, so that time and
#: memory stop growing with the log's length beyond about MAX_ROWS windows.
MAX_ROWS = 20_000


class ResidualProblem:
    """The smoothed force residual on decimated moving rows, and the smoothing that made it."""

    def __init__(self, log: MotionLog, model: FrictionModel, mass: float, force_constant: float,
                 window: int, holdout: float, effects: Sequence[Effect] = ()):
        self.mass, self.force_constant = mass, force_constant
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
            raise DataError(f"log has too few moving samples ({self.rows.size * self.decimation} "
                            f"with |v| > {self.v_min:.3g} m/s away from reversals); need a log "
                            "that moves for most of its length")
        self.target = self.at_rows(self.raw[:, None], np.arange(self.rows.size))[:, 0]
        self.v_smooth, self.x_smooth = v_s, savgol_filter(log.x, window, 2)
        self._ripple = None

    @property
    def n_effective(self) -> float:
        """Independent samples among the fit rows (one per smoothing window)."""
        return self.fit_rows.size * min(self.decimation, self.window) / self.window

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
        if self._ripple is None:
            x = self.signals.x
            span = float(np.ptp(x[self.rows]))
            speed = float(np.median(np.abs(self.v_smooth[self.rows])))
            p_min = max(span / 100.0, 0.5 * speed * self.window * self.sample_time)
            p_max = span / 2.0
            step = 2 * np.pi / (4.0 * span)
            ks = np.arange(2 * np.pi / p_max, 2 * np.pi / p_min + step, step)
            X = x[self.rows[:, None] + self.offsets]
            bank = np.empty((ks.size, self.rows.size, 2))
            for j, k in enumerate(ks):
                bank[j, :, 0] = np.sin(k * X) @ self.coeffs
                bank[j, :, 1] = np.cos(k * X) @ self.coeffs
            self._ripple = (ks, bank)
        return self._ripple


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
    samples from ``start`` on, driven by the measured current (NaN before ``start``): the axis
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
        state = axis.karnopp(state, sig.i[k], problem.sample_time, substeps)
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
    effect: str
    score: float
    mse: float
    fitted: Optional[Effect] = None


class Diagnoser:
    """Name the effect a friction model misses in a measured log, and add it.

    Parameters: ``window`` smoothing window (s), ``holdout`` fraction of the log kept for the
    gap, ``horizon`` restart interval of the simulations (s), ``folds`` of the blocked
    cross-validation, ``penalty`` (log-likelihood units) an effect must clear to beat "none",
    ``candidates`` effect names to consider (default: all), ``substeps`` per sample.
    """

    def __init__(self, window: float = 0.021, holdout: float = 0.3, horizon: float = 0.02,
                 folds: int = 5, penalty: float = 10.0, candidates: Optional[Sequence[str]] = None,
                 substeps: int = 10):
        self.window, self.holdout, self.horizon = window, holdout, horizon
        self.folds, self.penalty, self.candidates, self.substeps = folds, penalty, candidates, substeps

    def _validate(self):
        if not 0.05 <= self.holdout <= 0.6:
            raise ValueError(f"holdout must be in [0.05, 0.6], got {self.holdout}")
        if self.folds < 2:
            raise ValueError(f"folds must be >= 2, got {self.folds}")
        if not self.window > 0:
            raise ValueError(f"window must be > 0, got {self.window}")
        if not self.horizon > 0:
            raise ValueError(f"horizon must be > 0, got {self.horizon}")
        names = list(EFFECTS) if self.candidates is None else list(self.candidates)
        for name in names:
            if name not in EFFECTS:
                raise ValueError(f"candidates: unknown effect {name!r}; known: {', '.join(EFFECTS)}")
        return names

    def fit(self, log: MotionLog, model: FrictionModel, mass: float, force_constant: float) -> "Diagnoser":
        names = self._validate()
        mass = positive("mass", mass, DataError)
        force_constant = positive("force constant", force_constant, DataError)
        ts = log.sample_time
        w = max(5, int(round(self.window / ts)) | 1)
        base = model_effects(model)
        p = ResidualProblem(log, model, mass, force_constant, w, self.holdout, base)
        self.problem_ = p
        mse_none = float(np.mean(p.target[p.fit_rows] ** 2))
        cands = [Candidate("none", 0.0, mse_none)]
        for name in names:
            mse = cross_validated_mse(p, EFFECTS[name], self.folds)
            gain = 0.5 * p.n_effective * math.log(mse_none / mse) if mse > 0 else float("inf")
            cands.append(Candidate(name, gain - self.penalty, mse))
        cands.sort(key=lambda c: -c.score)
        self.candidates_ = cands
        scores = np.array([c.score for c in cands])
        weights = np.exp(scores - scores.max())
        self.confidence_ = float(weights[0] / weights.sum())
        best = cands[0]
        self.effect_ = best.effect
        if best.effect != "none":
            best.fitted = EFFECTS[best.effect].fit(p, p.fit_rows)
        self.fitted_ = best.fitted
        added = [self.fitted_] if self.fitted_ is not None else []
        self.model_ = with_effects(model, added)
        self.localization_ = localize(p)
        self.where_ = self._where()
        # the gap on the held-out part, before and after
        horizon = max(1, int(round(self.horizon / ts)))
        self.v_sim_before_ = resimulate(p, base, p.split, horizon, self.substeps)
        self.v_sim_after_ = (resimulate(p, base + added, p.split, horizon, self.substeps)
                             if added else self.v_sim_before_)
        held = moving_segments(p, p.split, horizon)
        self.gap_before_ = self._gap(self.v_sim_before_[held], log.v[held])
        self.gap_after_ = self._gap(self.v_sim_after_[held], log.v[held])
        self.gap_metric_ = (f"rms velocity error (m/s) of simulations restarted from the measured "
                            f"state every {horizon * ts:.3g} s and driven by the measured current, "
                            f"on the held-out last {self.holdout:.0%} of the log while moving")
        test = p.test_rows
        self.force_gap_before_ = rmse(p.target[test], 0.0)
        self.force_gap_after_ = (rmse(p.target[test], p.predict(self.fitted_, test))
                                 if added else self.force_gap_before_)
        self.residual_after_ = p.raw_residual(base + added)
        return self

    @staticmethod
    def _gap(v_sim, v_meas) -> float:
        ok = np.isfinite(v_sim)
        return rmse(v_sim[ok], v_meas[ok])

    def _where(self) -> str:
        top = self.localization_[0]
        if top["share"] < 0.05:
            return "nowhere beyond noise (no axis explains 5 % of the residual)"
        return f"{top['axis']}: {top['detail']} ({top['share']:.0%} of the residual)"

    def parameters(self) -> Dict[str, float]:
        return {} if self.fitted_ is None else self.fitted_.parameters()

    def summary(self) -> dict:
        """The ``--json`` object."""
        return {"effect": self.effect_, "confidence": self.confidence_, "parameters": self.parameters(),
                "where": self.where_, "gap_before": self.gap_before_, "gap_after": self.gap_after_,
                "gap_metric": self.gap_metric_,
                "candidates": [{"effect": c.effect, "score": c.score} for c in self.candidates_]}


def diagnose(log: MotionLog, model: FrictionModel, mass: float, force_constant: float, **kwargs) -> Diagnoser:
    """``Diagnoser(**kwargs).fit(log, model, mass, force_constant)``."""
    return Diagnoser(**kwargs).fit(log, model, mass, force_constant)
