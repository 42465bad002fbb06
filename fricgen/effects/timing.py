"""The named effect of the log's timing rather than of the axis: the logged motion and the
logged current are not simultaneous (a measurement filter, a bus latency), one small class of
the ``Effect`` contract (``base``).

With the motion x, v, a logged ``tau`` late, the force of [C1] at the logged signals is the
current's of ``tau`` earlier: m a + F(v) = phi i(t - tau), so the residual holds

    phi (i(t) - i(t - tau))      (about tau phi di/dt to first order),

read half a sample earlier in a sampled log (the current is held over each sample,
``SensorDelay.held_force``), so that ``tau`` is the delay a simulation driven by the held
current replays. It is read on the logged current, whose noise is far below that of m a (a
shift of g = m a + F(v) instead averages the acceleration's noise over a fraction of a
sample, and so fits a delay of half a sample on any log). It is no force of the axis: a
simulation replays it by driving the axis with the current ``tau`` earlier (``input_delay``).
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar, Tuple

import numpy as np

from ..errors import ModelError
from .base import Effect
from .fitting import grid_then_refine

#: The largest |tau| (s) a model may carry: beyond any drive's filter or bus latency.
MAX_DELAY = 0.1
#: The fit searches tau within this many samples of 0, either way.
SEARCH_SAMPLES = 20


def shifted(values: np.ndarray, samples: float) -> np.ndarray:
    """``values`` (uniformly sampled) read ``samples`` later, by linear interpolation between
    samples (a fraction of a sample too); held at the ends."""
    k = np.arange(values.size, dtype=float)
    return np.interp(k + samples, k, values)


#: The half sample (in samples) by which the held current leads the central-difference
#: acceleration of any log (``SensorDelay.held_force``).
HOLD = 0.5
#: Hat functions of |v| per direction, set aside before tau is fitted (knots at quantiles).
SPEED_KNOTS = 8


def _speed_basis(v: np.ndarray) -> np.ndarray:
    """Piecewise-linear functions of |v|, one set per direction: what a friction curve's own
    error looks like (on a sine, whose jerk is -w^2 v, a delay would stand in for it)."""
    speed = np.abs(v)
    knots = np.unique(np.quantile(speed, np.linspace(0.0, 1.0, SPEED_KNOTS)))
    cols = []
    for side in (v >= 0, v < 0):
        if not side.any():
            continue
        for j, k in enumerate(knots):
            lo = knots[j - 1] if j > 0 else k
            hi = knots[j + 1] if j + 1 < knots.size else k
            up = np.clip((speed - lo) / (k - lo), 0.0, 1.0) if k > lo else (speed >= k).astype(float)
            down = np.clip((hi - speed) / (hi - k), 0.0, 1.0) if hi > k else (speed <= k).astype(float)
            cols.append(np.where(side, np.minimum(up, down), 0.0))
    return np.column_stack(cols)


@dataclass(frozen=True)
class SensorDelay(Effect):
    """The logged motion lags the logged current by ``tau``: phi (i(t) - i(t - h - tau)), h
    the held current's half sample (``held_force``), the current read by linear interpolation
    between samples.

    A negative ``tau`` is the current logged ``-tau`` late instead.

    Parameters
    ----------
    tau : float
        The delay of the logged x, v behind the current (s), |tau| <= ``MAX_DELAY``.
    nominal_force_constant : float
        The force constant phi (N/A), > 0; held fixed by the fit.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals, SensorDelay
    >>> sig = Signals(preset("paper3"), v=np.full(5, 0.5), i=np.array([0, 1, 2, 3, 4.0]),
    ...               sample_time=0.001)
    >>> SensorDelay(tau=0.0015, nominal_force_constant=2.0).force(sig).tolist()  # 2 N/A x 1 A/ms x (1.5 + 0.5) ms
    [0.0, 2.0, 4.0, 4.0, 4.0]
    """

    tau: float
    nominal_force_constant: float
    name: ClassVar[str] = "sensor_delay"
    positive: ClassVar[Tuple[str, ...]] = ("nominal_force_constant",)
    fixed: ClassVar[Tuple[str, ...]] = ("nominal_force_constant",)
    via_timing: ClassVar[bool] = True

    @property
    def input_delay(self):
        return self.tau

    def for_log(self, mass, force_constant, t_start):
        """phi is the axis' force constant as given now."""
        return replace(self, nominal_force_constant=float(force_constant))

    def force(self, sig):
        return self.held_force(np.asarray(sig.i, dtype=float), self.nominal_force_constant,
                               self.tau / sig.sample_time)

    @staticmethod
    def held_force(i: np.ndarray, force_constant: float, samples: float) -> np.ndarray:
        """phi (i(t) - i(t - h - tau)), h half a sample: the current is held over each sample,
        so the central-difference acceleration of a log answers to i(t - h) even without a
        delay, and a delay shifts that reading by tau (``samples``) more. At tau = 0 the force
        is that half sample's alone, which a simulation driven by the held current needs not
        replay."""
        return force_constant * (i - shifted(i, -HOLD - samples))

    @classmethod
    def fit(cls, problem, rows):
        """tau on a grid of whole samples within ``SEARCH_SAMPLES``, refined between the best
        one's neighbours (the force has no free gain), after setting aside from the residual
        and the force alike functions of the speed per direction (``_speed_basis``) and the
        acceleration: a delay is fitted to what neither a friction curve's error nor a mass
        error explains (shifted by many samples, the current of pulse-shaped accelerations
        would stand in for a mass error)."""
        sig, r = problem.signals, problem.target[rows]
        i = np.asarray(sig.i, dtype=float)
        phi = problem.force_constant
        aside_basis = np.column_stack([_speed_basis(problem.v_smooth[problem.rows[rows]]),
                                       problem.at_rows(sig.a, rows)])
        q, _ = np.linalg.qr(aside_basis)

        def aside(y):
            return y - q @ (q.T @ y)

        r = aside(r)

        def rss(samples):
            force = cls.held_force(i, phi, samples)
            return float(np.sum((r - aside(problem.at_rows(force, rows))) ** 2))

        grid = np.arange(-SEARCH_SAMPLES, SEARCH_SAMPLES + 1, dtype=float)
        return cls(tau=grid_then_refine(rss, grid) * sig.sample_time, nominal_force_constant=phi)

    def unresolved(self, sample_time):
        """A delay within half a sample either way is refused: where in each sample the drive
        reads its current and its position is not logged, and the held current's own half
        sample (``HOLD``) is that large."""
        samples = self.tau / sample_time
        if abs(samples) < HOLD:
            return (f"a delay of {samples:.2f} samples is within half a sample, which the log "
                    f"cannot resolve")
        return ""

    def limits(self):
        out = super().limits()
        out["tau"] = (-MAX_DELAY, MAX_DELAY)
        return out

    @classmethod
    def from_dict(cls, d):
        effect = super().from_dict(d)
        if not abs(effect.tau) <= MAX_DELAY:
            raise ModelError(f"effects[{cls.name}].parameters.tau must be within +-{MAX_DELAY:g} s, "
                             f"got {effect.tau:g}")
        return effect
