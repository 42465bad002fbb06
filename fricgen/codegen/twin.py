"""Float32 Python twin of the emitted C: the same operations, in the same order, in float32.

Each C float operation (+, *, /) is IEEE single precision with round-to-nearest; numpy float32
arithmetic is the same. For libm functions (expf, sinf, sqrtf) the twin evaluates in double and
rounds once to float, i.e. the correctly rounded result; glibc's float functions are accurate to
better than 1 ULP, so each activation value may differ by at most 1 ULP from C.
"""
from __future__ import annotations

import numpy as np

from ..effects import model_effects
from ..model import FrictionModel
from ..networks import ElmNetwork, StribeckCurve
from ..networks.elm import exp_neg_f32
from .fast_sigmoid import aim_fast_f32, exp_neg_fast_f32

f32 = np.float32


def aim_f32(net: ElmNetwork, x) -> np.ndarray:
    """Mirror of ``fric_elm_<activation>_f32``: sum_k beta_k act(w_k x + b_k), k ascending."""
    return net.float32(x)


def stribeck_table(net: StribeckCurve) -> np.ndarray:
    """The emitted table of 1 / xs_k, each rounded once to float."""
    return (1.0 / net.stribeck).astype(f32)


#: g(u) of [F2] in float32 as the emitted grey-box C computes it, by implementation.
STRIBECK_SHAPES_F32 = {
    "libm": {"gauss": lambda u: exp_neg_f32(u * u), "exponential": exp_neg_f32,
             "rational": lambda u: f32(1.0) / (f32(1.0) + u)},
    "fast": {"gauss": lambda u: exp_neg_fast_f32(u * u), "exponential": exp_neg_fast_f32,
             "rational": lambda u: f32(1.0) / (f32(1.0) + u)},
}


def stribeck_aim_f32(net: StribeckCurve, x, activation_impl: str = "libm") -> np.ndarray:
    """Mirror of the emitted grey-box ``NAME_aim``: x < 0 (and NaN) as 0, then
    c + d x + sum_k a_k g(x / xs_k), k ascending."""
    x = np.atleast_1d(np.asarray(x, dtype=f32))
    with np.errstate(invalid="ignore"):
        x = np.where(x > 0, x, f32(0.0)).astype(f32)
    g = STRIBECK_SHAPES_F32[activation_impl][net.shape]
    inv, amp = stribeck_table(net), net.amplitudes.astype(f32)
    acc = f32(net.offset) + f32(net.slope) * x
    with np.errstate(over="ignore", under="ignore"):
        for k in range(inv.size):
            acc = acc + amp[k] * g(x * inv[k])
    return acc


def force_f32(model: FrictionModel, v, activation_impl: str = "libm") -> np.ndarray:
    """Mirror of the emitted ``NAME_force`` [F3] in float32; ``activation_impl`` as in emit."""
    if activation_impl not in ("libm", "fast"):
        raise ValueError(f"activation_impl must be 'libm' or 'fast', got {activation_impl!r}")
    def aim_twin(net, x):                   # each curve's own kind: ELM or [F1]
        if isinstance(net, StribeckCurve):
            return stribeck_aim_f32(net, x, activation_impl)
        return aim_fast_f32(net, x) if activation_impl == "fast" else aim_f32(net, x)

    v = np.asarray(v, dtype=f32)
    speed = np.abs(v)
    stribeck = _stribeck_f32(model, speed, aim_twin)
    signed = np.where(v > 0, stribeck, np.where(v < 0, -stribeck, f32(0.0)))
    force = signed + f32(model.viscous) * v
    if model.negative is None:
        return force
    negative = -_stribeck_f32(model.negative, speed, aim_twin) + f32(model.negative.viscous) * v
    return np.where(v < 0, negative, force)


def _stribeck_f32(curve, speed, aim_twin) -> np.ndarray:
    """AIM(K_in min(|v|, v_sat)) / K_out of one curve (a model or a ``Direction``) in float32."""
    v_sat = f32(curve.v_sat)
    x = f32(curve.scaling.k_in) * np.where(speed < v_sat, speed, v_sat)
    return aim_twin(curve.aim, x) * f32(1.0 / curve.scaling.k_out)


def force_xv_f32(model: FrictionModel, v, x, base=None) -> np.ndarray:
    """Float32 mirror of the emitted NAME_force_xv (``base``: the float32 NAME_force values)."""
    v, x = (np.asarray(a, dtype=np.float32) for a in np.broadcast_arrays(v, x))
    total = force_f32(model, v) if base is None else np.asarray(base, dtype=np.float32)
    base = total
    for e in model_effects(model):
        if e.in_xv:
            total = total + e.force_f32(v, x, base)
    return total
