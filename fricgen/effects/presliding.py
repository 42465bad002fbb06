"""Pre-sliding: the LuGre model's bristles (Canudas de Wit et al., 1995) on a static curve.

Below the breakaway the contact deflects like a spring before it slides; at every reversal the
friction passes through zero along that spring instead of jumping. With the static curve of a
model, F_ss(v) = sgn(v) g(v) + B v (g the velocity-weakening part of [F3], B its viscous
slope), the bristle deflection z and the friction are

    dz/dt = v - sigma0 |v| z / g(v),      F = sigma0 z + sigma1(v) dz/dt + B v,

with sigma0 the stiffness (N/m, Nm/rad) and sigma1(v) = sigma1 exp(-(v / v_d)^2) the
micro-damping (N s/m), which fades with speed beyond v_d (Canudas de Wit et al.'s variant; a
constant sigma1 without v_d). At constant v, F tends to F_ss(v): the static curve is kept, the
bristles only add the transient.

The update over one sample time dt holds v (zero-order hold) and is exact: with
a = sigma0 |v| / g(v) and y = a dt,

    z' = z + dt r(y) (v - a z),      r(y) = (1 - exp(-y)) / y  (r(0) = 1),

stable for any stiffness and rate (explicit Euler is unstable once y > 2, i.e. at speeds above
2 g / (sigma0 dt): 0.4 m/s for 2 N, 1e5 N/m and 10 kHz). The mean dz/dt over the sample,
(z' - z) / dt, is the damping's velocity. |z| never exceeds max g / sigma0.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Optional, Tuple

import numpy as np

from .._validate import FLOAT32_SCALE, json_number
from ..errors import ModelError

#: Below this y = a dt, r(y) is its series 1 - y/2 + y^2/6 (relative error < 1e-12 there).
SERIES_BELOW = 1e-4
#: The least g(v) the update divides by, as a share of the curve's static level g(0): a curve
#: that dips to zero slides with no bristle force (z -> 0) instead of dividing by zero.
LEAST_LEVEL = 1e-6
_FIELDS = ("stiffness", "damping")
#: The speed at which the negative curve's static level is read (g(0) is the positive curve's).
STATIC_SIDE = 1e-300


def least_level(level: Callable[[float], float]) -> float:
    """The least g the update divides by: LEAST_LEVEL of the curve's level at rest (the larger
    of its two directions'), the smallest positive float for a curve without one. The C's
    ``NAME_least_level`` is this value."""
    static = max(float(level(0.0)), float(level(-STATIC_SIDE)), 0.0)
    return LEAST_LEVEL * static if static > 0 else float(np.finfo(float).tiny)


def decay_ratio(y):
    """r(y) = (1 - exp(-y)) / y for y >= 0 (arrays or floats), 1 at y = 0."""
    if np.ndim(y) == 0:
        y = float(y)
        return 1.0 - y / 2 + y * y / 6 if y < SERIES_BELOW else -math.expm1(-y) / y
    y = np.asarray(y, dtype=float)
    small = y < SERIES_BELOW
    safe = np.where(small, 1.0, y)
    return np.where(small, 1.0 - y / 2 + y * y / 6, -np.expm1(-safe) / safe)


@dataclass(frozen=True)
class Bristles:
    """The LuGre bristles of a model: stiffness sigma0 and micro-damping sigma1 (see the module).

    Parameters
    ----------
    stiffness : float
        sigma0, N/m (Nm/rad on a rotary axis); > 0.
    damping : float
        sigma1, N s/m (Nm s/rad); >= 0 (0 where the data did not determine it).
    damping_speed : float, optional
        v_d, m/s (rad/s): the speed beyond which the damping fades; None: constant.

    Examples
    --------
    >>> from fricgen.effects.presliding import Bristles
    >>> round(Bristles(stiffness=1e5, damping=300.0).presliding_distance(2.0), 9)
    2e-05
    """

    stiffness: float
    damping: float
    damping_speed: Optional[float] = None

    def damping_at(self, v):
        """sigma1(v)."""
        if self.damping_speed is None:
            return self.damping + 0.0 * np.asarray(v, dtype=float)
        return self.damping * np.exp(-(np.asarray(v, dtype=float) / self.damping_speed) ** 2)

    def presliding_distance(self, level: float) -> float:
        """g / sigma0: how far the contact deflects before it slides at the level g."""
        return level / self.stiffness

    def to_dict(self) -> dict:
        return {"kind": "lugre", "stiffness": self.stiffness, "damping": self.damping,
                "damping_speed": self.damping_speed}

    @classmethod
    def from_dict(cls, d, where: str = "presliding") -> "Bristles":
        if not isinstance(d, dict) or d.get("kind") != "lugre" or not {"kind", *_FIELDS} <= set(d) \
                or not set(d) <= {"kind", *_FIELDS, "damping_speed"}:
            raise ModelError(f"{where} must be an object with kind 'lugre', stiffness, damping and "
                             f"damping_speed (null: constant), got {d!r}"[:200])
        values = {key: json_number(d, key, where) for key in _FIELDS}
        if d.get("damping_speed") is not None:
            values["damping_speed"] = json_number(d, "damping_speed", where, positive=True)
        for key, value in values.items():
            if not (value == 0 and key == "damping") and not FLOAT32_SCALE[0] <= value <= FLOAT32_SCALE[1]:
                raise ModelError(f"{where}.{key} must be within {FLOAT32_SCALE} (float32 C), got {value}")
        return cls(**values)


def bristle_states(v: np.ndarray, level: np.ndarray, stiffness: float, dt: float,
                   z0: float = 0.0) -> np.ndarray:
    """z after each sample of the exact update (module) driven by the velocities ``v`` held over
    ``dt``, the levels g(v) given per sample: the affine recursion z' = e z + c solved by a
    doubling scan (log2(n) vector passes, no loop over the samples)."""
    v = np.asarray(v, dtype=float)
    a = stiffness * np.abs(v) / level
    y = a * dt
    keep = np.exp(-y)                                   # e: how much of z survives the sample
    add = dt * decay_ratio(y) * v                        # c: what the sample adds
    step = 1
    while step < v.size:                                 # compose the maps pairwise (Hillis-Steele)
        add[step:] = keep[step:] * add[:-step] + add[step:]
        keep[step:] = keep[step:] * keep[:-step]
        step *= 2
    return keep * z0 + add


def bristles_of(curve) -> Optional[Bristles]:
    """The bristles of a friction curve: a ``FrictionModel``'s ``presliding``, None for a
    curve without (or any other curve)."""
    return getattr(curve, "presliding", None)


def bristle_force(level: Callable, viscous: Callable, bristles: Bristles, v: np.ndarray,
                  dt: float) -> Tuple[np.ndarray, np.ndarray]:
    """The friction along a sampled velocity history, each v held over its sample of ``dt``,
    from the contact relaxed: ``BristleStepper.step`` over ``v`` without the loop (the states by
    ``bristle_states``). Returns the force per sample and the deflection z after each sample;
    ``level`` and ``viscous`` vectorized, a non-finite v counts as 0."""
    v = np.asarray(v, dtype=float)
    v = np.where(np.isfinite(v), v, 0.0)
    z = bristle_deflection(level, bristles.stiffness, v, dt)
    dz = np.diff(np.concatenate([[0.0], z]))
    return bristles.stiffness * z + bristles.damping_at(v) * dz / dt + viscous(v), z


def bristle_deflection(level: Callable, stiffness: float, v: np.ndarray, dt: float) -> np.ndarray:
    """The deflection z after each sample of bristles of ``stiffness`` on the curve's ``level``
    (vectorized g(v), kept above ``least_level``), driven by ``v`` held over ``dt`` (a
    non-finite v counts as 0) from a relaxed contact (``bristle_states``); z depends on the
    stiffness alone, not on the damping."""
    v = np.asarray(v, dtype=float)
    v = np.where(np.isfinite(v), v, 0.0)
    g = np.maximum(level(v), least_level(lambda u: float(level(np.asarray(u)))))
    return bristle_states(v, g, stiffness, dt)


class BristleStepper:
    """The friction of a model with bristles, sample by sample at a fixed dt (``step(v)`` ->
    force, ``reset()``): the exact update of the module on the model's static curve.

    Parameters
    ----------
    level : callable
        g(v) >= 0, the velocity-weakening part of the static curve (each direction's own).
    viscous : callable
        B(v) v, the viscous force of the static curve.
    bristles : Bristles
        sigma0 and sigma1.
    dt : float
        The sample time, s.
    """

    def __init__(self, level: Callable[[float], float], viscous: Callable[[float], float],
                 bristles: Bristles, dt: float):
        if not (dt > 0 and math.isfinite(dt)):
            raise ValueError(f"the sample time dt must be a positive number of seconds, got {dt!r}")
        self._level, self._viscous, self.bristles, self.dt = level, viscous, bristles, float(dt)
        self._least = least_level(level)
        self.z = 0.0

    def reset(self, z: Optional[float] = None) -> None:
        """Start again from the deflection z (0: the contact relaxed)."""
        self.z = 0.0 if z is None else float(z)

    def step(self, v: float) -> float:
        """The friction force over the next sample, the velocity ``v`` held over it (a NaN or
        infinite v counts as 0: the contact holds its deflection)."""
        v = float(v)
        if not math.isfinite(v):
            v = 0.0
        s0, dt = self.bristles.stiffness, self.dt
        g = max(float(self._level(v)), self._least)
        a = s0 * abs(v) / g
        dz = dt * decay_ratio(a * dt) * (v - a * self.z)
        self.z += dz
        return s0 * self.z + float(self.bristles.damping_at(v)) * dz / dt + float(self._viscous(v))

    __call__ = step                  # a compensation of ``AdaptiveBackstepping``: one call a sample
