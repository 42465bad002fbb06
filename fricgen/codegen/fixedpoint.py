"""Fixed-point friction models (``fricgen emit --dtype q15|q31``) and their integer twin.

For MCUs without FPU, [F3] and [F7]-[F8] are evaluated in integers only:
``q15``: 16-bit tables and I/O, 32-bit products, 64-bit accumulator; ``q31``: 32-bit tables and
I/O, 64-bit products and accumulator. Every quantity q has a binary scale: value = q 2^-F.
The scales are chosen from the model's ranges (``FixedSpec.of``):

- input velocity: F_v so that |v| < V_RANGE = the smallest power of two >= 2 v_sat that also
  holds the covered speed ``v_max`` (``input_range``): given, else the fastest speed of the
  model's training data (``training.axis.speed_max``), else none;
- output force: F_f so that |F| < the smallest power of two >= 1.1 max |F| on |v| <= V_RANGE;
- w, b, beta: the finest scale that holds the largest magnitude of each table;
- z = w x + b: the finest scale that holds max |w|, |b|, |w + b| (x in [0, 1]);
- sigmoid: a table of polynomials on segments of |z| (degree 2 on quarters for q15, degree 4
  on halves for q31), sigma(-z) = 1 - sigma(z), 1 beyond |z| = 12 (q15) or 24 (q31).

Right shifts of negative numbers are arithmetic (as GCC, Clang and Arm compilers define them);
every product fits its type by construction, and the output saturates. ``error_bound`` adds
up the quantization and rounding errors against the float64 model (see its docstring);
``render_fixed`` refuses a model whose bound exceeds ``max_rel_error`` of the force range.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, Optional

import numpy as np

from ..c_literal import c_list
from ..errors import ModelError
from ..model import FrictionModel
from ..networks import ElmNetwork
from .context import emit_options, identity_context, render_source_and_header

#: Per dtype: storage bits B, sigmoid polynomial degree D, segment width 2^-HS, table end ZS.
DTYPE_PARAMS = {"q15": dict(bits=16, degree=2, hs=2, zs=12), "q31": dict(bits=32, degree=4, hs=1, zs=24)}
#: Product shift before accumulation (keeps M terms of beta * sigma inside 64 bits).
_TERM_SHIFT = {"q15": 0, "q31": 16}


def _ceil_log2(x: float) -> int:
    return int(math.ceil(math.log2(x))) if x > 0 else 0


def _frac_for(max_abs: float, bits: int) -> int:
    """The finest binary scale F with round(max_abs 2^F) < 2^(bits-1) (bits - 1 for 0): the
    logarithm's, one coarser when max_abs 2^F rounds to 2^(bits-1) (as 4 2^13 = 2^15 in q15)."""
    f = (bits - 1) - _ceil_log2(max_abs)
    if round(max_abs * 2.0 ** f) >= 2 ** (bits - 1):
        f -= 1
    return f


def _quantize(values, frac: int, bits: int, what: str) -> np.ndarray:
    q = np.round(np.asarray(values, dtype=float) * 2.0 ** frac).astype(np.int64)
    if np.any(np.abs(q) >= 2 ** (bits - 1)):
        raise ModelError(f"{what} does not fit {bits}-bit storage at scale 2^-{frac}")
    return q


@dataclass(frozen=True)
class ConstMul:
    """y_q = (x_q M + 2^(S-1)) >> S multiplies a value of scale F_in by c into scale F_out."""

    mant: int
    shift: int

    @classmethod
    def of(cls, c: float, f_in: int, f_out: int, bits: int, what: str) -> "ConstMul":
        scaled = c * 2.0 ** (f_out - f_in)
        if scaled == 0:
            return cls(0, 1)
        shift = (bits - 2) - _ceil_log2(abs(scaled))
        if shift < 1:
            raise ModelError(f"{what}: the constant {c:.6g} is too large for {bits}-bit fixed point")
        shift = min(shift, 2 * bits - 2)
        return cls(int(round(scaled * 2.0 ** shift)), shift)

    def apply(self, x) -> np.ndarray:
        return (np.asarray(x, dtype=np.int64) * self.mant + (1 << (self.shift - 1))) >> self.shift


def covered_speed(model: FrictionModel, v_max: Optional[float] = None) -> Optional[float]:
    """The speed (m/s) the fixed-point input must hold: ``v_max``, else the model's
    ``axis.speed_max``, else None (only 2 v_sat is covered)."""
    if v_max is not None:
        return float(v_max)
    axis = model.axis
    return None if axis is None else axis.speed_max


def input_range(model: FrictionModel, dtype: str, v_max: Optional[float] = None) -> float:
    """V_RANGE (m/s): the smallest power of two >= 2 v_sat (the larger of an asymmetric
    model's two) in which ``covered_speed`` is representable; the emitted C takes |v| < V_RANGE
    (a caller clamps faster speeds there)."""
    bits = DTYPE_PARAMS[dtype]["bits"]
    cover = covered_speed(model, v_max)
    v_sat = max(curve.v_sat for curve in model.directions)
    need = 2 * v_sat if cover is None else max(2 * v_sat, cover * (1 + 2.0 ** -(bits - 2)))
    return 2.0 ** _ceil_log2(need)


def check_dtype(dtype: str) -> None:
    """``ModelError`` unless ``dtype`` is one of DTYPE_PARAMS."""
    if dtype not in DTYPE_PARAMS:
        raise ModelError(f"dtype must be one of {sorted(DTYPE_PARAMS)}, got {dtype!r}")


def io_scales(model: FrictionModel, dtype: str, v_max: Optional[float] = None,
              f_v: Optional[int] = None, f_f: Optional[int] = None) -> dict:
    """The scales every fixed-point model shares (``FixedSpec``, ``TableSpec``): ``dtype`` and
    ``bits``; F_v of the input (``input_range``); F_f of the output (1.1 max |F| over it); F_aim
    of the AIM (1.1 max |AIM| over [0, 1]); v_sat in the input's scale; and the constant
    multipliers K_in, 1 / K_out and B. ``f_v`` and ``f_f``, where given, replace the first two
    (the scales two curves of one model share)."""
    bits = DTYPE_PARAMS[dtype]["bits"]
    if f_v is None:
        f_v = (bits - 1) - _ceil_log2(input_range(model, dtype, v_max))
    if f_f is None:
        f_max = float(np.max(np.abs(model.force(np.linspace(0.0, 2.0 ** (bits - 1 - f_v), 4001)))))
        f_f = (bits - 1) - _ceil_log2(1.1 * f_max)
    aim_max = float(np.max(np.abs(model.aim(np.linspace(0.0, 1.0, 4001)))))
    f_aim = (bits - 1) - _ceil_log2(1.1 * aim_max + 1e-12)
    return dict(dtype=dtype, bits=bits, f_v=f_v, f_f=f_f, f_aim=f_aim,
                v_sat_q=int(round(model.v_sat * 2.0 ** f_v)),
                k_in=ConstMul.of(model.scaling.k_in, f_v, bits - 1, bits, "k_in"),
                inv_k_out=ConstMul.of(1.0 / model.scaling.k_out, f_aim, f_f, bits, "1 / k_out"),
                viscous=ConstMul.of(model.viscous, f_v, f_f, bits, "viscous"))


@dataclass(frozen=True)
class FixedSpec:
    """Scales and integer tables of a fixed-point model (all derived from the model's ranges)."""

    dtype: str
    bits: int
    f_v: int
    f_f: int
    f_w: int
    f_b: int
    f_z: int
    f_beta: int
    f_aim: int
    v_sat_q: int
    k_in: ConstMul
    inv_k_out: ConstMul
    viscous: ConstMul
    w: np.ndarray
    b: np.ndarray
    beta: np.ndarray
    sig_coeffs: np.ndarray
    degree: int
    hs: int
    zs: int

    @property
    def one(self) -> int:
        return 1 << (self.bits - 1)

    @property
    def term_shift(self) -> int:
        return _TERM_SHIFT[self.dtype]

    @classmethod
    def of(cls, model: FrictionModel, dtype: str, v_max: Optional[float] = None) -> "FixedSpec":
        """The scales for ``model`` in ``dtype``, its input covering ``v_max`` (``input_range``)."""
        check_dtype(dtype)
        net = model.aim
        if not isinstance(net, ElmNetwork) or net.activation != "sigmoid":
            raise ModelError("fixed-point emission covers ELM models with sigmoid activation only")
        p = DTYPE_PARAMS[dtype]
        bits = p["bits"]
        w, b, beta = net.input_weights, net.biases, net.output_weights
        f_w = _frac_for(np.max(np.abs(w)), bits)
        f_b = _frac_for(np.max(np.abs(b)), bits)
        z_max = float(np.max(np.concatenate([np.abs(w), np.abs(b), np.abs(w + b)])))
        f_z = (2 * bits - 3) - max(_ceil_log2(z_max * 1.01 + 1e-9), 1)
        if f_z - p["hs"] < bits - 1 or f_z < f_b:
            raise ModelError(f"network weights too large for {dtype}: |w x + b| reaches {z_max:.4g}")
        f_beta = _frac_for(np.max(np.abs(beta)), bits)
        return cls(
            **io_scales(model, dtype, v_max), f_w=f_w, f_b=f_b, f_z=f_z, f_beta=f_beta,
            w=_quantize(w, f_w, bits, "input_weights"), b=_quantize(b, f_b, bits, "biases"),
            beta=_quantize(beta, f_beta, bits, "output_weights"),
            sig_coeffs=sigmoid_table(bits, p["degree"], p["hs"], p["zs"]),
            degree=p["degree"], hs=p["hs"], zs=p["zs"])


def sigmoid_table(bits: int, degree: int, hs: int, zs: int) -> np.ndarray:
    """Per segment [i h, (i + 1) h) of z >= 0, h = 2^-hs: coefficients of sigma(i h + r h) in r
    in [0, 1) (least squares on Chebyshev nodes ~ minimax), in Q(bits-1)."""
    h = 2.0 ** -hs
    nodes = 0.5 - 0.5 * np.cos(np.pi * (np.arange(64) + 0.5) / 64)
    rows = [np.polynomial.polynomial.polyfit(nodes, 1.0 / (1.0 + np.exp(-(i * h + nodes * h))), degree)
            for i in range(int(zs / h))]
    one = 2 ** (bits - 1)
    return np.clip(np.round(np.array(rows) * one), -one, one - 1).astype(np.int64)


def _rshift(x, s: int) -> np.ndarray:
    """Rounding arithmetic right shift by s >= 1 (the C macro FRIC_RSHIFT)."""
    return (np.asarray(x, dtype=np.int64) + (1 << (s - 1))) >> s


def sigmoid_q(spec: FixedSpec, z_q) -> np.ndarray:
    """Integer twin of the emitted NAME_sigmoid: sigma(z_q 2^-f_z) in Q(bits-1)."""
    z_q = np.asarray(z_q, dtype=np.int64)
    u = np.abs(z_q)
    seg_shift = spec.f_z - spec.hs
    seg = u >> seg_shift
    inside = seg < spec.sig_coeffs.shape[0]
    r = (u & ((1 << seg_shift) - 1)) >> (seg_shift - (spec.bits - 1))
    c = spec.sig_coeffs[np.where(inside, seg, 0)]
    acc = c[:, spec.degree]
    for j in range(spec.degree - 1, -1, -1):
        acc = c[:, j] + _rshift(acc * r, spec.bits - 1)
    s = np.where(inside, np.clip(acc, 0, spec.one), spec.one)
    return np.where(z_q < 0, spec.one - s, s)


def force_q(spec: FixedSpec, v_q) -> np.ndarray:
    """Integer twin of NAME_force_q15 / NAME_force_q31: F_q (scale 2^-f_f) from v_q (2^-f_v)."""
    v_q = np.asarray(v_q, dtype=np.int64)
    bits = spec.bits
    x_q = normalized_speed(spec, v_q)                                  # Q(bits-1), [0, 1]
    acc = np.zeros_like(v_q)
    zw_shift = spec.f_w + bits - 1 - spec.f_z
    for k in range(spec.w.size):
        z = _rshift(spec.w[k] * x_q, zw_shift) + spec.b[k] * (1 << (spec.f_z - spec.f_b))
        term = spec.beta[k] * sigmoid_q(spec, z)
        acc = acc + (term >> spec.term_shift if spec.term_shift else term)
    acc_frac = spec.f_beta + bits - 1 - spec.term_shift
    aim = np.clip(_rshift(acc, acc_frac - spec.f_aim), -2 * spec.one, 2 * spec.one)
    return signed_force(spec, aim, v_q)


def normalized_speed(spec, v_q) -> np.ndarray:
    """x = K_in min(|v|, v_sat) in Q(bits-1), within [0, 1] ([F9]'s input, saturated as
    [F3]); ``spec`` a ``FixedSpec`` or a ``TableSpec``."""
    speed = np.minimum(np.abs(np.asarray(v_q, dtype=np.int64)), spec.v_sat_q)
    return np.minimum(spec.k_in.apply(speed), spec.one)


def signed_force(spec, aim, v_q) -> np.ndarray:
    """[F3] from the AIM (scale 2^-f_aim): sgn(v) (AIM / K_out + B |v|), saturated to the
    output type; odd, the viscous term rounded on |v|."""
    v_q = np.asarray(v_q, dtype=np.int64)
    magnitude = spec.inv_k_out.apply(aim) + spec.viscous.apply(np.abs(v_q))
    total = np.where(v_q > 0, magnitude, np.where(v_q < 0, -magnitude, 0))
    return np.clip(total, -(spec.one - 1), spec.one - 1)


def error_bound(spec: FixedSpec, model: FrictionModel) -> float:
    """Bound (N) on |force_q(v_q) 2^-f_f - F(v_q 2^-f_v)| for every representable v_q.

    Sums, in newtons: the x rounding (1 LSB of Q(bits-1)) and the z roundings and w, b
    quantization, times |w| and the sigmoid slope 1/4; the sigmoid table's error (measured on
    all its segments); beta's quantization; the accumulator and AIM roundings; the constant
    multiplications' roundings (1/2 LSB each plus their mantissa error); the output LSB.
    """
    net = model.aim
    lsb = lambda f: 2.0 ** -f  # noqa: E731
    one = lsb(spec.bits - 1)
    dz = np.abs(net.input_weights) * input_rounding(spec, model) + lsb(spec.f_w + 1) \
        + lsb(spec.f_b + 1) + lsb(spec.f_z)
    sig_err = sigmoid_table_error(spec) + one
    beta_abs = np.abs(net.output_weights)
    aim_err = float(np.sum(beta_abs * (sig_err + dz / 4.0))) + spec.w.size * lsb(spec.f_beta + 1) \
        + spec.w.size * lsb(spec.f_beta + spec.bits - 1 - spec.term_shift) + lsb(spec.f_aim)
    return aim_err / model.scaling.k_out + output_error(spec, model)


def input_rounding(spec, model: FrictionModel) -> float:
    """Bound on the error of the integer x = K_in |v| in [0, 1] (``spec``: a ``FixedSpec`` or a
    ``TableSpec``): its rounding (1/2 LSB of Q(bits-1)), K_in's mantissa error up to v_sat, and
    the rounding of v_sat itself."""
    k_in_exact = model.scaling.k_in * 2.0 ** (spec.bits - 1 - spec.f_v)
    return 2.0 ** -(spec.bits - 1) * (0.5 + spec.v_sat_q * abs(
        spec.k_in.mant * 2.0 ** -spec.k_in.shift - k_in_exact)) + model.scaling.k_in * 2.0 ** -(spec.f_v + 1)


def output_error(spec, model: FrictionModel) -> float:
    """Bound (N) on what follows the AIM: the mantissa errors of 1 / K_out and B over the whole
    AIM and speed ranges, and 3 output LSBs of rounding (``spec`` as ``input_rounding``)."""
    a_max = 2.0 ** (spec.bits - 1 - spec.f_aim)
    v_max = 2.0 ** (spec.bits - 1 - spec.f_v)
    return (a_max * abs(spec.inv_k_out.mant * 2.0 ** (spec.f_aim - spec.f_f - spec.inv_k_out.shift)
                        - 1.0 / model.scaling.k_out)
            + v_max * abs(spec.viscous.mant * 2.0 ** (spec.f_v - spec.f_f - spec.viscous.shift)
                          - model.viscous)
            + 3 * 2.0 ** -spec.f_f)


def sigmoid_table_error(spec: FixedSpec) -> float:
    """max |sigmoid_q - sigmoid| over a dense grid of z_q in [0, zs + 1] (the table is odd-symmetric)."""
    z = np.linspace(0.0, spec.zs + 1.0, 400_001)
    z_q = np.round(z * 2.0 ** spec.f_z).astype(np.int64)
    exact = 1.0 / (1.0 + np.exp(-(z_q * 2.0 ** -spec.f_z)))
    return float(np.max(np.abs(sigmoid_q(spec, z_q) * 2.0 ** -(spec.bits - 1) - exact)))


@dataclass(frozen=True)
class BandSpec:
    """NAME_compensation_q15/q31's band ([the float NAME_compensation]'s ``velocity_band``) in
    the input's scale: 0 while |v_q| <= ``band_q`` (at least 1 LSB), a ramp to the force at
    2 band_q, the force beyond; the ramp's weight (|v_q| - band_q) / band_q in Q(bits-1) is
    ``weight``, a product and a shift."""

    band_q: int
    weight: ConstMul

    @classmethod
    def of(cls, model: FrictionModel, spec) -> Optional["BandSpec"]:
        """The band of ``model`` on ``spec``'s input scale, or None for a model without one."""
        if model.velocity_band is None:
            return None
        band_q = max(int(round(model.velocity_band * 2.0 ** spec.f_v)), 1)
        if 2 * band_q >= spec.one:
            raise ModelError(f"the velocity band {model.velocity_band:.4g} fills the {spec.dtype} "
                             "input's range")
        shift = 2 * spec.bits - 2 - _ceil_log2(band_q)          # (|v_q| - band_q) mant < 2^shift
        return cls(band_q, ConstMul(int(round(2.0 ** shift / band_q)), shift - (spec.bits - 1)))


def compensation_q(force, band: BandSpec, bits: int, v_q) -> np.ndarray:
    """Integer twin of NAME_compensation_q15 / q31: ``force`` (the twin of NAME_force_q15/q31, a
    function of v_q) within the band's ramp (``BandSpec``)."""
    v_q = np.asarray(v_q, dtype=np.int64)
    u = np.abs(v_q)
    edge = force(np.where(v_q < 0, -2 * band.band_q, 2 * band.band_q))
    ramp = _rshift(edge * band.weight.apply(np.clip(u - band.band_q, 0, band.band_q)), bits - 1)
    return np.where(u <= band.band_q, 0, np.where(u >= 2 * band.band_q, force(v_q), ramp))


def compensation_error_bound(force_bound: float, spec, model: FrictionModel) -> float:
    """Bound (N) on |compensation_q 2^-f_f - model.compensation(v_q 2^-f_v)|: the force's
    bound; the band rounded to whole LSBs of v (by delta), which tilts the ramp by up to
    2 delta / band of its end F(+-2 band) (but never by more than the largest |F| within the
    ramp: a band under an LSB), and moves its end by 2 delta, over which F changes (sampled);
    the weight's and the product's rounding; an output LSB."""
    lsb = 2.0 ** -spec.f_v
    band = model.velocity_band
    band_q = BandSpec.of(model, spec).band_q
    delta = abs(band - band_q * lsb)
    edge = float(np.max(np.abs(model.force(np.array([-2.0, 2.0]) * band))))
    peak = float(np.max(np.abs(model.force(np.linspace(-2.0, 2.0, 801) * (band_q + 1) * lsb))))
    between = np.linspace(2.0 * band, 2.0 * band_q * lsb, 65)     # the ramp's two ends
    step = max(float(np.ptp(model.force(side * between))) for side in (-1.0, 1.0))
    return force_bound + min(edge * (2.0 * delta / band + 2.0 ** -(spec.bits - 2)), peak) + step \
        + 2.0 ** -spec.f_f


def _c_int_array(values, per_line: int = 8) -> str:
    return c_list((str(int(v)) for v in np.asarray(values).ravel()), per_line)


def fixed_context(model: FrictionModel, name: str, spec, v_max: Optional[float], bound: float,
                  max_rel_error: float) -> dict:
    """What every fixed-point NAME.h/NAME.c states (``spec``: a ``FixedSpec`` or a
    ``TableSpec``): the identity, the types, the input and output scales and ranges, the
    constant multipliers and the error bound; ``ModelError`` when the bound exceeds
    ``max_rel_error`` of the force range."""
    cover = covered_speed(model, v_max)
    if cover is None:
        covers = "2 v_sat only: the model records no training speeds"
    else:
        covers = (f"{cover:.4g} {model.units.speed}" + (" (--v-max)" if v_max is not None else
                                         ", the fastest speed of the model's training data"))
    f_range = 2.0 ** (spec.bits - 1 - spec.f_f)
    if not bound <= max_rel_error * f_range:
        unit = model.units.force
        raise ModelError(f"{spec.dtype} cannot meet its error bound for this model: {bound:.4g} {unit} > "
                         f"{max_rel_error:g} x force range {f_range:g} {unit}")
    st, wt = ("int16_t", "int32_t") if spec.bits == 16 else ("int32_t", "int64_t")
    return {
        **identity_context(model, name), "units": model.units, "dtype": spec.dtype, "bits": spec.bits,
        "stype": st, "wtype": wt, "f_v": spec.f_v, "f_f": spec.f_f, "error_bound": f"{bound:.3g}",
        "covers": covers, "v_range": f"{2.0 ** (spec.bits - 1 - spec.f_v):g}", "f_range": f"{f_range:g}",
        "one": spec.one, "v_sat_q": spec.v_sat_q, "k_in": spec.k_in, "inv_k_out": spec.inv_k_out,
        "viscous": spec.viscous, "smin": -(spec.one - 1), "smax": spec.one - 1,   # F(-v) = -F(v)
        "table_size": 0,                                   # the ELM path; a table sets it
        "emit_options": emit_options(dtype=spec.dtype, v_max=v_max),
        "band": band_context(model, spec, bound),
    }


def band_context(model: FrictionModel, spec, force_bound: float) -> Optional[dict]:
    """NAME_compensation_q15/q31's constants and bound (``BandSpec``), None without a band."""
    band = BandSpec.of(model, spec)
    if band is None:
        return None
    return {"band_q": band.band_q, "twice_q": 2 * band.band_q, "weight": band.weight,
            "value": f"{model.velocity_band:.4g}",
            "source": model.training.get("velocity_band_from", "model.json velocity_band"),
            "bound": f"{compensation_error_bound(force_bound, spec, model):.3g}"}


def render_fixed(model: FrictionModel, name: str, dtype: str, max_rel_error: float = 0.025,
                 v_max: Optional[float] = None) -> Dict[str, str]:
    """NAME.h and NAME.c of the fixed-point ELM (no runtime files, no float, no libm), its
    input covering ``v_max`` m/s (default: the model's training speeds; ``input_range``)."""
    spec = FixedSpec.of(model, dtype, v_max)
    try:
        ctx = fixed_context(model, name, spec, v_max, error_bound(spec, model), max_rel_error)
    except ModelError as exc:
        raise ModelError(f"{exc} (||beta||_1 = {np.abs(model.aim.output_weights).sum():.3g}; "
                         "train with solver 'loo')") from None
    ctx.update({
        "n_hidden": spec.w.size,
        "w": _c_int_array(spec.w), "b": _c_int_array(spec.b), "beta": _c_int_array(spec.beta),
        "sig": ",\n".join("    {" + ", ".join(str(int(c)) for c in row) + "}" for row in spec.sig_coeffs),
        "n_seg": spec.sig_coeffs.shape[0],
        "degree": spec.degree, "seg_shift": spec.f_z - spec.hs, "hs": spec.hs, "zs": spec.zs,
        "r_shift": spec.f_z - spec.hs - (spec.bits - 1),
        "seg_mask": (1 << (spec.f_z - spec.hs)) - 1,
        "zw_shift": spec.f_w + spec.bits - 1 - spec.f_z, "zb_mul": 1 << (spec.f_z - spec.f_b),
        "term_shift": spec.term_shift,
        "aim_shift": spec.f_beta + spec.bits - 1 - spec.term_shift - spec.f_aim,
    })
    if ctx["aim_shift"] < 1 or ctx["zw_shift"] < 1:
        raise ModelError(f"{dtype}: the network's scales leave no rounding headroom (aim shift "
                         f"{ctx['aim_shift']}, z shift {ctx['zw_shift']})")
    return render_source_and_header(ctx, name, "model_fixed")


def to_fixed(values, frac: int, bits: int) -> np.ndarray:
    """Round and saturate real values to the integer grid value = q 2^-frac."""
    q = np.round(np.asarray(values, dtype=float) * 2.0 ** frac)
    return np.clip(q, -(2 ** (bits - 1)), 2 ** (bits - 1) - 1).astype(np.int64)
