"""The named effect of the contact itself: pre-sliding, which a static friction curve misses.

Below the breakaway the contact deflects like a spring before it slides, and at every reversal
the friction passes through zero along that spring instead of jumping: the LuGre bristles of
``effects.presliding`` on the model's own static curve. The effect's force is what they add to
the curve,

    F_LuGre(v history; sigma0, sigma1) - F(v),

driven by the log's velocity from a relaxed contact. It is no function of (v, x): named, it
becomes the model's ``presliding`` (``carried.with_effects``), which ``emit`` turns into
``NAME_step``, and the simulations run it as the axis's contact (``sim.bristle_axis``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar, Tuple

import numpy as np

from .base import Effect
from .fitting import grid_then_refine
from .presliding import Bristles, bristle_deflection, bristle_force

#: The pre-sliding distances tried (g(0) / sigma0), from this many position quanta of the log...
LEAST_DISTANCE_QUANTA = 0.5
#: ...to this share of its travel.
LARGEST_DISTANCE_TRAVEL = 0.05
#: Points of the grid over the distance's logarithm.
GRID_POINTS = 16


def _viscous(model):
    return model.viscous_force if hasattr(model, "viscous_force") else (lambda v: model.viscous * np.asarray(v))


@dataclass(frozen=True)
class Presliding(Effect):
    """The contact's pre-sliding (LuGre bristles, see the module) on the model's static curve.

    Parameters
    ----------
    stiffness : float
        sigma0, N/m (Nm/rad on a rotary axis), > 0.
    damping : float
        sigma1, N s/m, >= 0.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> from fricgen.effects.contact import Presliding
    >>> v = np.full(2000, 0.01)                 # from rest: the bristles build up, then slide
    >>> sig = Signals(preset("paper3"), v=v, sample_time=1e-4)
    >>> f = Presliding(stiffness=1e6, damping=0.0).force(sig)
    >>> bool(f[0] < -20.0), bool(abs(f[-1]) < 1e-9)
    (True, True)
    """

    stiffness: float
    damping: float = 0.0
    name: ClassVar[str] = "presliding"
    positive: ClassVar[Tuple[str, ...]] = ("stiffness",)
    non_negative: ClassVar[Tuple[str, ...]] = ("damping",)
    via_contact: ClassVar[bool] = True

    @property
    def bristles(self) -> Bristles:
        return Bristles(stiffness=self.stiffness, damping=self.damping)

    def force(self, sig):
        model = sig.model
        lugre, _ = bristle_force(model.stribeck, _viscous(model), self.bristles, sig.v, sig.sample_time)
        return lugre - model(sig.v)

    def linear(self, sig):
        _, rate = _spring_and_rate(sig, self.stiffness)
        return rate[:, None], np.array([self.damping])

    def with_coefficients(self, coef):
        return replace(self, damping=max(float(coef[0]), 0.0))

    @classmethod
    def fit(cls, problem, rows):
        """The pre-sliding distance g(0) / sigma0 on a log grid from half the log's position
        quantum to a twentieth of its travel, refined; sigma1 >= 0 by least squares at each."""
        sig = problem.signals
        r = problem.target[rows]
        static = _static_level(sig.model)
        x = sig.x[problem.rows]
        quantum = float(np.median(np.abs(np.diff(np.unique(np.round(sig.x, 12)))))) if sig.x.size > 1 else 0.0
        travel = float(np.ptp(x))
        lo = max(LEAST_DISTANCE_QUANTA * quantum, 1e-9 * max(travel, 1e-9))
        hi = max(LARGEST_DISTANCE_TRAVEL * travel, 4.0 * lo)

        def solve(stiffness):
            spring, rate = (problem.at_rows(part, rows) for part in _spring_and_rate(sig, stiffness))
            left = r - spring
            damping = max(float(rate @ left) / float(rate @ rate), 0.0) if rate @ rate > 0 else 0.0
            return damping, float(np.sum((left - damping * rate) ** 2))

        grid = np.linspace(math.log(lo), math.log(hi), GRID_POINTS)
        distance = math.exp(grid_then_refine(lambda g: solve(static / math.exp(g))[1], grid))
        stiffness = static / distance
        return cls(stiffness=float(stiffness), damping=float(solve(stiffness)[0]))


def _static_level(model) -> float:
    return max(float(model.stribeck(0.0)), float(model.stribeck(-1e-300)), 1e-300)


def deflection(sig, stiffness: float) -> np.ndarray:
    """z after each sample of bristles of ``stiffness`` on the curve of ``sig.model``, driven by
    ``sig.v`` from a relaxed contact (``presliding.bristle_deflection``)."""
    return bristle_deflection(sig.model.stribeck, stiffness, sig.v, sig.sample_time)


def _spring_and_rate(sig, stiffness):
    """sigma0 z + B v - F(v), the effect's force without the damping, and dz/dt over each
    sample, the damping's regressor: of one deflection."""
    model, z = sig.model, deflection(sig, stiffness)
    spring = stiffness * z + _viscous(model)(sig.v) - model(sig.v)
    return spring, np.diff(np.concatenate([[0.0], z])) / sig.sample_time
