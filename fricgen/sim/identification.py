"""Identification runs: an axis of [C1] under a velocity loop sweeps its speeds slowly in
both directions, recorded as an instrument would (for training from motion logs).

The truth friction may differ between the directions (``DirectionalFriction``: one [F1] per
direction). The velocity reference is v_max s|s| for a triangle wave s in [-1, 1], so low
speeds, where the Stribeck effect lives, get as much time as high ones. A PI velocity loop with
acceleration feedforward drives the current; the axis moves by Karnopp stick-slip steps.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict

import numpy as np

from ..friction import MultisourceFriction
from .axis import AxisState, MotorAxis
from .effect_law import EffectLaw


@dataclass(frozen=True)
class DirectionalFriction:
    """Friction with one [F1] per direction: ``positive`` for v >= 0, ``negative`` for v < 0."""

    positive: MultisourceFriction
    negative: MultisourceFriction

    def magnitude(self, speed, sign: int) -> np.ndarray:
        """|F| at the speed |v| moving in direction ``sign``."""
        curve = self.positive if sign > 0 else self.negative
        speed = np.abs(np.asarray(speed, dtype=float))
        return curve.stribeck(speed) + curve.viscous * speed

    def stribeck(self, v) -> np.ndarray:
        """The velocity-weakening part of the curve of v's direction (F(0+) at v = 0)."""
        v = np.asarray(v, dtype=float)
        return np.where(v < 0, self.negative.stribeck(v), self.positive.stribeck(v))

    def __call__(self, v) -> np.ndarray:
        v = np.asarray(v, dtype=float)
        return np.where(v < 0, self.negative(v), self.positive(v))


@dataclass(frozen=True)
class SweepRun:
    """An identification run: axis, reference, loop and the true-time sampling."""

    mass: float = 4.0              # kg
    force_constant: float = 20.0   # N/A
    i_max: float = 10.0            # A
    v_max: float = 0.2             # m/s, peak of the reference
    period: float = 8.0            # s, of one cycle -v_max .. v_max .. -v_max
    duration: float = 16.0         # s
    rate: float = 6000.0           # Hz, of the loop and of the true signals
    substeps: int = 1              # Karnopp steps per loop sample
    bandwidth: float = 100.0       # Hz, of the velocity loop (stiff enough to hold low speeds)


def velocity_reference(t: np.ndarray, run: SweepRun):
    """v_ref = v_max s|s| for the triangle wave s of ``run.period`` (starting at s = 0, rising),
    and its derivative."""
    phase = (np.asarray(t, dtype=float) / run.period + 0.25) % 1.0
    s = 1.0 - 4.0 * np.abs(phase - 0.5)
    ds = np.where(phase < 0.5, 4.0, -4.0) / run.period
    return run.v_max * s * np.abs(s), 2.0 * run.v_max * np.abs(s) * ds


def simulate_sweep_run(friction, run: SweepRun = SweepRun()) -> Dict[str, np.ndarray]:
    """The true signals of a run at ``run.rate``: t, x, v, a (mean acceleration over the
    sample), i (A) and the drive force phi i (N), with friction ``friction`` (any F(v))."""
    n = int(round(run.duration * run.rate)) + 1
    ts = 1.0 / run.rate
    t = np.arange(n) * ts
    v_ref, a_ref = velocity_reference(t, run)
    axis = MotorAxis(EffectLaw(friction, mass=run.mass, force_constant=run.force_constant,
                               i_max=run.i_max))
    kv = 2 * np.pi * run.bandwidth
    ki = kv * kv / 4.0
    state = AxisState.of(np.zeros(1))
    out = np.zeros((4, n))
    integral = 0.0
    for k in range(n):
        error = v_ref[k] - state.v[0]
        integral += error * ts
        i = run.mass * (a_ref[k] + kv * error + ki * integral) / run.force_constant
        i = float(np.clip(i, -run.i_max, run.i_max))
        out[:3, k] = state.x[0], state.v[0], i
        new = axis.karnopp(state, i, ts, run.substeps)
        out[3, k] = (new.v[0] - state.v[0]) / ts
        state = new
    return {"t": t, "x": out[0], "v": out[1], "a": out[3], "i": out[2],
            "force": run.force_constant * out[2]}
