"""The named effect of the log's timing rather than of the axis: the logged motion and the
logged current are not simultaneous (a measurement filter, a bus latency), one small class of
the ``Effect`` contract (``base``).

With the motion x, v, a logged ``tau`` late, the force of [C1] at the logged signals is that of
``tau`` later: phi i(t) = m a(t + tau) + F(v(t + tau)), so the residual holds

    g(t + tau) - g(t),   g = m a + F(v)   (about tau dg/dt to first order),

a delay acting on the inertial and the friction term alike, unlike a mass error (m a only) or
friction memory (the velocity-weakening part only, and lagging: about -tau_lag dS/dt). It is
no force of the axis: a simulation replays it by driving the axis with the current ``tau``
earlier (``input_delay``).
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


@dataclass(frozen=True)
class SensorDelay(Effect):
    """The logged motion lags the logged current by ``tau``: g(t + tau) - g(t), g = m a + F(v)
    of [C1] at the logged signals, read by linear interpolation between samples.

    A negative ``tau`` is the current logged ``-tau`` late instead (phi i(t) = g(t + tau) holds
    for both).

    Parameters
    ----------
    tau : float
        The delay of the logged x, v behind the current (s), |tau| <= ``MAX_DELAY``.
    nominal_mass : float
        The mass m of g (kg), > 0; held fixed by the fit.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals, SensorDelay
    >>> t = np.arange(5) * 0.001
    >>> sig = Signals(preset("paper3"), t=t, v=np.full(5, 0.5), a=np.array([0, 1, 2, 3, 4.0]),
    ...               sample_time=0.001)
    >>> SensorDelay(tau=0.0015, nominal_mass=2.0).force(sig).tolist()   # 2 kg x 1.5 m/s^2 ahead
    [3.0, 3.0, 3.0, 2.0, 0.0]
    """

    tau: float
    nominal_mass: float
    name: ClassVar[str] = "sensor_delay"
    positive: ClassVar[Tuple[str, ...]] = ("nominal_mass",)
    fixed: ClassVar[Tuple[str, ...]] = ("nominal_mass",)
    via_timing: ClassVar[bool] = True

    @property
    def input_delay(self):
        return self.tau

    def for_log(self, mass, force_constant, t_start):
        """g is that of the axis' mass as given now."""
        return replace(self, nominal_mass=float(mass))

    @staticmethod
    def model_force(sig, mass: float) -> np.ndarray:
        """g = m a + F(v) at the logged signals."""
        return mass * np.asarray(sig.a, dtype=float) + sig.friction

    def force(self, sig):
        g = self.model_force(sig, self.nominal_mass)
        return shifted(g, self.tau / sig.sample_time) - g

    @classmethod
    def fit(cls, problem, rows):
        """tau on a grid of whole samples within ``SEARCH_SAMPLES``, refined between the best
        one's neighbours (the force has no free gain)."""
        sig, r = problem.signals, problem.target[rows]
        g = cls.model_force(sig, problem.mass)

        def rss(samples):
            return float(np.sum((r - problem.at_rows(shifted(g, samples) - g, rows)) ** 2))

        grid = np.arange(-SEARCH_SAMPLES, SEARCH_SAMPLES + 1, dtype=float)
        return cls(tau=grid_then_refine(rss, grid) * sig.sample_time, nominal_mass=problem.mass)

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

