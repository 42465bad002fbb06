"""The fast sigmoid of [F8] without libm, its float32 twin, and its derived error bound.

``c_runtime/fric_fast.c`` is the specification: sigma(z) = 1 / (1 + e), e = exp(-z) = 2^t.
Adding 1.5 * 2^23 rounds t to the nearest integer n (no float-to-int conversion), f = t - n in
[-1/2, 1/2] is exact (Sterbenz), 2^f comes from a degree-4 polynomial P (Horner, float32; the
relative minimax with P(0) = 1 of ``minimax_exp2``, coefficients rounded to float, 2.9e-6
with the Horner rounding) and 2^n is added to its
exponent field; this is exact as described for |t| <= T_MAX = 125 (e is a normal float).

- ``fric_sigmoid_fast_f32(z)`` clamps z to [-86, 86] and forms t = fl(z * fl(-log2 e)),
  then returns fl(1 / fl(1 + e)).
- The ELM kernel ``fric_elm_sigmoid_fast_f32`` takes tables pre-multiplied by -log2(e)
  (``fast_tables``: w' = -log2(e) w and b' = -log2(e) b in float64, each rounded once to float),
  so t = fl(fl(w' x) + b') costs no extra multiply, and adds fl(beta / fl(1 + e)) per neuron.
  It clamps x to [0, X_MAX]; ``check_fast_model`` makes sure every |w' x + b'| <= 125 there.

The constants are read from the C files, so the twin cannot drift from them.

Error bounds, u = 2^-24 the unit roundoff of float32:
  (a) range reduction (``fric_sigmoid_fast_f32`` only): t = T (1 + r), T = -z log2 e,
      |r| <= rho_L + u, so e is off by a relative ln2 |T| |r| and the sigmoid by
      e / (1 + e)^2 times that (maximized over |T| <= 125);
  (b) polynomial: P(f) = 2^f (1 + eps_P) with |eps_P| the float32 Horner's relative error
      against 2^f (measured on a dense grid of [-1/2, 1/2]); the sigmoid moves by
      e / (1 + e)^2 |eps_P| <= |eps_P| / 4 (the scaling by 2^n is exact);
  (c) 1 + e and the quotient: two roundings, at most 2 u sigma <= 2 u.
``error_bound`` = (a) + (b) + (c) bounds |fric_sigmoid_fast_f32(z) - sigmoid(z)| for every float
z. ``kernel_error_bound`` = (b) + (c) bounds |fl(beta / fl(1 + e)) - beta / (1 + 2^t)| / |beta|
for each kernel neuron and the float t it forms; the rounding of the tables and of t itself
belongs to the float32 evaluation of w x + b, as for the libm kernel.
"""
from __future__ import annotations

import re
from functools import lru_cache
from typing import Dict

import numpy as np

from .._io import resource_dir
from ..errors import ModelError

f32 = np.float32
U32 = 2.0 ** -24
#: |t| the fast exp2 evaluates exactly as documented (e = 2^t stays a normal float).
T_MAX = 125.0
#: |z| fric_sigmoid_fast_f32 clamps to (|t| <= 125).
Z_MAX = 86.0
#: Degree of the polynomial P ~ 2^f on [-1/2, 1/2] (FRIC_FAST_P0..P4).
DEGREE = 4
#: log2(e) correctly rounded to float64; the fast tables are multiplied by its negation.
LOG2E = 1.4426950408889634


@lru_cache(maxsize=1)
def constants() -> Dict[str, float]:
    """The #define'd float constants of c_runtime/fric_fast.{c,h} (NEG_LOG2E, ROUND, Z_MAX,
    X_MAX, P0..P4; a negative one in parentheses), as float32 values."""
    rt = resource_dir("c_runtime")
    text = (rt / "fric_fast.c").read_text() + (rt / "fric_fast.h").read_text()
    found = dict(re.findall(r"#define FRIC_FAST_(\w+) \(?(-?[0-9.e+-]+)f\)?", text))
    expected = {"NEG_LOG2E", "ROUND", "Z_MAX", "X_MAX"} | {f"P{i}" for i in range(DEGREE + 1)}
    if set(found) != expected:
        raise RuntimeError(f"fric_fast.c/.h define {sorted(found)}, expected {sorted(expected)}")
    return {k: float(f32(v)) for k, v in found.items()}


def coefficients() -> np.ndarray:
    c = constants()
    return np.array([c[f"P{i}"] for i in range(DEGREE + 1)], dtype=f32)


def exp2_poly_f32(f) -> np.ndarray:
    """P(f) ~ 2^f on [-1/2, 1/2], Horner in float32 exactly as the C code."""
    c = coefficients()
    f = np.asarray(f, dtype=f32)
    acc = np.full_like(f, c[DEGREE])
    for k in range(DEGREE - 1, -1, -1):
        acc = c[k] + f * acc
    return acc


def _exp2(t: np.ndarray) -> np.ndarray:
    """e = 2^t as ``fric_fast_exp2`` (|t| <= T_MAX)."""
    c = constants()
    rounded = t + f32(c["ROUND"])
    f = t - (rounded - f32(c["ROUND"]))
    bits = exp2_poly_f32(f).view(np.uint32) + (rounded.view(np.uint32) << np.uint32(23))
    return bits.view(f32)


def _one_plus_exp2(t: np.ndarray) -> np.ndarray:
    """fl(1 + e), e = 2^t as ``fric_fast_one_plus_exp2`` (|t| <= T_MAX)."""
    return f32(1.0) + _exp2(t)


def exp_neg_fast_f32(a) -> np.ndarray:
    """Float32 twin of ``fric_exp_neg_fast_f32``: exp(-a) = 2^fl(a fl(-log2 e)), a clamped to
    [-86, 86], NaN kept; bit-equal to the C."""
    zmax = f32(constants()["Z_MAX"])
    a = np.atleast_1d(np.asarray(a, dtype=f32))
    with np.errstate(invalid="ignore"):
        clamped = np.where(np.isnan(a), f32(0.0), np.clip(a, -zmax, zmax)).astype(f32)
        return np.where(np.isnan(a), a, _exp2(clamped * f32(constants()["NEG_LOG2E"])))


def exp_neg_error_bound() -> float:
    """Derived bound on |fric_exp_neg_fast_f32(a) - exp(-a)| for every float a >= 0: the
    polynomial's relative error, plus the rounding of t = fl(a fl(-log2 e)), which moves e by a
    relative ln2 |t| (rho_L + u) = a (rho_L + u) and e^-a by at most (rho_L + u) / e."""
    c = constants()
    rho_l = abs(-c["NEG_LOG2E"] / np.log2(np.e) - 1.0)
    return polynomial_error() + (rho_l + U32) / np.e


def _sigmoid_core(z: np.ndarray) -> np.ndarray:
    return f32(1.0) / _one_plus_exp2(z * f32(constants()["NEG_LOG2E"]))


def sigmoid_fast_f32(z) -> np.ndarray:
    """Float32 twin of ``fric_sigmoid_fast_f32``: bit-equal to the C for every float z."""
    zmax = f32(constants()["Z_MAX"])
    z = np.asarray(z, dtype=f32)
    with np.errstate(invalid="ignore"):
        clamped = np.where(z < -zmax, -zmax, np.where(z > zmax, zmax, z))
        clamped = np.where(np.isnan(z), f32(0.0), clamped)
        return np.where(np.isnan(z), z, _sigmoid_core(clamped))


def fast_tables(net):
    """The tables the fast kernel is emitted with, float32: w' = -log2(e) w, b' = -log2(e) b
    (products in float64, each rounded once to float) and beta."""
    with np.errstate(over="ignore"):
        w = (-LOG2E * np.asarray(net.input_weights, dtype=np.float64)).astype(f32)
        b = (-LOG2E * np.asarray(net.biases, dtype=np.float64)).astype(f32)
        beta = np.asarray(net.output_weights, dtype=np.float64).astype(f32)
    return w, b, beta


def aim_fast_f32(net, x) -> np.ndarray:
    """Twin of ``fric_elm_sigmoid_fast_f32`` on the emitted tables: x clamped to [0, X_MAX],
    then sum_k beta_k / (1 + 2^(w'_k x + b'_k)), k ascending."""
    if net.activation != "sigmoid":
        raise ValueError(f"the fast implementation covers the sigmoid only, got {net.activation!r}")
    x = np.asarray(x, dtype=f32)
    x_max = f32(constants()["X_MAX"])
    with np.errstate(invalid="ignore"):
        x = np.where(x > 0, np.where(x > x_max, x_max, x), f32(0.0))
    w, b, beta = fast_tables(net)
    acc = np.zeros_like(x)
    for k in range(w.size):
        acc = acc + beta[k] / _one_plus_exp2(w[k] * x + b[k])
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
    # t = w' x + b' is linear in x: its extremes over [0, X_MAX] are at the two ends
    w, b, _ = fast_tables(net)
    if not (np.all(np.isfinite(w)) and np.all(np.isfinite(b))):
        raise ModelError("--activation-impl fast needs finite -log2(e) w and -log2(e) b")
    w, b = w.astype(np.float64), b.astype(np.float64)
    reach = float(np.max(np.maximum(np.abs(b), np.abs(w * x_max + b))))
    if reach > T_MAX * (1 - 1e-6):
        raise ModelError(f"--activation-impl fast needs |t| = log2(e) |w x + b| <= {T_MAX} for every "
                         f"neuron and x in [0, {x_max}], this model reaches {reach:.4g}")


def _alternating_extrema(err: np.ndarray, count: int) -> np.ndarray:
    """Indices of ``count`` extrema of ``err`` with alternating signs and the largest |err|: the
    extremum of each same-sign run, then the smaller end run dropped until ``count`` remain."""
    sign = np.sign(err)
    runs = np.split(np.arange(err.size), np.flatnonzero(sign[1:] != sign[:-1]) + 1)
    peaks = [int(run[np.argmax(np.abs(err[run]))]) for run in runs if sign[run[0]] != 0]
    while len(peaks) > count:
        drop = 0 if abs(err[peaks[0]]) < abs(err[peaks[-1]]) else -1
        peaks.pop(drop)
    return np.array(peaks)


def minimax_exp2(degree: int = DEGREE, iterations: int = 60, n_grid: int = 400_000,
                 tolerance: float = 1e-9) -> np.ndarray:
    """Coefficients c_0 = 1, c_1..c_degree (float64) of the polynomial P minimizing
    max |P(f) / 2^f - 1| over [-1/2, 1/2] subject to P(0) = 1 (so 2^t is exact at integer t and
    sigma(0) = 1/2); FRIC_FAST_P0..P4 are these rounded to float.

    With P(f) = 1 + f Q(f) and h(f) = (2^f - 1) / f the relative error is f (Q(f) - h(f)) / 2^f:
    a weighted minimax problem for Q (weight |f| / 2^f), solved by Remez exchange. The weight
    vanishes at f = 0, so no reference point may sit there: the first reference is the Chebyshev
    extrema pushed off 0. The exchange stops when the error levels out (the largest error on the
    grid exceeds the levelled error |E| by less than ``tolerance`` relative)."""
    q = degree - 1
    k = np.arange(q + 2)
    nodes = -0.5 * np.cos(np.pi * k / (q + 1))  # Chebyshev extrema as the first reference
    near_zero = np.abs(nodes) < 1e-3
    nodes[near_zero] = np.where(nodes[near_zero] < 0, -1e-3, 1e-3)
    grid = np.linspace(-0.5, 0.5, n_grid)      # n_grid even: 0 is not on the grid
    h = np.expm1(grid * np.log(2.0)) / grid
    weight = np.abs(grid) / 2.0 ** grid

    def solve(f):
        """Q on the reference f with equal, alternating weighted errors, and that error E."""
        a = np.hstack([f[:, None] ** np.arange(q + 1),
                       ((-1.0) ** k * 2.0 ** f / np.abs(f))[:, None]])
        sol = np.linalg.solve(a, np.expm1(f * np.log(2.0)) / f)
        return sol[:-1], abs(sol[-1])

    coef = np.zeros(q + 1)
    for _ in range(iterations):
        coef, level = solve(nodes)
        err = weight * (np.polyval(coef[::-1], grid) - h)
        peaks = _alternating_extrema(err, q + 2)
        if peaks.size < q + 2:
            break
        nodes = grid[peaks]
        if np.max(np.abs(err)) - level <= tolerance * level:
            break
    return np.concatenate([[1.0], coef])


def polynomial_error(n_points: int = 1 << 21) -> float:
    """max |P(f) / 2^f - 1| over f in [-1/2, 1/2]: float32 Horner against exact 2^f on a dense
    grid plus as many random floats (minimax error and Horner rounding together)."""
    grid = np.linspace(-0.5, 0.5, n_points)
    rand = np.random.default_rng(0).uniform(-0.5, 0.5, n_points)
    f = np.concatenate([grid, rand]).astype(f32)
    exact = 2.0 ** f.astype(np.float64)
    return float(np.max(np.abs(exp2_poly_f32(f).astype(np.float64) / exact - 1.0)))


def kernel_error_bound() -> float:
    """Derived bound on |fl(beta / fl(1 + e)) - beta / (1 + 2^t)| / |beta| for each neuron of
    the fast kernel and the float t it forms (module doc: (b) + (c))."""
    return polynomial_error() / 4.0 + 2.0 * U32


def error_bound() -> float:
    """Derived bound on |fric_sigmoid_fast_f32(z) - sigmoid(z)| for every float z (module doc)."""
    c = constants()
    rho_l = abs(-c["NEG_LOG2E"] / np.log2(np.e) - 1.0)
    T = np.linspace(-T_MAX, T_MAX, 500_001)
    E = 2.0 ** T
    slope = E / (1.0 + E) ** 2
    reduction = float(np.max(slope * np.log(2.0) * np.abs(T))) * (rho_l + U32)
    return reduction + kernel_error_bound()


def sigmoid_exact(z) -> np.ndarray:
    """The float64 sigmoid of [F8], without overflow warnings."""
    z = np.asarray(z, dtype=np.float64)
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + np.exp(-z))
