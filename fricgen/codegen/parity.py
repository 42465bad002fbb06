"""Numerical parity of emitted C with the Python model: the velocities probed and the figures."""
from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..model import FrictionModel
from .twin import force_f32

#: The largest deviation of the float32 C from the float64 model on [-v_sat, v_sat], relative
#: to max |F| there, that emit accepts. The default solvers keep it within 1e-5
#: (``fricgen.fit.elm.PARITY``); a network whose large output weights cancel (a standard ELM
#: solved by the pseudo-inverse, 10 neurons on the paper's benchmark) can be off by more than
#: its whole force.
FLOAT32_TOLERANCE = 1e-2


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


def float32_deviation(model: FrictionModel, activation_impl: str = "libm") -> dict:
    """Where the float32 twin (the emitted C's arithmetic) is farthest from the float64 model
    on the parity velocities within [-v_sat, v_sat]: ``deviation`` (N), ``velocity``, the two
    forces there, and ``max_force`` = max |F| on those velocities."""
    v_sat = max(c.v_sat for c in model.directions)
    v = parity_velocities(v_sat)
    v = v[np.abs(v) <= v_sat]
    exact = model.reference.force(v.astype(float))
    twin = force_f32(model, v, activation_impl).astype(float)
    k = int(np.argmax(np.abs(twin - exact)))
    return {"deviation": float(abs(twin[k] - exact[k])), "velocity": float(v[k]),
            "c_force": float(twin[k]), "model_force": float(exact[k]),
            "max_force": float(np.max(np.abs(exact)))}


def float32_problem(model: FrictionModel, activation_impl: str = "libm") -> str:
    """Why the float32 C of ``model`` cannot stand for it (deviation beyond
    ``FLOAT32_TOLERANCE`` of max |F|), or ""."""
    d = float32_deviation(model, activation_impl)
    if not d["deviation"] > FLOAT32_TOLERANCE * d["max_force"]:
        return ""
    return (f"in float32 C this model is off by {d['deviation']:.4g} N, "
            f"{d['deviation'] / d['max_force']:.3g} x its max |F| (at v = {d['velocity']:.4g} m/s: "
            f"{d['c_force']:.4g} N against {d['model_force']:.4g} N); its output weights cancel, "
            f"which float32 cannot follow (train with the default solver)")


def check_float32(model: FrictionModel, activation_impl: str = "libm") -> None:
    """``ModelError`` when the float32 C would not stand for ``model`` (``float32_problem``)."""
    why = float32_problem(model, activation_impl)
    if why:
        raise ModelError(why)
