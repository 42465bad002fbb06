"""Fixed-point grey-box models (``fricgen emit --dtype q15|q31`` of eq. (1)): the AIM as a table.

Eq. (1)'s exponentials have no cheap integer form, but the AIM of eq. (3) is a function of the
saturated input x = K_in min(|v|, v_sat) in [0, 1] alone. So it is tabulated at N + 1 points
x_i = i / N (N a power of two) and interpolated linearly: the index is the top log2 N bits of
x in Q(bits-1), the weight the rest. The rest of eq. (3) (1 / K_out, B |v|, the sign, the
saturation) is the ELM path's (``fricgen.codegen.fixedpoint``), as are the input and output
scales. N is the smallest power of two from MIN_TABLE whose interpolation error is within
TABLE_TOLERANCE of the force range, at most MAX_TABLE.

``table_error_bound`` adds, in newtons: the interpolation error (maximized over the worst
intervals: ``interpolation_error``), the table's rounding (1/2 LSB) and the interpolation's
(1 LSB), the input's rounding times the AIM's largest slope, and what follows the AIM
(``output_error``).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Optional

import numpy as np
from scipy.optimize import minimize_scalar

from ..errors import ModelError
from ..model import FrictionModel
from ..networks.stribeck import StribeckCurve
from .fixedpoint import (DTYPE_PARAMS, ConstMul, _c_int_array, _ceil_log2, _quantize, _rshift,
                         fixed_context, input_range, input_rounding, normalized_speed,
                         output_error, render_fixed_files, signed_force)

#: Fewest and most intervals of the table (powers of two).
MIN_TABLE, MAX_TABLE = 32, 2048
#: The table grows until its interpolation error is within this fraction of the force range.
TABLE_TOLERANCE = 2e-4
#: Points per interval on which the interpolation error is probed, and the worst intervals
#: then maximized exactly.
TABLE_PROBES, REFINED = 64, 4


@dataclass(frozen=True)
class TableSpec:
    """Scales and the integer AIM table of a fixed-point grey-box model."""

    dtype: str
    bits: int
    f_v: int
    f_f: int
    f_aim: int
    v_sat_q: int
    k_in: ConstMul
    inv_k_out: ConstMul
    viscous: ConstMul
    log2_n: int
    table: np.ndarray
    interpolation_error: float        # of the exact table, normalized AIM units

    @property
    def one(self) -> int:
        return 1 << (self.bits - 1)

    @property
    def index_shift(self) -> int:
        """Bits of x below the table index: the interpolation weight's."""
        return self.bits - 1 - self.log2_n

    @classmethod
    def of(cls, model: FrictionModel, dtype: str, v_max: Optional[float] = None) -> "TableSpec":
        """The scales and table for the grey-box ``model`` in ``dtype`` (``input_range``)."""
        if dtype not in DTYPE_PARAMS:
            raise ModelError(f"dtype must be one of {sorted(DTYPE_PARAMS)}, got {dtype!r}")
        if not isinstance(model.aim, StribeckCurve):
            raise ModelError("the fixed-point table covers grey-box models of eq. (1)")
        bits = DTYPE_PARAMS[dtype]["bits"]
        v_range = input_range(model, dtype, v_max)
        f_v = (bits - 1) - _ceil_log2(v_range)
        f_max = float(np.max(np.abs(model.force(np.linspace(0.0, v_range, 4001)))))
        f_f = (bits - 1) - _ceil_log2(1.1 * f_max)
        aim_max = float(np.max(np.abs(model.aim(np.linspace(0.0, 1.0, 4001)))))
        f_aim = (bits - 1) - _ceil_log2(1.1 * aim_max + 1e-12)
        tolerance = TABLE_TOLERANCE * 2.0 ** (bits - 1 - f_f) * model.scaling.k_out
        log2_n = int(np.log2(MIN_TABLE))
        while True:
            error = interpolation_error(model.aim, 2 ** log2_n)
            if error <= tolerance or 2 ** log2_n >= MAX_TABLE:
                break
            log2_n += 1
        exact = model.aim(np.linspace(0.0, 1.0, 2 ** log2_n + 1))
        return cls(dtype=dtype, bits=bits, f_v=f_v, f_f=f_f, f_aim=f_aim,
                   v_sat_q=int(round(model.v_sat * 2.0 ** f_v)),
                   k_in=ConstMul.of(model.scaling.k_in, f_v, bits - 1, bits, "k_in"),
                   inv_k_out=ConstMul.of(1.0 / model.scaling.k_out, f_aim, f_f, bits, "1 / k_out"),
                   viscous=ConstMul.of(model.viscous, f_v, f_f, bits, "viscous"),
                   log2_n=log2_n, table=_quantize(exact, f_aim, bits, "the AIM table"),
                   interpolation_error=error)


def interpolation_error(aim, n: int) -> float:
    """max |linear interpolation of ``aim`` between x_i = i / n - aim|: probed at TABLE_PROBES
    points per interval, then the REFINED worst intervals maximized to machine precision
    around their worst probe (bounded scalar search)."""
    knots = aim(np.linspace(0.0, 1.0, n + 1))

    def error(i, r):
        return abs(knots[i] * (1 - r) + knots[i + 1] * r - float(aim(np.array([(i + r) / n]))[0]))

    r = np.arange(1, TABLE_PROBES) / TABLE_PROBES
    x = (np.arange(n)[:, None] + r[None, :]) / n
    probed = np.abs(knots[:-1, None] * (1 - r) + knots[1:, None] * r - aim(x.ravel()).reshape(x.shape))
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
    index = x_q >> spec.index_shift
    weight = x_q & ((1 << spec.index_shift) - 1)
    low = spec.table[index]
    high = spec.table[np.minimum(index + 1, spec.table.size - 1)]
    aim = low + (_rshift((high - low) * weight, spec.index_shift) if spec.index_shift else 0)
    return signed_force(spec, aim, v_q)


def table_error_bound(spec: TableSpec, model: FrictionModel) -> float:
    """Bound (N) on |force_table_q(v_q) 2^-f_f - F(v_q 2^-f_v)| for every representable v_q (see
    the module)."""
    x = np.linspace(0.0, 1.0, 200_001)
    slope = float(np.max(np.abs(np.diff(model.aim(x)) / np.diff(x))))
    aim_err = spec.interpolation_error + 1.5 * 2.0 ** -spec.f_aim + slope * input_rounding(spec, model)
    return aim_err / model.scaling.k_out + output_error(spec, model)


def render_fixed_table(model: FrictionModel, name: str, dtype: str, max_rel_error: float = 0.025,
                       v_max: Optional[float] = None) -> Dict[str, str]:
    """NAME.h and NAME.c of the fixed-point grey-box model (integers only, no runtime files),
    its input covering ``v_max`` m/s (default: the model's training speeds)."""
    spec = TableSpec.of(model, dtype, v_max)
    ctx = fixed_context(model, name, spec, v_max, table_error_bound(spec, model), max_rel_error)
    ctx.update({"table_size": spec.table.size, "table": _c_int_array(spec.table),
                "index_shift": spec.index_shift, "f_aim": spec.f_aim, "weight_mask": (1 << spec.index_shift) - 1,
                "source_count": model.aim.n_sources, "shape": model.aim.shape})
    return render_fixed_files(name, ctx)
