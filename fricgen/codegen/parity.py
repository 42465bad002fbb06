"""Numerical parity of emitted C with the Python model: the velocities probed and the figures."""
from __future__ import annotations

import numpy as np

from ..model import FrictionModel
from .twin import force_f32


def parity_velocities(v_sat: float, n: int = 10_000) -> np.ndarray:
    """At least ``n`` float32 velocities: a dense grid over [-2 v_sat, 2 v_sat] plus the edges
    0, +-1e-7, +-v_sat, the float32 neighbours of +-v_sat, and far beyond (+-10 v_sat, +-1e3)."""
    vs = np.float32(v_sat)
    edges = [0.0, 1e-7, vs, np.nextafter(vs, np.float32(0)), np.nextafter(vs, np.float32(np.inf)),
             1.001 * vs, 10 * vs, 1e3]
    edges = np.array(edges, dtype=np.float32)
    grid = np.linspace(-2 * v_sat, 2 * v_sat, n, dtype=np.float32)
    return np.concatenate([grid, edges, -edges]).astype(np.float32)


def c_forces(lib, name: str, v) -> np.ndarray:
    fn = getattr(lib, f"{name}_force")
    return np.array([fn(float(x)) for x in np.asarray(v, dtype=np.float32)], dtype=np.float32)


def measure(model: FrictionModel, lib, name: str, v=None) -> dict:
    """Max |C - float32 twin| (N), and max |C - float64 model| relative to max |F|."""
    v = parity_velocities(max(c.v_sat for c in model.directions)) if v is None else np.asarray(v, dtype=np.float32)
    c = c_forces(lib, name, v).astype(float)
    twin = force_f32(model, v).astype(float)
    exact = model.force(v.astype(float))
    return {"n_velocities": int(v.size),
            "max_abs_c_vs_twin": float(np.max(np.abs(c - twin))),
            "n_not_bit_equal": int(np.sum(c != twin)),
            "max_rel_c_vs_model": float(np.max(np.abs(c - exact)) / np.max(np.abs(exact)))}
