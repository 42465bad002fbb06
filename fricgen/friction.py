"""Multisource friction, eq. (1), with the Stribeck shapes of eq. (2)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Dict, Sequence, Tuple

import numpy as np


def _gauss(v, vs):
    return np.exp(-((v / vs) ** 2))


def _exponential(v, vs):
    return np.exp(-np.abs(v) / vs)


def _rational(v, vs):
    return 1.0 / (1.0 + np.abs(v) / vs)


#: The three shape functions g(v, v_s) of eq. (2), by name.
SHAPES: Dict[str, Callable[[np.ndarray, float], np.ndarray]] = {
    "gauss": _gauss,
    "exponential": _exponential,
    "rational": _rational,
}


@dataclass(frozen=True)
class FrictionSource:
    """One source of eq. (1): Coulomb f_c, Stribeck f_s, Stribeck velocity v_s, viscous B."""

    fc: float
    fs: float
    vs: float
    B: float

    def __post_init__(self):
        for name in ("fc", "fs", "vs", "B"):
            value = getattr(self, name)
            if not np.isfinite(value):
                raise ValueError(f"{name} must be finite, got {value}")
        if self.vs <= 0:
            raise ValueError(f"vs must be > 0, got {self.vs}")


@dataclass(frozen=True)
class MultisourceFriction:
    """F_F(v) = sum_k [f_ck + (f_sk - f_ck) g(v, v_sk)] sgn(v) + sum_k B_k v   (eq. 1)."""

    sources: Tuple[FrictionSource, ...]
    shape: str = "gauss"

    def __post_init__(self):
        if self.shape not in SHAPES:
            raise ValueError(f"shape must be one of {sorted(SHAPES)}, got {self.shape!r}")
        if len(self.sources) == 0:
            raise ValueError("a multisource friction needs at least one source")
        object.__setattr__(self, "sources", tuple(self.sources))

    @property
    def viscous(self) -> float:
        """The total viscous coefficient B = sum_k B_k."""
        return float(sum(s.B for s in self.sources))

    @property
    def vs_max(self) -> float:
        """The largest Stribeck velocity max_k v_sk."""
        return float(max(s.vs for s in self.sources))

    def stribeck(self, v) -> np.ndarray:
        """The velocity-weakening part sum_k [f_ck + (f_sk - f_ck) g] for |v| (no sign, no B v)."""
        v = np.abs(np.asarray(v, dtype=float))
        g = SHAPES[self.shape]
        return sum(s.fc + (s.fs - s.fc) * g(v, s.vs) for s in self.sources)

    def __call__(self, v) -> np.ndarray:
        v = np.asarray(v, dtype=float)
        return self.stribeck(v) * np.sign(v) + self.viscous * v

    def to_dict(self) -> dict:
        return {"shape": self.shape,
                "sources": [{"fc": s.fc, "fs": s.fs, "vs": s.vs, "B": s.B} for s in self.sources]}

    @classmethod
    def from_dict(cls, d: dict) -> "MultisourceFriction":
        return cls(tuple(FrictionSource(**s) for s in d["sources"]), shape=d.get("shape", "gauss"))


def multisource(fc: Sequence[float], fs: Sequence[float], vs: Sequence[float],
                B: Sequence[float], shape: str = "gauss") -> MultisourceFriction:
    """Build eq. (1) from per-source parameter columns (as Table 1 lists them)."""
    lengths = {len(fc), len(fs), len(vs), len(B)}
    if len(lengths) != 1:
        raise ValueError(f"fc, fs, vs, B must have equal lengths, got {len(fc)}, {len(fs)}, {len(vs)}, {len(B)}")
    return MultisourceFriction(tuple(FrictionSource(*p) for p in zip(fc, fs, vs, B)), shape=shape)


#: Named presets. ``paper3`` is Table 1 of the paper (3 sources, SI units).
PRESETS: Dict[str, Callable[[str], MultisourceFriction]] = {
    "paper3": lambda shape="gauss": multisource(
        fc=(4.0, 6.0, 5.0), fs=(8.0, 16.0, 20.0), vs=(0.01, 0.005, 0.02), B=(2.5, 50.0, 5.0),
        shape=shape),
}


def preset(name: str, shape: str = "gauss") -> MultisourceFriction:
    """A named friction preset, e.g. ``preset("paper3")`` = Table 1."""
    if name not in PRESETS:
        raise ValueError(f"unknown friction preset {name!r}; known: {sorted(PRESETS)}")
    return PRESETS[name](shape)
