"""The motor axis of [C1] under a pluggable force law, and its integrators:

    x' = v,   m v' = phi i - F_fr(v, t, s) - F_ext(x, v, t),   tau s' = |v| - s,

with the current limited to |i| <= i_max and held over each call (zero-order hold). The force
law supplies m, phi, i_max, the sliding friction F_fr (odd in v, discontinuous at v = 0), the
external force F_ext (it acts at rest too: ripple, load) and the time constant tau of the
friction memory s, a low-passed speed (tau = 0: no memory, s = |v|). At rest, friction
balances the applied force phi i - F_ext up to the breakaway force |F_fr(0+)| in its direction
(Karnopp): the axis starts only when the applied force exceeds it.

Three integrators advance a batch of axes (every quantity an array over the batch):
``rk4`` (RK4 steps on one friction branch, for the controlled axis), ``karnopp`` (explicit
stick-slip steps, for truth logs and re-simulations) and ``euler_f32`` (semi-implicit Euler in
float32, the twin of examples/firmware/fw_plant.c).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Protocol

import numpy as np

#: The speed at which ``rk4`` probes friction at rest: F_fr(0+).
RK4_PROBE = float(np.finfo(float).tiny)
#: The speed at which ``karnopp`` probes friction at rest.
KARNOPP_PROBE = 1e-12


class ForceLaw(Protocol):
    """What the axis needs of its forces (arrays over a batch of axes, or scalars)."""

    mass: float
    force_constant: float
    i_max: float
    lag_tau: float

    def thrust(self, i) -> np.ndarray:
        """The motor's force at the current ``i`` (phi i of an ideal actuator)."""

    def sliding_friction(self, v, t, s) -> np.ndarray:
        """F_fr: odd in v, discontinuous at v = 0; ``s`` is the friction memory."""

    def external_force(self, x, v, t) -> np.ndarray:
        """F_ext: forces that act at rest too (positive: opposes positive motion)."""


@dataclass(frozen=True)
class AxisState:
    """Position x (m), velocity v (m/s), time t (s) and friction memory s (m/s) of a batch."""

    x: np.ndarray
    v: np.ndarray
    t: np.ndarray
    s: np.ndarray

    @classmethod
    def of(cls, x, v=0.0, t=0.0, s=None) -> "AxisState":
        """A batch shaped like ``x`` (v, t, s broadcast to it; s defaults to |v|)."""
        x = np.array(x, dtype=float)
        v = np.array(v, dtype=float) + 0.0 * x
        t = np.array(t, dtype=float) + 0.0 * x
        s = np.abs(v) if s is None else np.array(s, dtype=float) + 0.0 * x
        return cls(x, v, t, s)


def _memory_tau(law) -> Optional[np.ndarray]:
    """The law's memory time constants, or None when no axis has memory."""
    tau = np.asarray(law.lag_tau, dtype=float)
    return tau if np.any(tau > 0) else None


def _memory_gain(tau: Optional[np.ndarray], h: float):
    """The gain min(h / tau, 1) of an explicit memory step of h seconds."""
    if tau is None:
        return 1.0
    return np.where(tau > 0, np.minimum(h / np.where(tau > 0, tau, 1.0), 1.0), 1.0)


def _memory_step(s, speed, tau: Optional[np.ndarray], gain):
    """s after an explicit step toward ``speed``; s = speed where there is no memory."""
    return speed if tau is None else np.where(tau > 0, s + gain * (speed - s), speed)


@dataclass(frozen=True)
class MotorAxis:
    """The axis of [C1], under ``law``: m v' = phi i - F_fr(v, t, s) - F_ext(x, v, t),
    stuck at rest until the applied force exceeds the breakaway force (Karnopp).

    Parameters
    ----------
    law : ForceLaw
        m, phi, i_max, lag_tau and the forces, arrays over a batch of axes or scalars (e.g.
        ``sim.effect_law.EffectLaw``: a friction curve of [F1] or [F3] and named effects).

    Examples
    --------
    >>> from fricgen import preset
    >>> from fricgen.sim import MotorAxis
    >>> from fricgen.sim.axis import AxisState
    >>> from fricgen.sim.effect_law import EffectLaw
    >>> axis = MotorAxis(EffectLaw(preset("paper3"), mass=2.0, force_constant=18.0))
    >>> float(axis.breakaway())                 # |F(0+)| of Table 1's friction (N)
    44.0
    >>> end = axis.karnopp(AxisState.of([0.0, 0.0]), i=[1.0, 4.0], dt=0.01, substeps=10)
    >>> (end.v > 0).tolist()                    # 18 N and 72 N against 44 N breakaway
    [False, True]
    """

    law: ForceLaw

    def breakaway(self, direction: float = 1.0, t=0.0, s=0.0) -> np.ndarray:
        """|F_fr(0+)| in ``direction``: the largest force friction exerts at rest."""
        return np.abs(self.law.sliding_friction(np.asarray(direction * RK4_PROBE), t, s))

    def _current(self, i):
        return np.clip(np.asarray(i, dtype=float), -self.law.i_max, self.law.i_max)

    def _branch(self, v, applied, t, s, probe):
        """The friction branch of a step and F_fr at its start: sgn(v) while moving; from rest,
        the direction of the applied force if it exceeds the breakaway force (friction probed
        at +-``probe`` in that direction), else 0 (stuck)."""
        moving = v != 0.0
        f = self.law.sliding_friction(np.where(moving, v, np.sign(applied) * probe), t, s)
        starts = ~moving & (np.abs(applied) > np.abs(f))
        direction = np.where(moving, np.sign(v), np.where(starts, np.sign(applied), 0.0))
        return direction, moving, starts, f

    def rk4(self, state: AxisState, i, dt: float, substeps: int = 10) -> AxisState:
        """``substeps`` RK4 steps over ``dt``, each on the friction branch it starts on.

        RK4 cannot integrate through the discontinuity of friction at v = 0: within a step,
        friction is evaluated at velocities clamped to the branch's side of 0 (the breakaway
        force at 0), a stuck axis does not accelerate, and a step that would carry v through
        0 stops the axis there. The memory s follows the same RK4 stages.
        """
        law = self.law
        thrust = law.thrust(self._current(i))
        tau = _memory_tau(law)
        h = dt / substeps
        x, v, t, s = state.x, state.v, state.t, state.s

        def accel(x_k, v_k, t_k, s_k, d):
            applied = thrust - law.external_force(x_k, v_k, t_k)
            on_branch = np.where(d * v_k > 0.0, v_k, d * RK4_PROBE)
            a = (applied - law.sliding_friction(on_branch, t_k, s_k)) / law.mass
            return np.where(d == 0.0, 0.0, a)

        def memory_rate(v_k, s_k):
            if tau is None:
                return 0.0
            return np.where(tau > 0, (np.abs(v_k) - s_k) / np.where(tau > 0, tau, 1.0), 0.0)

        for _ in range(substeps):
            applied = thrust - law.external_force(x, v, t)
            d, _, _, f = self._branch(v, applied, t, s, RK4_PROBE)
            k1, r1 = np.where(d == 0.0, 0.0, (applied - f) / law.mass), memory_rate(v, s)
            v2, s2 = v + 0.5 * h * k1, s + 0.5 * h * r1
            k2, r2 = accel(x + 0.5 * h * v, v2, t + 0.5 * h, s2, d), memory_rate(v2, s2)
            v3, s3 = v + 0.5 * h * k2, s + 0.5 * h * r2
            k3, r3 = accel(x + 0.5 * h * v2, v3, t + 0.5 * h, s3, d), memory_rate(v3, s3)
            v4, s4 = v + h * k3, s + h * r3
            k4, r4 = accel(x + h * v3, v4, t + h, s4, d), memory_rate(v4, s4)
            x = x + (h / 6.0) * (v + 2.0 * v2 + 2.0 * v3 + v4)
            v_new = v + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
            s_new = s + (h / 6.0) * (r1 + 2.0 * r2 + 2.0 * r3 + r4)
            v = np.where(d * v_new < 0.0, 0.0, v_new)   # carried through 0: the axis stops
            s = np.abs(v) if tau is None else np.where(tau > 0, s_new, np.abs(v))
            t = t + h
        return AxisState(x, v, t, s)

    def advance(self, state: AxisState, i, dt: float, substeps: int = 10) -> AxisState:
        """The controlled axis' step over ``dt`` (``control.loop.simulate``): ``rk4``."""
        return self.rk4(state, i, dt, substeps)

    def karnopp(self, state: AxisState, i, dt: float, substeps: int = 1) -> AxisState:
        """``substeps`` explicit stick-slip steps over ``dt`` (Karnopp).

        A moving axis takes an explicit Euler velocity step (trapezoidal position); one whose
        velocity would change sign stops at 0. An axis at rest starts only when the applied
        force exceeds the breakaway force in its direction. The memory s is low-passed with
        gain min(h / tau, 1) per step of h = dt / substeps.
        """
        law = self.law
        thrust = law.thrust(self._current(i))
        tau = _memory_tau(law)
        h = dt / substeps
        gain = _memory_gain(tau, h)
        x, v, t, s = state.x, state.v, state.t, state.s
        for _ in range(substeps):
            applied = thrust - law.external_force(x, v, t)
            _, moving, starts, f = self._branch(v, applied, t, s, KARNOPP_PROBE)
            v_new = v + h * (applied - f) / law.mass
            v_new = np.where(moving | starts, v_new, 0.0)
            v_new = np.where(moving & (v_new * v < 0.0), 0.0, v_new)
            x = x + 0.5 * h * (v + v_new)
            s = _memory_step(s, np.abs(v_new), tau, gain)
            v = v_new
            t = t + h
        return AxisState(x, v, t, s)

    def euler_f32(self, state: AxisState, i, dt: float, substeps: int) -> AxisState:
        """``substeps`` semi-implicit Euler steps over ``dt`` in float32 arithmetic (v first,
        then x with the new v), as ``fw_plant_advance`` of examples/firmware/fw_plant.c.

        For smooth (regularized) friction laws: there is no stick model. The law's forces
        are rounded to float32; a law that computes in float32, without external force,
        memory or actuator effects, reproduces the C operation for operation. The memory s is
        low-passed with gain min(h / tau, 1) per step.
        """
        f32 = np.float32
        law = self.law
        x, v, s, t = f32(state.x), f32(state.v), f32(state.s), state.t
        h = f32(dt) / f32(substeps)
        i_max = f32(law.i_max)
        current = np.clip(f32(i), -i_max, i_max)
        actuator_loss = law.force_constant * current - law.thrust(current)    # 0: ideal actuator
        thrust = f32(law.force_constant) * current - f32(actuator_loss)
        mass = f32(law.mass)
        tau = _memory_tau(law)
        gain = f32(_memory_gain(tau, h))
        for _ in range(substeps):
            applied = thrust - f32(law.external_force(x, v, t))
            a = (applied - f32(law.sliding_friction(v, t, s))) / mass
            v = v + h * a
            x = x + h * v
            s = f32(_memory_step(s, abs(v), tau, gain))
            t = t + dt / substeps
        return AxisState(x, v, t, s)
