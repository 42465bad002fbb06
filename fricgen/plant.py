"""The controlled axis of section 6, eq. (18): x' = v, m v' = phi i - F_friction(v).

The motor current is held constant over each controller sample (zero-order hold) and the
mechanics are integrated with fine RK4 steps. Friction is discontinuous at v = 0, which RK4
cannot integrate through; the axis therefore sticks: when the velocity changes sign within a
step it is set to 0, and at v = 0 friction balances the thrust up to the breakaway force
|F(0+)| (a Karnopp-style stick model), so a mover at rest starts only when |phi i| exceeds it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable, Tuple

import numpy as np

from .friction import preset


def _positive(name: str, value: float) -> float:
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be > 0, got {value}")
    return float(value)


@dataclass(frozen=True)
class LinearAxis:
    """A linear permanent-magnet motor axis, eq. (18), with thrust F_e = phi i (eq. 2 of sec. 6).

    Defaults: a 2 kg mover, force constant phi = 18 N/A (the controller assumes a nominal 20 N/A,
    i.e. phi is "not known exactly"), current limit 10 A (180 N peak thrust), and the paper's
    benchmark friction (Table 1): up to 44 N breakaway, B = 57.5 N s/m.
    """

    friction: Callable = field(default_factory=lambda: preset("paper3"))
    mass: float = 2.0
    phi: float = 18.0
    i_max: float = 10.0

    def __post_init__(self):
        _positive("mass", self.mass)
        _positive("phi", self.phi)
        _positive("i_max", self.i_max)
        if not callable(self.friction):
            raise ValueError(f"friction must be callable F(v), got {type(self.friction).__name__}")

    @cached_property
    def breakaway(self) -> float:
        """|F(0+)|, the largest force friction can exert at rest."""
        return float(abs(np.asarray(self.friction(np.array([np.finfo(float).tiny])))[0]))

    def acceleration(self, v, i) -> np.ndarray:
        """dv/dt of eq. (18); at v = 0 friction cancels the thrust up to the breakaway force."""
        thrust = self.phi * np.clip(i, -self.i_max, self.i_max)
        return self._acceleration(np.asarray(v, dtype=float), thrust, self._held(thrust))

    def _held(self, thrust):
        return np.clip(thrust, -self.breakaway, self.breakaway)

    def _acceleration(self, v, thrust, held):
        return (thrust - np.where(v == 0.0, held, self.friction(v))) / self.mass

    def advance(self, x, v, i, dt: float, substeps: int = 10) -> Tuple[np.ndarray, np.ndarray]:
        """Integrate eq. (18) over ``dt`` with current ``i`` held constant (zero-order hold).

        ``substeps`` RK4 steps; arrays of states advance together (one axis per element).
        """
        x = np.array(x, dtype=float)
        v = np.array(v, dtype=float)
        thrust = self.phi * np.clip(np.asarray(i, dtype=float), -self.i_max, self.i_max)
        held = self._held(thrust)
        accel = self._acceleration
        h = dt / substeps
        for _ in range(substeps):
            k1v = accel(v, thrust, held)
            v2 = v + 0.5 * h * k1v
            k2v = accel(v2, thrust, held)
            v3 = v + 0.5 * h * k2v
            k3v = accel(v3, thrust, held)
            v4 = v + h * k3v
            k4v = accel(v4, thrust, held)
            x = x + (h / 6.0) * (v + 2.0 * v2 + 2.0 * v3 + v4)
            v_new = v + (h / 6.0) * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
            v = np.where(v * v_new < 0.0, 0.0, v_new)   # a sign change within the step: stick
        return x, v
