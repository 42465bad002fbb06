"""The cogging map: a force periodic in position, as a sparse Fourier series of a fundamental
period P (a revolution, a pole pitch, a screw lead),

    C(x) = sum_{h in H} a_h sin(2 pi h x / P) + b_h cos(2 pi h x / P),

with the standard error of each coefficient. ``CoggingMap.table`` samples it at N points of
one period for the firmware's linear interpolation and measures the largest error of that
interpolation against the series (``table_error``).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

import numpy as np

from .._validate import finite_number
from ..errors import ModelError

#: Most harmonics a map holds; highest harmonic number model.json accepts.
MAX_TERMS = 64
MAX_HARMONIC = 4096
#: How far (relative) a rotary axis's period may exceed a turn (a turn typed to a few digits):
#: beyond a turn its position force repeats.
TURN_EXCESS = 1e-3
#: Sizes of the firmware table: powers of two from MIN_TABLE to MAX_TABLE points per period.
MIN_TABLE, MAX_TABLE = 64, 4096
#: Points per table interval at which ``table_error`` evaluates the series.
ERROR_GRID = 32


@dataclass(frozen=True)
class CoggingMap:
    """A sparse Fourier series in position (see the module docstring).

    Parameters
    ----------
    period : float
        P, the fundamental period (m, or rad for a rotary axis), > 0.
    harmonics : tuple of int
        The harmonic numbers h (distinct, >= 1).
    sine, cosine : tuple of float
        a_h and b_h (N, or Nm).
    sine_se, cosine_se : tuple of float
        Their standard errors.

    Examples
    --------
    >>> import numpy as np
    >>> m = CoggingMap(period=2 * np.pi, harmonics=(1, 24), sine=(0.5, 0.1), cosine=(0.0, 0.0),
    ...                sine_se=(0.01, 0.01), cosine_se=(0.01, 0.01))
    >>> float(m.force(np.pi / 2).round(6)), m.amplitude.round(3).tolist()
    (0.5, [0.5, 0.1])
    """

    period: float
    harmonics: Tuple[int, ...]
    sine: Tuple[float, ...]
    cosine: Tuple[float, ...]
    sine_se: Tuple[float, ...]
    cosine_se: Tuple[float, ...]

    @property
    def wavenumber(self) -> float:
        """k = 2 pi / P."""
        return 2 * np.pi / self.period

    @property
    def amplitude(self) -> np.ndarray:
        """|c_h| = sqrt(a_h^2 + b_h^2) of each harmonic."""
        return np.hypot(self.sine, self.cosine)

    @property
    def amplitude_se(self) -> np.ndarray:
        """The standard error of each amplitude (first order)."""
        amp = np.maximum(self.amplitude, 1e-300)
        a, b = np.asarray(self.sine), np.asarray(self.cosine)
        return np.sqrt((a * np.asarray(self.sine_se)) ** 2 + (b * np.asarray(self.cosine_se)) ** 2) / amp

    @property
    def rms(self) -> float:
        """The map's root mean square over a period: sqrt(sum |c_h|^2 / 2)."""
        return float(np.sqrt(np.sum(self.amplitude ** 2) / 2))

    def force(self, x) -> np.ndarray:
        """C(x) at positions ``x`` (array in, array out; any x: the series is periodic)."""
        x = np.asarray(x, dtype=float)
        arg = self.wavenumber * x[..., None] * np.asarray(self.harmonics, dtype=float)
        return np.sin(arg) @ np.asarray(self.sine) + np.cos(arg) @ np.asarray(self.cosine)

    def table(self, points: int) -> np.ndarray:
        """C at ``points`` equally spaced positions of one period, from x = 0."""
        return self.force(np.arange(points) * self.period / points)

    def table_error(self, points: int) -> float:
        """The largest |interpolated table - C| over a period, evaluated at ERROR_GRID points of
        each interval plus the bound (dx^2 / 8) max|C''| of what lies between them."""
        values = self.table(points)
        u = np.arange(points * ERROR_GRID) / ERROR_GRID
        k = np.floor(u).astype(int)
        frac = u - k
        interpolated = values[k] + frac * (values[(k + 1) % points] - values[k])
        exact = self.force(u * self.period / points)
        curvature = float(np.sum(self.amplitude * (self.wavenumber * np.asarray(self.harmonics)) ** 2))
        between = (self.period / points / ERROR_GRID) ** 2 / 8 * 2 * curvature
        return float(np.max(np.abs(interpolated - exact))) + between

    def table_size(self, tolerance: float) -> Tuple[int, float]:
        """The fewest points (a power of two, MIN_TABLE to MAX_TABLE) whose interpolation error
        (``table_error``) is within ``tolerance``, MAX_TABLE if none is; and that error."""
        points = MIN_TABLE
        error = self.table_error(points)
        while points < MAX_TABLE and error > tolerance:
            points *= 2
            error = self.table_error(points)
        return points, error

    def to_dict(self) -> dict:
        return {"period": self.period, "harmonics": list(self.harmonics),
                "sine": list(self.sine), "cosine": list(self.cosine),
                "sine_se": list(self.sine_se), "cosine_se": list(self.cosine_se)}

    @classmethod
    def from_dict(cls, d, where: str = "cogging") -> "CoggingMap":
        """The map of a model.json's ``cogging`` object, validated (one line names a problem)."""
        if not isinstance(d, dict):
            raise ModelError(f"{where} must be an object")
        period = d.get("period")
        if not finite_number(period) or period <= 0:
            raise ModelError(f"{where}.period must be a finite number > 0, got {period!r}"[:200])
        harmonics = d.get("harmonics")
        if (not isinstance(harmonics, list) or not 1 <= len(harmonics) <= MAX_TERMS
                or not all(isinstance(h, int) and not isinstance(h, bool) and 1 <= h <= MAX_HARMONIC
                           for h in harmonics) or len(set(harmonics)) != len(harmonics)):
            raise ModelError(f"{where}.harmonics must list 1 to {MAX_TERMS} distinct integers from 1 to "
                             f"{MAX_HARMONIC}, got {harmonics!r}"[:200])
        lists = {}
        for key in ("sine", "cosine", "sine_se", "cosine_se"):
            value = d.get(key)
            if (not isinstance(value, list) or len(value) != len(harmonics)
                    or not all(finite_number(c) for c in value)):
                raise ModelError(f"{where}.{key} must list {len(harmonics)} finite numbers, got {value!r}"[:200])
            lists[key] = tuple(float(c) for c in value)
        if any(s < 0 for key in ("sine_se", "cosine_se") for s in lists[key]):
            raise ModelError(f"{where}: a standard error must be >= 0")
        return cls(period=float(period), harmonics=tuple(harmonics), **lists)


def check_rotary_period(period: float, where: str, error=ModelError) -> None:
    """``error`` for a rotary axis's period longer than a turn (TURN_EXCESS)."""
    if period > 2 * np.pi * (1 + TURN_EXCESS):
        raise error(f"{where} {period:.6g} rad is longer than a turn (6.28319 rad), after which a "
                    "rotary axis's position force repeats: give a turn or a part of one")
