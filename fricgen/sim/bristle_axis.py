"""The motor axis of [C1] with the bristles of a model that has pre-sliding (LuGre,
``effects.presliding``):

    x' = v,   m v' = phi i - F - F_ext(x, v, t) - F_e(v, t),   F = sigma0 z + sigma1(v) z' + B v,
    z' = v - sigma0 |v| z / g(v),

F_e the law's effects that change the friction (``EffectLaw.sliding_effects``: an asymmetry, an
extra source, a drift), added to the contact's; a frictional lag, a memory of its own, is refused.

with the deflection z kept in the friction memory s of ``AxisState``. There is no stick-slip
switch: at rest the bristles hold the axis like a spring until the applied force exceeds the
breakaway, and at a reversal the friction passes through zero along them.

Each step of h seconds holds F_ext at its start, takes z exactly (the update of
``effects.presliding``) under the step's mean velocity (v + v') / 2, and puts the spring at the
mean deflection (z + z') / 2 and the damping at the mean rate (z' - z) / h: the implicit midpoint
rule, which neither damps nor excites the contact's oscillation at any stiffness; v' solves that
linear equation. a = sigma0 |v| / g(v), sigma1(v) and B v are taken at v in a first pass and at
the mean velocity of its result in a second (second order: against a Radau reference, 0.26 %
of the peak position at 10 steps a millisecond and 0.018 % at 40, tests/test_bristle_axis.py). The steps resolve
the contact's natural frequency sqrt(sigma0 / m) with PHASE_STEP radians each (at most
MAX_SUBSTEPS a sample; the rule stays stable beyond).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Callable

import numpy as np

from ..effects.presliding import Bristles, decay_ratio, least_level
from .axis import AxisState, MotorAxis

#: The phase of the contact's natural oscillation one step may cover, rad.
PHASE_STEP = 0.25
#: The most steps one controller sample is cut into.
MAX_SUBSTEPS = 1000


@dataclass(frozen=True)
class BristleAxis(MotorAxis):
    """``MotorAxis`` whose friction is the LuGre contact of ``bristles`` on a static curve
    (``advance`` integrates it; the module says how).

    Parameters
    ----------
    law : ForceLaw
        m, phi, i_max and the external force (its sliding friction is not used).
    bristles : Bristles
        sigma0 and sigma1(v).
    level : callable
        g(v) >= 0, the velocity-weakening part of the static curve, vectorized
        (``FrictionModel.stribeck``).
    viscous : callable
        B v, vectorized (``FrictionModel.viscous_force``).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen.effects.presliding import Bristles
    >>> from fricgen.sim.axis import AxisState
    >>> from fricgen.sim.bristle_axis import BristleAxis
    >>> from fricgen.sim.effect_law import EffectLaw
    >>> from fricgen import preset
    >>> law = EffectLaw(preset("paper3"), mass=2.0, force_constant=18.0)
    >>> axis = BristleAxis(law, Bristles(1e6, 3000.0), lambda v: 10.0 + 0.0 * v, lambda v: 0.0 * v)
    >>> end = axis.advance(AxisState.of([0.0, 0.0]), i=[0.5, 1.0], dt=0.1)   # 9 N, 18 N
    >>> (end.s * 1e6).round(2).tolist()     # z in um: 9 N on the spring; g = 10 N sliding
    [9.0, 10.0]
    >>> bool(abs(end.v[0]) < 1e-9), bool(end.v[1] > 0.3)                 # held; sliding
    (True, True)
    """

    bristles: Bristles
    level: Callable
    viscous: Callable

    def __post_init__(self):
        if np.any(np.asarray(self.law.lag_tau) > 0):
            raise ValueError("a frictional lag is a friction memory of its own: the bristles are "
                             "this axis's")

    @cached_property
    def least_level(self) -> float:
        """The least g the bristle update divides by (``effects.presliding.least_level``)."""
        return least_level(lambda u: float(self.level(np.asarray(u))))

    def substeps(self, dt: float) -> int:
        """The steps one sample of ``dt`` seconds is cut into (PHASE_STEP of the contact's
        natural oscillation each, at most MAX_SUBSTEPS)."""
        omega = math.sqrt(self.bristles.stiffness / float(np.min(self.law.mass)))
        return int(min(max(math.ceil(dt * omega / PHASE_STEP), 1), MAX_SUBSTEPS))

    def advance(self, state: AxisState, i, dt: float, substeps: int = 10) -> AxisState:
        """At least ``substeps`` implicit-midpoint steps over ``dt`` (``substeps(dt)`` when more
        are needed), the current held; ``state.s`` is the deflection z (m)."""
        law, b = self.law, self.bristles
        thrust = law.thrust(self._current(i))
        n = max(int(substeps), self.substeps(dt))
        h = dt / n
        least, m = self.least_level, law.mass
        x, v, t, z = state.x, state.v, state.t, state.s
        for _ in range(n):               # frozen at the step's start: the external force
            external = law.external_force(x, v, t)
            v_new = v
            for _pass in range(2):                  # frozen at v, then at the mean velocity
                u = 0.5 * (v + v_new)
                push = thrust - external - self.viscous(u) - law.sliding_effects(u, t)
                y = h * b.stiffness * np.abs(u) / np.maximum(self.level(u), least)
                keep, gain = np.exp(-y), 0.5 * h * decay_ratio(y)   # z' = keep z + gain (v + v')
                s1 = b.damping_at(u)
                base = keep * z + gain * v
                v_new = (m * v + h * push - 0.5 * h * b.stiffness * (z + base) - s1 * (base - z)) \
                    / (m + gain * (0.5 * h * b.stiffness + s1))
            z = base + gain * v_new
            x = x + 0.5 * h * (v + v_new)
            v = v_new
            t = t + h
        return AxisState(x, v, t, z)
