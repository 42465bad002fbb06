"""The fast sigmoid of eq. (8) without libm, its float32 twin, and its derived error bound.

``c_runtime/fric_fast.c`` is the specification: for z >= 0, sigma(z) = 1 / (1 + E) with
E = exp(-z) = 2^-T, T = z log2(e). The C code splits t = fl(|z| log2e) into n = floor(t) and
f = t - n (exact), evaluates 2^-f with a degree-5 polynomial P (Horner, float32), and scales by
2^-n through the float exponent; z < 0 uses sigma(z) = E / (1 + E). The constants are read
from the C file, so the twin cannot drift from it.

Error bound (``error_bound``), per term, against the exact sigmoid:
  (a) range reduction: t = T (1 + r), |r| <= rho_L + u, so E is off by a relative ln2 T |r|;
      the sigmoid moves by E / (1 + E)^2 times that (maximized over T numerically);
  (b) polynomial: P(f) = 2^-f (1 + eps_P), |eps_P| <= minimax error + Horner rounding;
      the sigmoid moves by at most E / (1 + E)^2 |eps_P| <= |eps_P| / 4;
  (c) 1 + e and the quotient: two roundings, at most 2 u sigma <= 2 u;
  (d) the clamp t <= 60: at most 2^-60.
u = 2^-24 is the unit roundoff of float32.
"""
from __future__ import annotations

import re
from functools import lru_cache
from typing import Dict

import numpy as np

f32 = np.float32
U32 = 2.0 ** -24


@lru_cache(maxsize=1)
def constants() -> Dict[str, float]:
    """The #define'd constants of c_runtime/fric_fast.c (LOG2E, T_MAX, P0..P5), as float32 values."""
    from .codegen import resource_dir

    text = (resource_dir("c_runtime") / "fric_fast.c").read_text()
    found = dict(re.findall(r"#define FRIC_FAST_(\w+) (-?[0-9.e+-]+)f", text))
    expected = {"LOG2E", "T_MAX"} | {f"P{i}" for i in range(6)}
    if set(found) != expected:
        raise RuntimeError(f"fric_fast.c defines {sorted(found)}, expected {sorted(expected)}")
    return {k: float(f32(v)) for k, v in found.items()}


def coefficients() -> np.ndarray:
    c = constants()
    return np.array([c[f"P{i}"] for i in range(6)], dtype=f32)


def exp2_poly_f32(f) -> np.ndarray:
    """P(f) ~ 2^-f on [0, 1), Horner in float32 exactly as the C code."""
    c = coefficients()
    f = np.asarray(f, dtype=f32)
    acc = np.full_like(f, c[5])
    for k in range(4, -1, -1):
        acc = c[k] + f * acc
    return acc


def sigmoid_fast_f32(z) -> np.ndarray:
    """Float32 twin of ``fric_sigmoid_fast_f32``: bit-equal to the C for every float z."""
    c = constants()
    z = np.asarray(z, dtype=f32)
    with np.errstate(invalid="ignore", over="ignore"):
        a = np.where(z < 0, -z, z)
        t = a * f32(c["LOG2E"])
        t = np.where(t < f32(c["T_MAX"]), t, f32(c["T_MAX"]))
        n = t.astype(np.int32)
        f = t - n.astype(f32)
        bits = exp2_poly_f32(f).view(np.uint32) - (n.astype(np.uint32) << np.uint32(23))
        e = bits.view(f32)
        num = np.where(z < 0, e, f32(1.0))
        return num / (f32(1.0) + e)


def aim_fast_f32(net, x) -> np.ndarray:
    """Twin of ``fric_elm_sigmoid_fast_f32``: sum_k beta_k sigma_fast(w_k x + b_k), k ascending."""
    if net.activation != "sigmoid":
        raise ValueError(f"the fast implementation covers the sigmoid only, got {net.activation!r}")
    x = np.asarray(x, dtype=f32)
    w, b, beta = (a.astype(f32) for a in (net.input_weights, net.biases, net.output_weights))
    acc = np.zeros_like(x)
    for k in range(w.size):
        acc = acc + beta[k] * sigmoid_fast_f32(w[k] * x + b[k])
    return acc


def polynomial_error(n_points: int = 1 << 20) -> float:
    """max |P(f) / 2^-f - 1| over f in [0, 1): float32 Horner against exact 2^-f, on a dense
    grid plus 2^20 random floats (the minimax error and the Horner rounding together)."""
    grid = np.linspace(0.0, 1.0, n_points, endpoint=False)
    rand = np.random.default_rng(0).uniform(0.0, 1.0, n_points)
    f = np.concatenate([grid, rand]).astype(f32)
    f = f[f < 1.0]
    exact = 2.0 ** -f.astype(np.float64)
    return float(np.max(np.abs(exp2_poly_f32(f).astype(np.float64) / exact - 1.0)))


def error_bound() -> float:
    """Derived bound on |fric_sigmoid_fast_f32(z) - sigmoid(z)| for every float z (see module doc)."""
    c = constants()
    rho_l = abs(c["LOG2E"] / np.log2(np.e) - 1.0)
    T = np.linspace(0.0, c["T_MAX"], 200_001)
    E = 2.0 ** -T
    slope = E / (1.0 + E) ** 2
    reduction = float(np.max(slope * np.log(2.0) * T)) * (rho_l + U32)
    return reduction + polynomial_error() / 4.0 + 2.0 * U32 + 2.0 ** -c["T_MAX"]


def sigmoid_exact(z) -> np.ndarray:
    """The float64 sigmoid of eq. (8), without overflow warnings."""
    z = np.asarray(z, dtype=np.float64)
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + np.exp(-z))
