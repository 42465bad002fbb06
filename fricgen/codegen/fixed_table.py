"""Fixed-point grey-box models (``fricgen emit --dtype q15|q31`` of [F1]): the AIM as a table.

[F1]'s exponentials have no cheap integer form, but the AIM of [F3] is a function of the
saturated input x = K_in min(|v|, v_sat) in [0, 1] alone. So it is tabulated and interpolated
linearly, on knots as fine as its steepest part needs: [0, 1] is cut into the octaves
[2^-j, 2^-(j-1)) for j = 1..K and the base [0, 2^-K), each into M = 2^m equal intervals (a
Stribeck drop a thousandth of v_sat wide gets knots that fine, the rest fewer). In Q(bits-1)
every bound and width is a power of two, so the segment is found by at most K comparisons and
the index and weight by a shift and a mask. The rest of [F3] (1 / K_out, B |v|, the sign,
the saturation) is the ELM path's (``fricgen.codegen.fixedpoint``), as are the input and
output scales. (K, m) is the smallest table whose interpolation error is within
TABLE_TOLERANCE of the force range, else the most accurate of at most MAX_TABLE intervals.

``table_error_bound`` adds, in newtons: the interpolation error (maximized over the worst
intervals: ``interpolation_error``), the table's rounding (1/2 LSB) and the interpolation's
(1 LSB), the input's rounding times the AIM's largest slope, and what follows the AIM
(``output_error``).
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Dict, Optional, Sequence, Tuple

import numpy as np
from scipy.optimize import minimize_scalar

from ..errors import ModelError
from ..model import FrictionModel
from ..networks.stribeck import StribeckCurve
from .context import render_source_and_header
from .fixedpoint import (ConstMul, _c_int_array, _quantize, check_dtype, fixed_context,
                         input_rounding, io_scales, normalized_speed, output_error,
                         signed_force)

#: Intervals per segment, 2^m for m in this range; most intervals of a table.
LOG2_INTERVALS, MAX_TABLE = range(3, 8), 2048
#: The table grows until its interpolation error is within this fraction of the force range.
TABLE_TOLERANCE = 2e-4
#: Points per interval on which the interpolation error is probed, and the worst intervals
#: then maximized exactly.
TABLE_PROBES, REFINED = 64, 4


@dataclass(frozen=True)
class TableSpec:
    """Scales and the integer AIM table of a fixed-point grey-box model: ``octaves`` K and
    2^``log2_m`` intervals per segment (see the module)."""

    dtype: str
    bits: int
    f_v: int
    f_f: int
    f_aim: int
    v_sat_q: int
    k_in: ConstMul
    inv_k_out: ConstMul
    viscous: ConstMul
    octaves: int
    log2_m: int
    table: np.ndarray
    interpolation_error: float        # of the exact table, normalized AIM units

    @property
    def one(self) -> int:
        return 1 << (self.bits - 1)

    @property
    def base_shift(self) -> int:
        """Bits of x below the index in the base segment and the first octave."""
        return self.bits - 1 - self.octaves - self.log2_m

    @classmethod
    def of(cls, model: FrictionModel, dtype: str, v_max: Optional[float] = None,
           f_v: Optional[int] = None, f_f: Optional[int] = None) -> "TableSpec":
        """The scales and table for the symmetric grey-box ``model`` in ``dtype``
        (``input_range``; ``f_v``, ``f_f`` as ``io_scales``); ``table_specs`` for any model."""
        check_dtype(dtype)
        if not isinstance(model.aim, StribeckCurve):
            raise ModelError("the fixed-point table covers grey-box models of [F1]")
        if model.negative is not None:
            raise ModelError("an asymmetric model has a table per direction: table_specs")
        scales = io_scales(model, dtype, v_max, f_v, f_f)
        bits, f_aim = scales["bits"], scales["f_aim"]
        tolerance = TABLE_TOLERANCE * 2.0 ** (bits - 1 - scales["f_f"]) * model.scaling.k_out
        octaves, log2_m, error = _layout(model.aim, bits, tolerance)
        exact = model.aim(knots(octaves, log2_m))
        return cls(**scales, octaves=octaves, log2_m=log2_m,
                   table=_quantize(exact, f_aim, bits, "the AIM table"), interpolation_error=error)


def curve_models(model: FrictionModel) -> Tuple[FrictionModel, ...]:
    """Each curve of ``model`` (``FrictionModel.directions``: v >= 0, then v < 0 where it is
    asymmetric) as a symmetric model of its own."""
    return tuple(replace(model, aim=c.aim, scaling=c.scaling, viscous=c.viscous, v_sat=c.v_sat,
                         negative=None) for c in model.directions)


def table_specs(model: FrictionModel, dtype: str,
                v_max: Optional[float] = None) -> Tuple[TableSpec, ...]:
    """The ``TableSpec`` of each curve of ``model`` (``curve_models``), all on the input and
    output scales of the curve that needs the coarser ones: one input and one output for the
    whole model."""
    check_dtype(dtype)
    curves = curve_models(model)
    scales = [io_scales(c, dtype, v_max) for c in curves]
    f_v, f_f = min(s["f_v"] for s in scales), min(s["f_f"] for s in scales)
    return tuple(TableSpec.of(c, dtype, v_max, f_v, f_f) for c in curves)


def knots(octaves: int, log2_m: int) -> np.ndarray:
    """The table's x: 2^m equal intervals on [0, 2^-K) and on each octave [2^-j, 2^-(j-1)),
    j = K..1, and x = 1."""
    m = 2 ** log2_m
    lows = [0.0] + [2.0 ** -j for j in range(octaves, 0, -1)]
    widths = [2.0 ** -octaves] + lows[1:]
    return np.append(np.concatenate([lo + w * np.arange(m) / m for lo, w in zip(lows, widths)]), 1.0)


def _layout(aim, bits: int, tolerance: float):
    """(K, m, interpolation error): the smallest table within ``tolerance``, else the most
    accurate one of at most MAX_TABLE intervals; every interval at least 2 LSB of x wide."""
    best = None
    for log2_m in LOG2_INTERVALS:
        for octaves in range(0, bits - 2 - log2_m + 1):
            size = (octaves + 1) * 2 ** log2_m
            if size > MAX_TABLE:
                break
            error = interpolation_error(aim, knots(octaves, log2_m))
            key = (error > tolerance, size if error <= tolerance else error)
            if best is None or key < best[0]:
                best = (key, (octaves, log2_m, error))
            if error <= tolerance:
                break                       # more octaves only grow the table
    return best[1]


def interpolation_error(aim, x_knots) -> float:
    """max |linear interpolation of ``aim`` between ``x_knots`` - aim|: probed at TABLE_PROBES
    points per interval, then the REFINED worst intervals maximized to machine precision
    around their worst probe (bounded scalar search)."""
    x_knots = np.asarray(x_knots, dtype=float)
    values = aim(x_knots)

    def error(i, r):
        x = x_knots[i] + r * (x_knots[i + 1] - x_knots[i])
        return abs(values[i] * (1 - r) + values[i + 1] * r - float(aim(np.array([x]))[0]))

    r = np.arange(1, TABLE_PROBES) / TABLE_PROBES
    x = x_knots[:-1, None] + r[None, :] * np.diff(x_knots)[:, None]
    probed = np.abs(values[:-1, None] * (1 - r) + values[1:, None] * r - aim(x.ravel()).reshape(x.shape))
    worst = float(probed.max())
    for i in np.argsort(probed.max(axis=1))[-REFINED:]:
        k = int(np.argmax(probed[i]))
        lo, hi = max(r[k] - 1.0 / TABLE_PROBES, 0.0), min(r[k] + 1.0 / TABLE_PROBES, 1.0)
        best = minimize_scalar(lambda u: -error(i, u), bounds=(lo, hi), method="bounded",
                               options={"xatol": 1e-12})
        worst = max(worst, -float(best.fun))
    return worst


def force_table_q(spec: TableSpec, v_q) -> np.ndarray:
    """Integer twin of the emitted NAME_force_q15 / NAME_force_q31 of a grey-box model."""
    x_q = normalized_speed(spec, v_q)
    k = spec.octaves
    segment = sum((x_q >= (spec.one >> (k - u))).astype(np.int64) for u in range(k)) if k else \
        np.zeros_like(x_q)
    low = np.where(segment == 0, 0, spec.one >> np.maximum(k - segment + 1, 0))
    shift = spec.base_shift + np.maximum(segment - 1, 0)
    index = (segment << spec.log2_m) + ((x_q - low) >> shift)
    weight = (x_q - low) & ((np.int64(1) << shift) - 1)
    last = spec.table.size - 1
    a = spec.table[np.minimum(index, last)]
    b = spec.table[np.minimum(index + 1, last)]
    step = ((b - a) * weight + (np.int64(1) << (shift - 1))) >> shift
    aim = np.where(index < last, a + step, spec.table[last])
    return signed_force(spec, aim, v_q)


def force_tables_q(specs: Sequence[TableSpec], v_q) -> np.ndarray:
    """Integer twin of NAME_force_q15 / NAME_force_q31 of a grey-box model of any symmetry
    (``table_specs``): the first table for v >= 0, the last for v < 0."""
    v_q = np.asarray(v_q, dtype=np.int64)
    return np.where(v_q < 0, force_table_q(specs[-1], v_q), force_table_q(specs[0], v_q))


def tables_error_bound(specs: Sequence[TableSpec], model: FrictionModel) -> float:
    """``table_error_bound`` of the worse of ``model``'s curves (``table_specs``)."""
    return max(table_error_bound(s, c) for s, c in zip(specs, curve_models(model)))


def table_error_bound(spec: TableSpec, model: FrictionModel) -> float:
    """Bound (N) on |force_table_q(v_q) 2^-f_f - F(v_q 2^-f_v)| for every representable v_q (see
    the module)."""
    x = np.linspace(0.0, 1.0, 200_001)
    slope = float(np.max(np.abs(np.diff(model.aim(x)) / np.diff(x))))
    aim_err = spec.interpolation_error + 1.5 * 2.0 ** -spec.f_aim + slope * input_rounding(spec, model)
    return aim_err / model.scaling.k_out + output_error(spec, model)


def render_fixed_table(model: FrictionModel, name: str, dtype: str, max_rel_error: float = 0.025,
                       v_max: Optional[float] = None) -> Dict[str, str]:
    """NAME.h and NAME.c of the fixed-point grey-box model (integers only, no runtime files; a
    table per curve), its input covering ``v_max`` m/s (default: the model's training speeds)."""
    specs = table_specs(model, dtype, v_max)
    ctx = fixed_context(model, name, specs[0], v_max, tables_error_bound(specs, model), max_rel_error)
    suffixes = ("",) if len(specs) == 1 else ("_positive", "_negative")
    ctx.update({"table_size": sum(s.table.size for s in specs), "curves": [
        {"suffix": suffix, "table_size": s.table.size, "table": _c_int_array(s.table),
         "octaves": s.octaves, "log2_m": s.log2_m, "base_shift": s.base_shift, "f_aim": s.f_aim,
         "v_sat_q": s.v_sat_q, "k_in": s.k_in, "inv_k_out": s.inv_k_out, "viscous": s.viscous,
         "source_count": c.aim.n_sources, "shape": c.aim.shape}
        for suffix, s, c in zip(suffixes, specs, curve_models(model))]})
    return render_source_and_header(ctx, name, "model_fixed")
