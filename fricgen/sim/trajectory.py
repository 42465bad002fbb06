"""Smooth reference trajectories x_d(t) with the derivatives the controller needs (section 6).

The backstepping controller uses x_d, x_d' [C3] and x_d'' [C7]. A sum of sines in the
velocity, v_d(t) = sum_k a_k sin(w_k t), has all three in closed form and starts at rest from
x_d(0) = 0. The randomized scenarios draw theirs (``drawn_reference``): point-to-point moves
with dwells, a sine, a multisine or ramps with smoothed reversals.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence, Tuple

import numpy as np
from scipy.integrate import cumulative_trapezoid
from scipy.interpolate import CubicSpline


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


#: A tabulated reference whose spline leaves the table's range by more than this share of the
#: move is refused (a few points of a step: the spline swings far beyond them).
OVERSHOOT = 0.05


class TabulatedTrajectory:
    """A reference given as positions x at times t (a user's move): x_d(t) the cubic spline
    through them with zero velocity at both ends, shifted to start at rest from x_d(0) = 0 at
    t = 0 (the simulated axis starts there), and held at its last position after the table."""

    def __init__(self, t, x):
        t, x = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
        if t.ndim != 1 or t.size != x.size:
            raise ValueError(f"a reference needs as many t as x, got {t.size} and {x.size}")
        if t.size < 4:
            raise ValueError(f"a reference needs 4 or more rows of t and x, got {t.size}")
        bad = ~(np.isfinite(t) & np.isfinite(x))
        if bad.any():
            k = int(np.argmax(bad))
            raise ValueError(f"the reference's t and x must be finite, data row {k + 1} holds "
                             f"t = {t[k]:g}, x = {x[k]:g}")
        if not np.all(np.diff(t) > 0):
            k = int(np.argmax(np.diff(t) <= 0))
            raise ValueError(f"the reference's t must increase, it steps from {t[k]:.6g} to "
                             f"{t[k + 1]:.6g} s at rows {k + 1} and {k + 2}")
        self.duration = float(t[-1] - t[0])
        moved = x - x[0]
        self._spline = CubicSpline(t - t[0], moved, bc_type="clamped")
        dense = self._spline(np.linspace(0.0, self.duration, 20 * t.size))
        span = float(np.ptp(x)) or 1.0
        beyond = max(float(dense.max() - moved.max()), float(moved.min() - dense.min()))
        if beyond > OVERSHOOT * span:
            raise ValueError(f"the spline through the reference's {t.size} points overshoots them by "
                             f"{beyond:.3g} ({beyond / span:.0%} of the move): give the move as a "
                             "log gives it, sampled finely enough to follow its ramps")

    def __call__(self, t) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x_d, x_d', x_d'') at times t (any shape)."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        after = t >= self.duration
        spline = self._spline
        return (spline(t), np.where(after, 0.0, spline(t, 1)), np.where(after, 0.0, spline(t, 2)))


def sampled(trajectory, times: Sequence[float]) -> np.ndarray:
    """The trajectory at ``times`` as an array of shape (len(times), 3): x_d, x_d', x_d''."""
    return np.stack(trajectory(np.asarray(times, dtype=float)), axis=-1)


#: Trajectory kinds.
TRAJECTORIES = ("point_to_point", "dwell", "sine", "multisine", "ramps")


def _smoothstep(t, ramp):
    tau = np.clip(t / ramp, 0.0, 1.0)
    s = 3 * tau ** 2 - 2 * tau ** 3
    ds = np.where(tau < 1, (6 * tau - 6 * tau ** 2) / ramp, 0.0)
    return s, ds


def _velocity_profile(kind, rng, t, v_peak, a_max):
    """(v, a, description) of a trajectory kind on the grid t, before fading in."""
    if kind in ("sine", "multisine"):
        n = 1 if kind == "sine" else int(rng.integers(3, 7))
        f = np.exp(rng.uniform(math.log(0.2), math.log(2.0 if n == 1 else 5.0), n))
        amp = rng.uniform(0.3, 1.0, n)
        ph = rng.uniform(0, 2 * np.pi, n)
        w = 2 * np.pi * f
        v = np.zeros_like(t)
        a = np.zeros_like(t)
        for k in range(n):
            v += amp[k] * np.sin(w[k] * t + ph[k])
            a += amp[k] * w[k] * np.cos(w[k] * t + ph[k])
        return v, a, {"frequencies_hz": f.tolist()}
    if kind == "ramps":
        period = rng.uniform(0.5, 4.0)
        width = rng.uniform(0.05, 0.3)
        w = 2 * np.pi / period
        ph = rng.uniform(0, 2 * np.pi)
        arg = np.sin(w * t + ph) / width
        v = np.tanh(arg) / math.tanh(1.0 / width)
        a = (1.0 - np.tanh(arg) ** 2) * np.cos(w * t + ph) * w / width / math.tanh(1.0 / width)
        return v, a, {"period_s": period, "reversal_width": width}
    raise ValueError(f"unknown trajectory {kind!r}")


def _moves(rng, t, travel, v_peak, a_max, dwell_range):
    """Point-to-point moves with 1 - cos speed bumps, dwelling between them: x, v, a."""
    starts, targets, lengths = [], [], []
    clock, pos = 0.5, 0.0
    end = t[-1] + 1.0
    dwells = []
    while clock < end:
        target = rng.uniform(-travel, travel)
        if abs(target - pos) < 0.2 * travel:
            target = pos - math.copysign(0.5 * travel, pos if pos else 1.0)
        dist = abs(target - pos)
        peak = v_peak * rng.uniform(0.4, 1.0)
        length = max(2.0 * dist / peak, math.sqrt(2 * np.pi * dist / a_max))
        starts.append(clock)
        targets.append(target)
        lengths.append(length)
        dwell = rng.uniform(*dwell_range)
        dwells.append(dwell)
        clock += length + dwell
        pos = target
    starts, targets, lengths = map(np.asarray, (starts, targets, lengths))
    origin = np.concatenate([[0.0], targets[:-1]])
    dist = targets - origin
    k = np.clip(np.searchsorted(starts, t, side="right") - 1, -1, None)
    before = k < 0
    k = np.maximum(k, 0)
    tau = np.clip(t - starts[k], 0.0, lengths[k])
    moving = (t >= starts[k]) & (t - starts[k] < lengths[k]) & ~before
    ratio = dist[k] / lengths[k]
    arg = 2 * np.pi * tau / lengths[k]
    x = np.where(before, 0.0, origin[k] + ratio * (tau - lengths[k] / (2 * np.pi) * np.sin(arg)))
    v = np.where(moving, ratio * (1.0 - np.cos(arg)), 0.0)
    a = np.where(moving, ratio * 2 * np.pi / lengths[k] * np.sin(arg), 0.0)
    return x, v, a, {"moves": int(np.sum(starts < t[-1])), "mean_dwell_s": float(np.mean(dwells))}


def drawn_reference(kind, rng, t, v_peak, a_max, travel):
    """x_d, v_d, a_d on the grid t (starting at rest at 0) and a description."""
    if kind in ("point_to_point", "dwell"):
        dwell = (0.02, 0.3) if kind == "point_to_point" else (0.3, 1.5)
        x, v, a, info = _moves(rng, t, travel, v_peak, a_max, dwell)
        return x, v, a, info
    u, du, info = _velocity_profile(kind, rng, t, v_peak, a_max)
    ramp = 0.5
    s, ds = _smoothstep(t, ramp)
    v = s * u
    a = ds * u + s * du
    scale = min(v_peak / max(np.max(np.abs(v)), 1e-12), a_max / max(np.max(np.abs(a)), 1e-12))
    v, a = v * scale, a * scale
    x = cumulative_trapezoid(v, t, initial=0.0)
    if kind == "ramps":
        x = x - np.mean(x)                 # any offset: the axis starts at x_d(0) anyway
        x = x - x[0]
    return x, v, a, info
