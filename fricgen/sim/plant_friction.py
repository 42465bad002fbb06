"""The scenarios' plant friction, of a family other than [F2]'s shapes, and the model the
user holds of it: fricgen's default estimator trained on a noisy sweep of it (section 6's
scenarios, ``scenarios``)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Tuple

import numpy as np

from ..data import Sweep, prepare
from ..fit import default_estimator
from ..model import FrictionModel


@dataclass(frozen=True)
class StretchedStribeck:
    """F_p(v) = sgn(v) sum_k [fc_k + (fs_k - fc_k) g_k(|v|)] + B v with
    g_k(u) = exp(-(u / vs_k)^d_k) (``stretched``) or 1 / (1 + (u / vs_k)^d_k) (``rational``)."""

    fc: Tuple[float, ...]
    fs: Tuple[float, ...]
    vs: Tuple[float, ...]
    exponent: Tuple[float, ...]
    kind: Tuple[str, ...]
    viscous: float

    def shape(self, speed, k):
        q = (np.abs(speed) / self.vs[k]) ** self.exponent[k]
        return np.exp(-q) if self.kind[k] == "stretched" else 1.0 / (1.0 + q)

    def stribeck(self, speed) -> np.ndarray:
        speed = np.abs(np.asarray(speed, dtype=float))
        return sum(self.fc[k] + (self.fs[k] - self.fc[k]) * self.shape(speed, k)
                   for k in range(len(self.fc)))

    def __call__(self, v) -> np.ndarray:
        v = np.asarray(v, dtype=float)
        return np.sign(v) * self.stribeck(v) + self.viscous * v

    @property
    def coulomb(self) -> float:
        return float(sum(self.fc))

    def flat_speed(self, level: float = 0.01) -> float:
        """The speed beyond which every source is within ``level`` of its Coulomb value."""
        out = 0.0
        for k in range(len(self.fc)):
            d = self.exponent[k]
            q = math.log(1.0 / level) if self.kind[k] == "stretched" else 1.0 / level - 1.0
            out = max(out, self.vs[k] * q ** (1.0 / d))
        return out

    def table(self, top: float, points: int = 4000):
        """S tabulated on 0 and geometric speeds from 1e-9 top to ``top`` (for fast lookups)."""
        speed = np.concatenate([[0.0], np.geomspace(1e-9 * top, top, points)])
        return speed, self.stribeck(speed)

    def to_dict(self) -> dict:
        return {"fc": list(self.fc), "fs": list(self.fs), "vs": list(self.vs),
                "exponent": list(self.exponent), "kind": list(self.kind), "B": self.viscous}


def draw_friction(rng, mass: float, v_peak: float) -> StretchedStribeck:
    """Two or three sources, F_c = 0.05-0.4 m g, fs/fc 1.2-2.5, vs 2-20 mm/s; B such that
    B v_peak is 0.2-1.5 F_c."""
    n = int(rng.integers(2, 4))
    total = mass * 9.81 * rng.uniform(0.05, 0.4)             # F_c
    share = rng.dirichlet(np.ones(n))
    fc = total * share
    fs = fc * rng.uniform(1.2, 2.5, n)
    vs = np.exp(rng.uniform(math.log(2e-3), math.log(2e-2), n))
    kind = tuple(str(k) for k in rng.choice(["stretched", "rational"], n))
    exponent = np.where(np.array(kind) == "stretched", rng.uniform(0.8, 2.5, n),
                        rng.uniform(1.5, 2.5, n))
    viscous = total / v_peak * rng.uniform(0.2, 1.5)
    return StretchedStribeck(tuple(float(f) for f in fc), tuple(float(f) for f in fs),
                             tuple(float(f) for f in vs), tuple(float(e) for e in exponent),
                             kind, viscous=float(viscous))


@lru_cache(maxsize=64)
def user_model(friction: StretchedStribeck, v_top: float, sigma: float, seed: int) -> FrictionModel:
    """The default estimator trained on a noisy sweep of ``friction`` up to ``v_top``."""
    rng = np.random.default_rng([seed, 11])
    vs_max = friction.flat_speed(0.02) / 3.0
    v_sat = 3.0 * vs_max
    top = max(v_top, 2.0 * v_sat)
    low = np.exp(rng.uniform(math.log(v_sat * 1e-3), math.log(v_sat), 200))
    high = rng.uniform(v_sat, top, 60)
    v = np.concatenate([low, high]) * rng.choice([-1.0, 1.0], 260)
    f = friction(v) + sigma * rng.standard_normal(v.size)
    dataset = prepare(Sweep(v, f), vs_max=vs_max)
    return FrictionModel.fit(dataset, default_estimator(seed), name="user_model",
                             training={"method": "auto", "source": "scenario sweep"})


def tabulated_force(model: FrictionModel, v) -> np.ndarray:
    """The model's F(v) of [F3] with its Stribeck part interpolated from 4097 speeds in
    [0, v_sat] (beyond it the network input saturates): error ~1e-5 N, fast on long logs."""
    grid = np.linspace(0.0, model.v_sat, 4097)
    return np.sign(v) * np.interp(np.abs(v), grid, model.stribeck(grid)) + model.viscous * v


def log_uniform(rng, lo, hi):
    """A draw log-uniform in [lo, hi]."""
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))
