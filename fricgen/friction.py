"""Multisource friction, [F1], with the Stribeck shapes of [F2]."""
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


#: The three shape functions g(v, v_s) of [F2], by name.
SHAPES: Dict[str, Callable[[np.ndarray, float], np.ndarray]] = {
    "gauss": _gauss,
    "exponential": _exponential,
    "rational": _rational,
}


@dataclass(frozen=True)
class FrictionSource:
    """One source k of [F1].

    Parameters
    ----------
    fc : float
        Coulomb friction f_ck (N).
    fs : float
        Stribeck (static) friction f_sk (N).
    vs : float
        Stribeck velocity v_sk (m/s), > 0.
    B : float
        Viscous coefficient B_k (N s/m).

    Examples
    --------
    >>> from fricgen.friction import FrictionSource
    >>> FrictionSource(fc=4.0, fs=8.0, vs=0.01, B=2.5).vs
    0.01
    """

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
    r"""Multisource Stribeck friction, [F1], with the shape functions g of [F2].

    Parameters
    ----------
    sources : sequence of FrictionSource
        The S sources (at least one).
    shape : {"gauss", "exponential", "rational"}
        g(v, v_s) of [F2]: exp(-(v/v_s)^2), exp(-|v|/v_s) or 1/(1 + |v|/v_s).

    Notes
    -----
    Calling the object evaluates [F1], the friction force in N at velocities v in m/s:

    .. math::

        F_F(v) = \sum_{k=1}^S [f_{ck} + (f_{sk} - f_{ck}) g(v, v_{sk})] \operatorname{sgn}(v)
                 + \sum_{k=1}^S B_k v

    Examples
    --------
    >>> import fricgen
    >>> friction = fricgen.preset("paper3")          # Table 1
    >>> len(friction.sources), round(friction.viscous, 1), friction.vs_max
    (3, 57.5, 0.02)
    >>> round(float(friction(0.0)), 1), round(float(friction(-1e-9)), 1)   # f_s sum at rest
    (0.0, -44.0)
    """

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
    """[F1] from per-source parameter columns, as Table 1 lists them.

    Parameters
    ----------
    fc, fs : sequence of float
        Coulomb and Stribeck friction of each source (N).
    vs : sequence of float
        Stribeck velocity of each source (m/s).
    B : sequence of float
        Viscous coefficient of each source (N s/m).
    shape : str
        The g of [F2]: "gauss", "exponential" or "rational".

    Returns
    -------
    MultisourceFriction

    Examples
    --------
    >>> from fricgen.friction import multisource
    >>> f = multisource(fc=[4.0], fs=[8.0], vs=[0.01], B=[2.0])
    >>> round(float(f(1.0)), 3)      # f_c + B v far above v_s
    6.0
    """
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
    """A named friction preset: ``"paper3"`` is the paper's Table 1 (3 sources, SI units).

    Parameters
    ----------
    name : str
        The preset's name.
    shape : str
        The g of [F2] to give it ("gauss", "exponential" or "rational").

    Returns
    -------
    MultisourceFriction

    Examples
    --------
    >>> from fricgen import preset
    >>> [s.fs for s in preset("paper3", shape="rational").sources]
    [8.0, 16.0, 20.0]
    """
    if name not in PRESETS:
        raise ValueError(f"unknown friction preset {name!r}; known: {sorted(PRESETS)}")
    return PRESETS[name](shape)
