"""The controlled axis of section 6, eq. (18): x' = v, m v' = phi i - F_friction(v) - load.

The motor current is held constant over each controller sample (zero-order hold) and the
mechanics are integrated with fine RK4 steps. Friction is discontinuous at v = 0, which RK4
cannot integrate through; each step therefore stays on one friction branch (the direction of
motion) and a step that would carry the velocity through 0 stops the axis there. At rest,
friction balances the thrust up to the breakaway force |F(0+)| (a Karnopp-style stick model):
the axis starts only when |phi i - load| exceeds it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable, Tuple

import numpy as np

from ..friction import preset


def _positive(name: str, value: float) -> float:
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be > 0, got {value}")
    return float(value)


@dataclass(frozen=True)
class LinearAxis:
    """A linear permanent-magnet motor axis, eq. (18), with thrust F_e = phi i (eq. 2 of sec. 6).

    Defaults: a 2 kg mover, force constant phi = 18 N/A (the controller assumes a nominal 20 N/A,
    i.e. phi is "not known exactly"), current limit 10 A (180 N peak thrust), and the paper's
    benchmark friction (Table 1): up to 44 N breakaway, B = 57.5 N s/m. ``load`` is a constant
    external force opposing positive thrust (a disturbance no model knows), N.
    """

    friction: Callable = field(default_factory=lambda: preset("paper3"))
    mass: float = 2.0
    phi: float = 18.0
    i_max: float = 10.0
    load: float = 0.0

    def __post_init__(self):
        _positive("mass", self.mass)
        _positive("phi", self.phi)
        _positive("i_max", self.i_max)
        if not np.isfinite(self.load):
            raise ValueError(f"load must be finite, got {self.load}")
        if not callable(self.friction):
            raise ValueError(f"friction must be callable F(v), got {type(self.friction).__name__}")

    @cached_property
    def breakaway(self) -> float:
        """|F(0+)|, the largest force friction can exert at rest."""
        return float(abs(np.asarray(self.friction(np.array([np.finfo(float).tiny])))[0]))

    def direction(self, v, thrust) -> np.ndarray:
        """The friction branch of a step: sgn(v) when moving; from rest, the direction the net
        thrust pushes if it exceeds the breakaway force, else 0 (the axis stays stuck)."""
        start = np.where(np.abs(thrust) > self.breakaway, np.sign(thrust), 0.0)
        return np.where(v != 0.0, np.sign(v), start)

    def acceleration(self, v, i, direction=None) -> np.ndarray:
        """dv/dt of eq. (18) on the friction branch ``direction`` (default: that of v).

        On a branch, friction is evaluated at velocities clamped to that direction's side of
        0, so it stays continuous (the breakaway force at 0) while an RK4 stage overshoots the
        stop; a stuck axis (direction 0) does not accelerate.
        """
        v = np.asarray(v, dtype=float)
        thrust = self.phi * np.clip(i, -self.i_max, self.i_max) - self.load
        s = self.direction(v, thrust) if direction is None else direction
        return self._acceleration(v, thrust, s)

    def _acceleration(self, v, thrust, s):
        tiny = np.finfo(float).tiny
        on_branch = np.where(s * v > 0.0, v, s * tiny)
        a = (thrust - self.friction(on_branch)) / self.mass
        return np.where(s == 0.0, 0.0, a)

    def advance(self, x, v, i, dt: float, substeps: int = 10) -> Tuple[np.ndarray, np.ndarray]:
        """Integrate eq. (18) over ``dt`` with current ``i`` held constant (zero-order hold).

        ``substeps`` RK4 steps, each on the friction branch it starts on; a step that would
        carry v through 0 stops the axis at v = 0. Arrays of states advance together.
        """
        x = np.array(x, dtype=float)
        v = np.array(v, dtype=float)
        thrust = self.phi * np.clip(np.asarray(i, dtype=float), -self.i_max, self.i_max) - self.load
        accel = self._acceleration
        h = dt / substeps
        for _ in range(substeps):
            s = self.direction(v, thrust)
            k1v = accel(v, thrust, s)
            v2 = v + 0.5 * h * k1v
            k2v = accel(v2, thrust, s)
            v3 = v + 0.5 * h * k2v
            k3v = accel(v3, thrust, s)
            v4 = v + h * k3v
            k4v = accel(v4, thrust, s)
            x = x + (h / 6.0) * (v + 2.0 * v2 + 2.0 * v3 + v4)
            v_new = v + (h / 6.0) * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
            v = np.where(s * v_new < 0.0, 0.0, v_new)   # carried through 0: the axis stops
        return x, v
