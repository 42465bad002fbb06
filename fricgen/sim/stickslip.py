"""Batch integration of m dv/dt = phi i - F_fr(v, t, s) - F_ext(x, v, t) with Karnopp stiction.

The force law is split in two: ``friction`` (sliding friction, odd in v, discontinuous at
v = 0) and ``external`` (forces that act at rest too: ripple, load). At v = 0 the axis stays
at rest while the applied force phi i - F_ext does not exceed the break-away friction
|F_fr(0+)| in its direction; a velocity that changes sign within a step is set to 0 (Karnopp).
``s`` is a friction-memory state, the speed |v| low-passed with the law's time constant
``lag_tau`` (0: no memory, s = |v|). Every quantity is an array over a batch of axes, so many
logs (or many re-started simulation segments) advance in one vectorized loop.
"""
from __future__ import annotations

from typing import Protocol

import numpy as np

#: The velocity probed for the break-away friction F_fr(0+) at rest.
V_PROBE = 1e-12


class ForceLaw(Protocol):
    mass: np.ndarray
    force_constant: np.ndarray
    lag_tau: np.ndarray

    def friction(self, v: np.ndarray, t: np.ndarray, s: np.ndarray) -> np.ndarray: ...

    def external(self, x: np.ndarray, v: np.ndarray, t: np.ndarray) -> np.ndarray: ...


class StickSlipAxis:
    """A batch of axes under one force law, advanced with explicit steps of ``dt`` seconds."""

    def __init__(self, law: ForceLaw, x0, v0, t0, s0=None, dt: float = 1e-4):
        if not dt > 0:
            raise ValueError(f"dt must be > 0, got {dt}")
        self.law = law
        self.x = np.array(x0, dtype=float)
        self.v = np.array(v0, dtype=float) + 0.0 * self.x
        self.t = np.array(t0, dtype=float) + 0.0 * self.x
        self.s = np.abs(self.v) if s0 is None else np.array(s0, dtype=float) + 0.0 * self.x
        self.dt = float(dt)
        tau = np.asarray(law.lag_tau, dtype=float) + 0.0 * self.x
        self._alpha = np.where(tau > 0, np.minimum(self.dt / np.where(tau > 0, tau, 1.0), 1.0), 1.0)

    def step(self, i) -> None:
        """One step of ``dt`` with motor current ``i`` (A), held over the step."""
        law, dt = self.law, self.dt
        x, v, t, s = self.x, self.v, self.t, self.s
        applied = law.force_constant * i - law.external(x, v, t)
        moving = v != 0.0
        probe = np.where(moving, v, np.sign(applied) * V_PROBE)
        fr = law.friction(probe, t, s)
        starts = ~moving & (np.abs(applied) > np.abs(fr))
        v_new = v + dt * (applied - fr) / law.mass
        v_new = np.where(moving | starts, v_new, 0.0)
        v_new = np.where(moving & (v_new * v < 0.0), 0.0, v_new)
        self.x = x + 0.5 * dt * (v + v_new)
        self.s = s + self._alpha * (np.abs(v_new) - s)
        self.v = v_new
        self.t = t + dt

    def advance(self, i, n_steps: int) -> None:
        """Hold current ``i`` over ``n_steps`` steps (one controller sample, zero-order hold)."""
        for _ in range(n_steps):
            self.step(i)
