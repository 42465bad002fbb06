"""The fast sigmoid of eq. (8) without libm, its float32 twin, and its derived error bound.

``c_runtime/fric_fast.c`` is the specification: sigma(z) = 1 / (1 + e), e = exp(-z) = 2^t,
t = fl(z * fl(-log2 e)). Adding 1.5 * 2^23 rounds t to the nearest integer n (no float-to-int
conversion), f = t - n in [-1/2, 1/2] is exact (Sterbenz), 2^f comes from a degree-5 polynomial
P (Horner, float32) and 2^n is added to its exponent field. The kernel clamps x to
[0, X_MAX]; ``check_fast_model`` makes sure every |z| = |w x + b| <= 86 then (|t| <= 125, e is a
normal float). The constants are read from the C files, so the twin cannot drift from them.

Error bound (``error_bound``), against the exact sigmoid of the same float z:
  (a) range reduction: t = T (1 + r), T = -z log2 e, |r| <= rho_L + u, so e is off by a
      relative ln2 |T| |r| and the sigmoid by e / (1 + e)^2 times that (maximized over |T| <= 125);
  (b) polynomial: P(f) = 2^f (1 + eps_P) with |eps_P| the float32 Horner's relative error
      against 2^f (measured on a dense grid of [-1/2, 1/2]); the sigmoid moves by
      e / (1 + e)^2 |eps_P| <= |eps_P| / 4 (the scaling by 2^n is exact);
  (c) 1 + e and the quotient: two roundings, at most 2 u sigma <= 2 u.
u = 2^-24 is the unit roundoff of float32.
"""
from __future__ import annotations

import re
from functools import lru_cache
from typing import Dict

import numpy as np

from .model import ModelError

f32 = np.float32
U32 = 2.0 ** -24
#: |z| the fast kernel evaluates exactly as documented (|t| <= 125).
Z_MAX = 86.0


@lru_cache(maxsize=1)
def constants() -> Dict[str, float]:
    """The #define'd float constants of c_runtime/fric_fast.{c,h} (NEG_LOG2E, ROUND, Z_MAX,
    X_MAX, P0..P5), as float32 values."""
    from .codegen import resource_dir

    rt = resource_dir("c_runtime")
    text = (rt / "fric_fast.c").read_text() + (rt / "fric_fast.h").read_text()
    found = dict(re.findall(r"#define FRIC_FAST_(\w+) (-?[0-9.e+-]+)f", text))
    expected = {"NEG_LOG2E", "ROUND", "Z_MAX", "X_MAX"} | {f"P{i}" for i in range(6)}
    if set(found) != expected:
        raise RuntimeError(f"fric_fast.c/.h define {sorted(found)}, expected {sorted(expected)}")
    return {k: float(f32(v)) for k, v in found.items()}


def coefficients() -> np.ndarray:
    c = constants()
    return np.array([c[f"P{i}"] for i in range(6)], dtype=f32)


def exp2_poly_f32(f) -> np.ndarray:
    """P(f) ~ 2^f on [-1/2, 1/2], Horner in float32 exactly as the C code."""
    c = coefficients()
    f = np.asarray(f, dtype=f32)
    acc = np.full_like(f, c[5])
    for k in range(4, -1, -1):
        acc = c[k] + f * acc
    return acc


def _sigmoid_core(z: np.ndarray) -> np.ndarray:
    c = constants()
    t = z * f32(c["NEG_LOG2E"])
    rounded = t + f32(c["ROUND"])
    f = t - (rounded - f32(c["ROUND"]))
    bits = exp2_poly_f32(f).view(np.uint32) + (rounded.view(np.uint32) << np.uint32(23))
    return f32(1.0) / (f32(1.0) + bits.view(f32))


def sigmoid_fast_f32(z) -> np.ndarray:
    """Float32 twin of ``fric_sigmoid_fast_f32``: bit-equal to the C for every float z."""
    zmax = f32(constants()["Z_MAX"])
    z = np.asarray(z, dtype=f32)
    with np.errstate(invalid="ignore"):
        clamped = np.where(z < -zmax, -zmax, np.where(z > zmax, zmax, z))
        clamped = np.where(np.isnan(z), f32(0.0), clamped)
        return np.where(np.isnan(z), z, _sigmoid_core(clamped))


def aim_fast_f32(net, x) -> np.ndarray:
    """Twin of ``fric_elm_sigmoid_fast_f32``: x clamped to [0, X_MAX], then
    sum_k beta_k sigma_fast(w_k x + b_k), k ascending."""
    if net.activation != "sigmoid":
        raise ValueError(f"the fast implementation covers the sigmoid only, got {net.activation!r}")
    x = np.asarray(x, dtype=f32)
    x_max = f32(constants()["X_MAX"])
    with np.errstate(invalid="ignore"):
        x = np.where(x > 0, np.where(x > x_max, x_max, x), f32(0.0))
    w, b, beta = (a.astype(f32) for a in (net.input_weights, net.biases, net.output_weights))
    acc = np.zeros_like(x)
    for k in range(w.size):
        acc = acc + beta[k] * _sigmoid_core(w[k] * x + b[k])
    return acc


def check_fast_model(model) -> None:
    """Refuse (ModelError) a model the fast kernel cannot evaluate as documented."""
    net = model.aim
    if net.activation != "sigmoid":
        raise ModelError(f"--activation-impl fast covers the sigmoid only, this model uses {net.activation!r}")
    x_max = constants()["X_MAX"]
    x_force = float(f32(model.scaling.k_in) * f32(model.v_sat))
    if x_force > x_max:
        raise ModelError(f"--activation-impl fast clamps the network input to {x_max}, but "
                         f"k_in * v_sat = {x_force:.6g}")
    # z = w x + b is linear in x: its extremes over [0, X_MAX] are at the two ends
    reach = float(np.max(np.maximum(np.abs(net.biases), np.abs(net.input_weights * x_max + net.biases))))
    if reach > Z_MAX * (1 - 1e-6):
        raise ModelError(f"--activation-impl fast needs |w x + b| <= {Z_MAX} for every neuron and "
                         f"x in [0, {x_max}], this model reaches {reach:.4g}")


def polynomial_error(n_points: int = 1 << 21) -> float:
    """max |P(f) / 2^f - 1| over f in [-1/2, 1/2]: float32 Horner against exact 2^f on a dense
    grid plus as many random floats (minimax error and Horner rounding together)."""
    grid = np.linspace(-0.5, 0.5, n_points)
    rand = np.random.default_rng(0).uniform(-0.5, 0.5, n_points)
    f = np.concatenate([grid, rand]).astype(f32)
    exact = 2.0 ** f.astype(np.float64)
    return float(np.max(np.abs(exp2_poly_f32(f).astype(np.float64) / exact - 1.0)))


def error_bound() -> float:
    """Derived bound on |fric_sigmoid_fast_f32(z) - sigmoid(z)| for every float z (module doc)."""
    c = constants()
    rho_l = abs(-c["NEG_LOG2E"] / np.log2(np.e) - 1.0)
    T = np.linspace(-125.0, 125.0, 500_001)
    E = 2.0 ** T
    slope = E / (1.0 + E) ** 2
    reduction = float(np.max(slope * np.log(2.0) * np.abs(T))) * (rho_l + U32)
    return reduction + polynomial_error() / 4.0 + 2.0 * U32


def sigmoid_exact(z) -> np.ndarray:
    """The float64 sigmoid of eq. (8), without overflow warnings."""
    z = np.asarray(z, dtype=np.float64)
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + np.exp(-z))
