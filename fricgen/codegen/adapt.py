"""``fricgen emit --adapt``: the model as a regressor for online adaptation (NAME_adapt.{h,c})
and the runtime that adapts it (c_runtime/fric_adapt.{h,c}), see fricgen.control.adaptation."""
from __future__ import annotations

from typing import Dict

from .._io import resource_dir
from ..c_literal import c_array, c_float
from ..control.adaptation import RULE, FrictionAdapter, parameter_scale
from ..control.regressor import Regressor, parameter_names, trained_parameters
from ..model import FrictionModel
from ..networks import StribeckCurve
from .context import identity_context, template_environment
from .render import STRIBECK_C_SHAPES
from .twin import stribeck_table

#: The adaptation runtime copied beside the controller runtime.
ADAPT_FILES = ("fric_adapt.h", "fric_adapt.c")
#: One hidden unit's output h(z) of eq. (8) in the generated regressor, by implementation.
ACTIVATION_C = {"libm": {"sigmoid": "1.0f / (1.0f + expf(-z))", "sine": "sinf(z)",
                         "rbf": "expf(-(z * z))", "multiquadric": "sqrtf(1.0f + z * z)"},
                "fast": {"sigmoid": "fric_sigmoid_fast_f32(z)"}}
#: The fields of fric_adapt_params_t that are one float, in the header's order.
SCALAR_FIELDS = ("forgetting", "p0", "trace_max", "gain", "leak", "v_dead", "e_dead")


def adapt_params(adapter) -> dict:
    """The fric_adapt_params_t of a ``FrictionAdapter`` (validated first): field -> float,
    list of n floats, or for ``rule`` the enumerator."""
    adapter.validate()
    lo, hi = adapter.bounds()
    theta0 = trained_parameters(adapter.model)
    values = {"n": theta0.size, "rule": RULE.member(adapter.rule), "theta0": list(theta0),
              "lo": list(lo), "hi": list(hi), "scale": list(parameter_scale(adapter.model))}
    values.update({"forgetting": adapter.forgetting, "p0": adapter.p0,
                   "trace_max": adapter.trace_max, "gain": adapter.gain(), "leak": adapter.leak,
                   "v_dead": adapter.v_dead, "e_dead": adapter.e_dead})
    return values


def render_adapt(model: FrictionModel, name: str, activation_impl: str = "libm") -> Dict[str, str]:
    """NAME_adapt.h, NAME_adapt.c (for ``FrictionAdapter(model)``'s defaults) and the runtime
    fric_adapt.{h,c}, by file name."""
    Regressor(model, "float32", activation_impl)                 # refuses what cannot adapt
    adapter = FrictionAdapter(model, activation_impl=activation_impl)
    params = adapt_params(adapter)
    net = model.aim
    ctx = {**identity_context(model, name), "GUARD": f"FRICGEN_{name.upper()}_ADAPT_H",
           "names": parameter_names(model), "n": params["n"], "box": f"{adapter.box:g}",
           "rule": adapter.rule, "rule_enum": params["rule"].name, "kind": net.kind,
           "k_in": c_float(model.scaling.k_in), "v_sat": c_float(model.v_sat),
           "inv_k_out": c_float(1.0 / model.scaling.k_out),
           "theta0": c_array(params["theta0"]), "lo": c_array(params["lo"]),
           "hi": c_array(params["hi"]), "scale": c_array(params["scale"]),
           "scalars": [(f, c_float(params[f])) for f in SCALAR_FIELDS]}
    if isinstance(net, StribeckCurve):
        ctx.update(n_basis=net.n_sources, inv_stribeck=c_array(stribeck_table(net)),
                   slope=c_float(net.slope), g_expr=STRIBECK_C_SHAPES[activation_impl][net.shape],
                   describe=f"grey-box eq. (1), {net.n_sources} {net.shape} Stribeck sources",
                   header='"fric_fast.h"' if activation_impl == "fast" else "<math.h>")
    else:
        ctx.update(n_basis=net.n_hidden, input_weights=c_array(net.input_weights),
                   biases=c_array(net.biases),
                   act_expr=ACTIVATION_C[activation_impl][net.activation],
                   describe=f"{net.n_hidden} {net.activation} neurons",
                   header='"fric_fast.h"' if activation_impl == "fast" else "<math.h>")
    env = template_environment()
    runtime = resource_dir("c_runtime")
    return {f"{name}_adapt.h": env.get_template("model_adapt.h.j2").render(ctx),
            f"{name}_adapt.c": env.get_template("model_adapt.c.j2").render(ctx),
            **{fname: (runtime / fname).read_text() for fname in ADAPT_FILES}}
