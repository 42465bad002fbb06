"""The force law of a friction curve with named effects, for the axis of [C1]:

    m dv/dt = phi i - F(v) - sum_k effect_k        (F of [F1] or [F3], effects of
                                                    ``fricgen.effects``),

split as ``MotorAxis`` needs it: effects that act at rest (ripple, load) form the external
force, those simulated through the dynamics shift m and phi, those of the actuator (a
saturation) take from the motor's force phi i (``thrust``), those of the log's timing (a
sensor delay) are no force (``input_delay``: whoever drives the law shifts its current), the
contact's pre-sliding is the axis's own (``sim.bristle_axis``), and the others add to the
sliding friction. One law serves the truth axes of synthesized logs, the re-simulations of the
diagnosis and the controlled axis; ``EffectLaw.batch`` gives each axis of a batch its own
effects.
"""
from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Dict, Sequence, Tuple

import numpy as np

from .._validate import positive
from ..effects import Effect, FrictionCurve, Signals


@dataclass(frozen=True)
class _OnAxes:
    """An effect acting only on the axes of a batch where ``mask`` holds (0 elsewhere); the
    parameters of ``effect`` are arrays over the batch."""

    effect: Effect
    mask: np.ndarray

    @property
    def acts_at_rest(self) -> bool:
        return self.effect.acts_at_rest

    @property
    def via_dynamics(self) -> bool:
        return self.effect.via_dynamics

    @property
    def via_timing(self) -> bool:
        return self.effect.via_timing

    @property
    def via_current(self) -> bool:
        return self.effect.via_current

    @property
    def via_contact(self) -> bool:
        return self.effect.via_contact

    @property
    def mass_delta(self):
        return np.where(self.mask, self.effect.mass_delta, 0.0)

    @property
    def force_constant_delta(self):
        return np.where(self.mask, self.effect.force_constant_delta, 0.0)

    @property
    def lag_tau(self):
        return np.where(self.mask, self.effect.lag_tau, 0.0)

    @property
    def input_delay(self):
        return np.where(self.mask, self.effect.input_delay, 0.0)

    def force(self, sig: Signals) -> np.ndarray:
        return np.where(self.mask, self.effect.force(sig), 0.0)


def _stack(effects_per_axis: Sequence[Sequence[Effect]]) -> Tuple[_OnAxes, ...]:
    """One effect per kind (class and non-numeric parameters such as ``shape``), its
    parameters arrays over the axes; axes without it carry another axis' values, masked."""
    n = len(effects_per_axis)
    groups: Dict[tuple, Dict[int, Effect]] = {}
    for j, effects in enumerate(effects_per_axis):
        for e in effects:
            key = (type(e),) + tuple(getattr(e, f.name) for f in fields(e)
                                     if isinstance(getattr(e, f.name), str))
            members = groups.setdefault(key, {})
            if j in members:
                raise ValueError(f"axis {j} has two {e.name} effects of one kind")
            members[j] = e
    stacked = []
    for members in groups.values():
        first = next(iter(members.values()))
        params = {}
        for f in fields(first):
            value = getattr(first, f.name)
            params[f.name] = value if isinstance(value, str) else np.array(
                [getattr(members.get(j, first), f.name) for j in range(n)], dtype=float)
        stacked.append(_OnAxes(type(first)(**params), np.array([j in members for j in range(n)])))
    return tuple(stacked)


class EffectLaw:
    """A ``ForceLaw`` of ``sim.axis``: the friction curve ``friction`` (a ``FrictionModel`` or
    a ``MultisourceFriction``) plus ``effects``, the nominal ``mass`` (kg) and
    ``force_constant`` (N/A) shifted by the effects that act through them, current limit
    ``i_max`` (A). The friction memory is that of the first effect with one (frictional lag).
    ``input_delay`` (s): the sum of the timing effects' (sensor delay), by which a log's current
    must be read earlier to drive the axis; the law itself leaves them out.
    """

    def __init__(self, friction: FrictionCurve, effects: Sequence = (), *, mass: float,
                 force_constant: float, i_max: float = np.inf):
        if not callable(friction):
            raise ValueError(f"friction must be callable F(v), got {type(friction).__name__}")
        positive("mass", mass)
        positive("force_constant", force_constant)
        positive("i_max", i_max, allow_inf=True)
        self.friction, self.effects, self.i_max = friction, tuple(effects), i_max
        self.mass = mass + sum(e.mass_delta for e in self.effects)
        self.force_constant = force_constant + sum(e.force_constant_delta for e in self.effects)
        lags = [e.lag_tau for e in self.effects if np.any(np.asarray(e.lag_tau) > 0)]
        self.lag_tau = lags[0] if lags else 0.0
        self.input_delay = sum((e.input_delay for e in self.effects), 0.0)
        self._at_rest = [e for e in self.effects if e.acts_at_rest]
        self._actuator = [e for e in self.effects if e.via_current]
        self._sliding = [e for e in self.effects
                         if not (e.acts_at_rest or e.via_dynamics or e.via_timing or e.via_current
                                 or e.via_contact)]

    @classmethod
    def batch(cls, friction: FrictionCurve, effects_per_axis: Sequence[Sequence[Effect]],
              mass: float, force_constant: float, i_max: float = np.inf) -> "EffectLaw":
        """One law for a batch of axes, axis j with the effects ``effects_per_axis[j]``. Each
        axis moves as under ``EffectLaw(friction, effects_per_axis[j], ...)`` alone. Effects of
        a log's timing (a sensor delay) are refused: no batched simulation shifts its current."""
        timing = [e.name for effects in effects_per_axis for e in effects if e.via_timing]
        if timing:
            raise ValueError(f"{timing[0]} is a log's timing, not a force: a batch of axes "
                             "cannot simulate it")
        return cls(friction, _stack(effects_per_axis), mass=mass, force_constant=force_constant,
                   i_max=i_max)

    def thrust(self, i) -> np.ndarray:
        """The motor's force at current ``i``: phi i less the effects of the actuator
        (saturation)."""
        force = self.force_constant * i
        if self._actuator:
            sig = Signals(self.friction, i=np.asarray(i, dtype=float))
            for e in self._actuator:
                force = force - e.force(sig)
        return force

    def sliding_friction(self, v, t, s) -> np.ndarray:
        """F(v) plus the effects that change friction (asymmetry, extra source, lag, drift)."""
        sig = Signals(self.friction, t=t, v=v, s=s)
        return self._plus_sliding(sig.friction, sig)

    def sliding_effects(self, v, t) -> np.ndarray:
        """The forces of the effects that change friction without a memory of their own
        (asymmetry, extra source, drift): ``sliding_friction`` less F(v), for a contact whose
        own friction is integrated apart (``sim.bristle_axis``)."""
        zero = np.zeros_like(np.asarray(v, dtype=float))
        return self._plus_sliding(zero, Signals(self.friction, t=t, v=v)) if self._sliding else zero

    def _plus_sliding(self, f, sig) -> np.ndarray:
        """``f`` plus each effect that changes friction, at ``sig``, in turn."""
        for e in self._sliding:
            f = f + e.force(sig)
        return f

    def external_force(self, x, v, t) -> np.ndarray:
        """The effects that act at rest too (ripple, load)."""
        total = np.zeros_like(x)
        if self._at_rest:
            sig = Signals(self.friction, t=t, x=x, v=v)
            for e in self._at_rest:
                total = total + e.force(sig)
        return total
