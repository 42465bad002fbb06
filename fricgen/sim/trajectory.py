"""Smooth reference trajectories x_d(t) with the derivatives the controller needs (section 6).

The backstepping controller uses x_d, x_d' (eq. 3) and x_d'' (eq. 7). A sum of sines in the
velocity, v_d(t) = sum_k a_k sin(w_k t), has all three in closed form and starts at rest from
x_d(0) = 0.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence, Tuple

import numpy as np


@dataclass(frozen=True)
class SineSumTrajectory:
    """x_d'(t) = sum_k a_k sin(w_k t), x_d(0) = 0: infinitely smooth, every derivative exact."""

    amplitudes: Tuple[float, ...]
    omegas: Tuple[float, ...]

    def __post_init__(self):
        a = np.asarray(self.amplitudes, dtype=float).ravel()
        w = np.asarray(self.omegas, dtype=float).ravel()
        if a.size != w.size or a.size == 0:
            raise ValueError(f"amplitudes and omegas must have one equal, non-zero length, "
                             f"got {a.size} and {w.size}")
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(w))):
            raise ValueError("amplitudes and omegas must be finite")
        if np.any(w <= 0):
            raise ValueError(f"omegas must be > 0, got {w.tolist()}")
        object.__setattr__(self, "amplitudes", tuple(a.tolist()))
        object.__setattr__(self, "omegas", tuple(w.tolist()))

    def __call__(self, t) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x_d, x_d', x_d'') at times t (any shape)."""
        t = np.asarray(t, dtype=float)
        a = np.asarray(self.amplitudes)
        w = np.asarray(self.omegas)
        phase = t[..., None] * w
        s, c = np.sin(phase), np.cos(phase)
        return (((a / w) * (1.0 - c)).sum(-1), (a * s).sum(-1), ((a * w) * c).sum(-1))


def reversing(v_low: float = 0.02, v_high: float = 0.2, period: float = 0.5,
              cycles: int = 8) -> SineSumTrajectory:
    """Back-and-forth motion whose peak speed swings between ``v_low`` and ``v_high``.

    x_d'(t) = V(t) sin(w t) with w = 2 pi / period and the envelope
    V(t) = (v_low + v_high)/2 + (v_low - v_high)/2 cos(w t / cycles): the direction reverses every
    half period; the first and last reversals of each envelope period happen at peak speed
    ~v_low (inside the Stribeck region when v_low < 3 vs_max), the middle ones at ~v_high.
    One envelope period lasts ``cycles * period`` seconds.
    """
    for name, value in (("v_low", v_low), ("v_high", v_high), ("period", period)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be > 0, got {value}")
    if int(cycles) != cycles or cycles < 2:
        raise ValueError(f"cycles must be an integer >= 2, got {cycles}")
    w = 2.0 * np.pi / period
    wo = w / cycles
    mean, swing = 0.5 * (v_low + v_high), 0.5 * (v_low - v_high)
    # V(t) sin(w t) = mean sin(w t) + swing/2 [sin((w + wo) t) + sin((w - wo) t)]
    return SineSumTrajectory((mean, 0.5 * swing, 0.5 * swing), (w, w + wo, w - wo))


def sampled(trajectory, times: Sequence[float]) -> np.ndarray:
    """The trajectory at ``times`` as an array of shape (len(times), 3): x_d, x_d', x_d''."""
    return np.stack(trajectory(np.asarray(times, dtype=float)), axis=-1)
