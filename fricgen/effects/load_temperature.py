"""Friction that depends on the load and the temperature: the operating point of a gear or a
lubricated contact, beside the velocity.

A geared joint's friction grows with the torque it transmits, at another rate when the motor
drives the load than when the load drives the motor; a lubricant's friction falls as it warms.
On the curve of a model (F0(v) = sgn(v) g(v) + B v, g the velocity-weakening part of [F3]):

    F(v, L, T) = sgn(v) g(v) (1 + s_q min(|L|, L_max)) exp(-k_c (T~ - T_ref))
                 + B v exp(-k_v (T~ - T_ref)),

with q the quadrant: s_d where the motor drives the load (v L > 0), s_b where it is driven
(v L <= 0); L_max the largest |load| of the training data (beyond it |L| saturates, as v does
beyond v_sat); T~ the temperature clipped to the trained range. The Coulomb and Stribeck
levels grow with |L| and change with T at one rate (k_c), the viscous term at its own (k_v).
The load L is the external force on the axis (gravity, a process force) in the axis's units,
with the sign of [C1] read as f = m a + L + F + o: the drive supplies it.

A model uses the load, the temperature or both; the term it does not use is absent (not 0).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from .._validate import json_number
from ..errors import ModelError, UsageError

#: The least factor (1 + s |L|) over the trained box: a slope that would make a level vanish or
#: change sign within it is no friction (a level of 5 % of the base's, at least).
LEAST_FACTOR = 0.05
#: The largest factor (1 + s |L|) over the trained box: a geared axis loses at most about
#: twice the load it transmits (an efficiency of 1/3), against a no-load level rarely below a
#: few percent of it; a steeper slope is an intercept the data did not determine.
LARGEST_FACTOR = 50.0
#: The largest |k (T - T_ref)| over the trained range: a factor of e^8 ~ 3000 is far beyond any
#: lubricant's, and keeps the float32 C's exponentials finite.
LARGEST_EXPONENT = 8.0
#: Temperatures (deg C) a model's range may span: a lubricated axis in service.
TEMPERATURE_BOUNDS = (-60.0, 250.0)


def _pair(d: dict, key: str, where: str) -> Tuple[float, float]:
    value = d.get(key)
    if not (isinstance(value, list) and len(value) == 2):
        raise ModelError(f"{where}.{key} must be a list of two numbers [low, high]")
    low, high = (json_number({"v": x}, "v", f"{where}.{key}") for x in value)
    if not low <= high:
        raise ModelError(f"{where}.{key} must be [low, high] with low <= high, got {value}"[:200])
    return low, high


@dataclass(frozen=True)
class LoadDependence:
    """The levels' growth with |load|: slopes per unit of |load| (1/N, 1/Nm) where the drive
    drives the load (v L > 0) and where it is driven; ``largest`` the |load| it saturates at."""

    driving: float
    back_driving: float
    largest: float

    def factor(self, v: np.ndarray, load: np.ndarray) -> np.ndarray:
        """1 + s_q min(|L|, L_max) (np.fmin: a NaN load reads as L_max, as the C's fminf)."""
        slope = np.where(v * load > 0, self.driving, self.back_driving)
        return 1.0 + slope * np.fmin(np.abs(load), self.largest)

    def to_dict(self) -> dict:
        return {"driving": self.driving, "back_driving": self.back_driving, "largest": self.largest}

    @classmethod
    def from_dict(cls, d) -> "LoadDependence":
        where = "inputs.load"
        if not isinstance(d, dict):
            raise ModelError(f"{where} must be an object")
        dep = cls(*(json_number(d, k, where) for k in ("driving", "back_driving", "largest")))
        if dep.largest < 0:
            raise ModelError(f"{where}.largest must be >= 0, got {dep.largest}")
        least = 1.0 + min(dep.driving, dep.back_driving, 0.0) * dep.largest
        most = 1.0 + max(dep.driving, dep.back_driving, 0.0) * dep.largest
        if not most <= LARGEST_FACTOR:
            raise ModelError(f"{where}: a slope of {max(dep.driving, dep.back_driving):.4g} per unit of "
                             f"load makes the friction {most:.3g} x its level at |load| = "
                             f"{dep.largest:.4g} (at most {LARGEST_FACTOR:g})")
        if not least >= LEAST_FACTOR:
            raise ModelError(f"{where}: a slope of {min(dep.driving, dep.back_driving):.4g} per unit "
                             f"of load makes the friction {least:.3g} x its level at |load| = "
                             f"{dep.largest:.4g}: no friction (at least {LEAST_FACTOR})")
        return dep


@dataclass(frozen=True)
class TemperatureDependence:
    """exp(-k (T - T_ref)) for the levels (``levels``) and the viscous term (``viscous``), 1/degC,
    with T clipped to ``span`` (degC), the trained range."""

    reference: float
    levels: float
    viscous: float
    span: Tuple[float, float]

    def clipped(self, temperature: np.ndarray) -> np.ndarray:
        """T clipped to the trained span (np.fmax/np.fmin: NaN reads as the span's top, as the C)."""
        return np.fmax(self.span[0], np.fmin(temperature, self.span[1])) - self.reference

    def factors(self, temperature: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(exp(-k_c dT), exp(-k_v dT)) at dT = T~ - T_ref."""
        dt = self.clipped(temperature)
        return np.exp(-self.levels * dt), np.exp(-self.viscous * dt)

    def to_dict(self) -> dict:
        return {"reference": self.reference, "levels": self.levels, "viscous": self.viscous,
                "range": list(self.span)}

    @classmethod
    def from_dict(cls, d) -> "TemperatureDependence":
        where = "inputs.temperature"
        if not isinstance(d, dict):
            raise ModelError(f"{where} must be an object")
        span = _pair(d, "range", where)
        dep = cls(*(json_number(d, k, where) for k in ("reference", "levels", "viscous")), span)
        low, high = TEMPERATURE_BOUNDS
        if not (low <= span[0] and span[1] <= high and low <= dep.reference <= high):
            raise ModelError(f"{where}: range {list(span)} and reference {dep.reference:g} must lie in "
                             f"[{low:g}, {high:g}] degC (a temperature in K or degF?)")
        reach = max(abs(span[0] - dep.reference), abs(span[1] - dep.reference))
        for key in ("levels", "viscous"):
            if abs(getattr(dep, key)) * reach > LARGEST_EXPONENT:
                raise ModelError(f"{where}.{key} = {getattr(dep, key):.4g} /degC changes the friction "
                                 f"by more than e^{LARGEST_EXPONENT:g} over the range {list(span)}")
        return dep


@dataclass(frozen=True)
class LoadTemperature:
    """What a model's friction depends on beside v (see the module): ``load``, ``temperature``
    or both (the absent one None)."""

    load: Optional[LoadDependence] = None
    temperature: Optional[TemperatureDependence] = None

    def __post_init__(self):
        if self.load is None and self.temperature is None:
            raise ModelError("inputs must hold a load or a temperature dependence")

    @property
    def names(self) -> Tuple[str, ...]:
        """The inputs the model reads besides v, in the order of ``NAME_force_lt``."""
        return tuple(n for n in ("load", "temperature") if getattr(self, n) is not None)

    def factors(self, v, load=None, temperature=None) -> Tuple[np.ndarray, np.ndarray]:
        """(levels' factor, viscous factor) at (v, L, T), broadcast; ``UsageError`` when an
        input the model uses is missing."""
        missing = [n for n in self.names if {"load": load, "temperature": temperature}[n] is None]
        if missing:
            raise UsageError(f"the model depends on the {' and the '.join(self.names)}: give "
                             f"{' and '.join(missing)} (force(v, load=..., temperature=...))")
        v = np.asarray(v, dtype=float)
        level = np.ones(v.shape)
        viscous = np.ones(v.shape)
        if self.load is not None:
            level = level * self.load.factor(v, np.asarray(load, dtype=float))
        if self.temperature is not None:
            t_level, t_viscous = self.temperature.factors(np.asarray(temperature, dtype=float))
            level, viscous = level * t_level, viscous * t_viscous
        return level, viscous

    def to_dict(self) -> dict:
        return {n: getattr(self, n).to_dict() for n in self.names}

    @classmethod
    def from_dict(cls, d) -> "LoadTemperature":
        if not isinstance(d, dict):
            raise ModelError("inputs must be an object")
        unknown = sorted(set(d) - {"load", "temperature"})
        if unknown:
            raise ModelError(f"inputs: unknown field {unknown[0]!r} (load, temperature)"[:200])
        return cls(load=None if d.get("load") is None else LoadDependence.from_dict(d["load"]),
                   temperature=(None if d.get("temperature") is None
                                else TemperatureDependence.from_dict(d["temperature"])))
