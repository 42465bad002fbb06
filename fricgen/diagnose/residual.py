"""The force residual of [C1], smoothed and sampled where the axis moves.

From a measured log (t, x, v, i), a friction model [F3], the nominal mass m and force
constant phi,

    r = phi i - m dv/dt - F(v) - sum(effects already in the model),

F(v) the model's friction along the log (with its bristles' state where it has pre-sliding),

is smoothed (Savitzky-Golay, polynomial order 2) and sampled on decimated rows where the axis
moves (|v| above the noise and the window clear of reversals and sticking, where friction is
undetermined). The last ``holdout`` fraction of the log is never used for fitting.
"""
from __future__ import annotations

import copy
from typing import Optional, Sequence

import numpy as np
from scipy.ndimage import minimum_filter1d
from scipy.signal import savgol_coeffs, savgol_filter

from ..data import MotionLog
from ..data.motionlog import check_varies
from ..effects import PLAUSIBLE_FACTOR, Effect, Signals
from ..effects.contact import deflection
from ..effects.presliding import bristles_of
from ..errors import DataError
from ..metrics import least_squares_errors
from ..model import FrictionModel

#: Fewest moving rows the fit part must keep after masking.
MIN_ROWS = 100
#: Most rows the residual is sampled at: long logs are decimated further, so that time and
#: memory stop growing with the log's length beyond about MAX_ROWS windows.
MAX_ROWS = 8_000
#: A mass this many times off the one the log's accelerations ask for, or friction this many
#: times the model's, is a wrong input (a unit), refused before the diagnosis; up to
#: ``PLAUSIBLE_FACTOR`` it is an inertia mismatch, a force-constant mismatch or an extra source.
PART_OFF = 10.0


class ResidualProblem:
    """The smoothed force residual on decimated moving rows, and the smoothing that made it."""

    def __init__(self, log: MotionLog, model: FrictionModel, mass: float, force_constant: float,
                 window: int, holdout: float, effects: Sequence[Effect] = (),
                 pitch: Optional[float] = None):
        self.mass, self.force_constant = mass, force_constant
        #: A known fundamental period of the effects periodic in position (m), or None: found
        #: from the data (``effects.position_series``).
        self.pitch = pitch
        check_varies(log.i, "current i", "A")
        ts = log.sample_time
        self.sample_time = ts
        self.signals = Signals(model, t=log.t, x=log.x, v=log.v, a=np.gradient(log.v, ts), i=log.i,
                               sample_time=ts, tabulate=True,
                               friction=model.force_along(log.v, ts) if bristles_of(model) else None)
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
        coef, se = least_squares_errors(X, motor_force, self.independent(every.size))
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

    def deflection(self, stiffness: float) -> np.ndarray:
        """The deflection z of bristles of ``stiffness`` on the model's curve at the start of
        each sample, driven by the measured velocity from a relaxed contact as the residual's
        friction is (cached)."""
        key = ("deflection", stiffness)
        if key not in self._cache:
            z = deflection(self.signals, stiffness)
            self._cache[key] = np.concatenate([[0.0], z[:-1]])
        return self._cache[key]

    def log_speeds(self, points: int = 256) -> np.ndarray:
        """Speeds up to the log's fastest (smoothed) |v|, log-spaced from a thousandth of its
        noise floor ``v_min`` (the firmware compensates below the floor too, at every
        reversal): where an effect's force must stay physical."""
        top = max(float(np.max(np.abs(self.v_smooth))), 2.0 * self.v_min)
        return np.geomspace(1e-3 * self.v_min, top, points)

    def with_target(self, target: np.ndarray) -> "ResidualProblem":
        """A shallow copy whose residual ``target`` (at the rows) is ``target``."""
        other = copy.copy(self)
        other.target = target
        return other

    def after(self, effects: Sequence[Effect], skip=None) -> "ResidualProblem":
        """This problem whose target is the residual after ``effects`` (but ``skip``)."""
        target = self.target.copy()
        every = np.arange(self.rows.size)
        for e in effects:
            if e is not skip:
                target -= self.predict(e, every)
        return self.with_target(target)

    def independent(self, rows: int) -> float:
        """Independent samples among ``rows`` decimated rows (one per smoothing window)."""
        return rows * min(self.decimation, self.window) / self.window

    @property
    def n_effective(self) -> float:
        """Independent samples among the fit rows."""
        return self.independent(self.fit_rows.size)

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
