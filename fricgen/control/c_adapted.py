"""``fricgen emit --adapt``: the model as a regressor for online adaptation (NAME_adapt.{h,c},
``render_adapt``) beside the runtime that adapts it (c_runtime/fric_adapt.{h,c}) and the
controller; and that C through cffi: ``CAdaptedController`` runs ``fric_adapt_ctrl_step`` in the closed loops of
``fricgen.control.loop.simulate``, beside its float32 twin ``AdaptedController``."""
from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

from typing import Dict

from .._io import write_all_atomic
from ..c_literal import c_array, c_float
from ..codegen.cbuild import build_module, model_cdef
from ..codegen.context import identity_context, runtime_text, template_environment
from ..codegen.render import BYTES_FILES, STRIBECK_C_SHAPES, controller_files, render
from ..codegen.twin import stribeck_table
from ..model import FrictionModel
from ..networks import StribeckCurve
from .adaptation import FLAGS, MAX_PARAMS, RULE, AdaptedController, FrictionAdapter, parameter_scale
from .c_abi import CDEF as CTRL_CDEF
from .c_controller import CController
from .regressor import Regressor, adapts_offset, parameter_names, trained_parameters

#: The adaptation runtime copied beside the controller runtime.
ADAPT_FILES = ("fric_adapt.h", "fric_adapt.c", *BYTES_FILES)
#: One hidden unit's output h(z) of [F8] in the generated regressor, by implementation: the
#: model's own kernels (exp's argument clamped: no errno, ``fric_kernel.h``).
ACTIVATION_C = {"libm": {"sigmoid": "1.0f / (1.0f + fric_exp_neg_inline_f32(z))", "sine": "sinf(z)",
                         "rbf": "fric_exp_neg_inline_f32(z * z)",
                         "multiquadric": "sqrtf(1.0f + (z * z))"},
                "fast": {"sigmoid": "fric_sigmoid_fast_f32(z)"}}
#: The fields of fric_adapt_params_t that are one float, in the header's order.
SCALAR_FIELDS = ("forgetting", "p0", "trace_max", "gain", "leak", "v_dead", "e_dead", "e_max",
                 "band", "v_max")



#: The cffi declarations of fric_adapt.h (tests/test_adaptation_c.py checks them against it).
CDEF = (RULE.cdef() + FLAGS.cdef()
        + "typedef enum { FRIC_ADAPT_OK_INIT = 0, FRIC_ADAPT_ERR_NULL = -1, "
          "FRIC_ADAPT_ERR_PARAM = -2, FRIC_ADAPT_ERR_SIZE = -3, FRIC_ADAPT_ERR_FOREIGN = -4, "
          "FRIC_ADAPT_ERR_CHECKSUM = -5, FRIC_ADAPT_ERR_RANGE = -6 } fric_adapt_status_t;\n"
        + "typedef float (*fric_adapt_regressor_fn)(float v, float *phi);\n"
        + "typedef struct {\n    unsigned int n;\n    fric_adapt_rule_t rule;\n"
          "    unsigned int n_leak;\n    unsigned int hold_at_rest;\n"
        + "".join(f"    float {a}[{MAX_PARAMS}];\n" for a in ("theta0", "lo", "hi", "scale"))
        + "".join(f"    float {s};\n" for s in SCALAR_FIELDS)
        + "} fric_adapt_params_t;\n"
        + f"typedef struct {{\n    fric_adapt_params_t p;\n    float theta[{MAX_PARAMS}];\n"
          f"    float P[{MAX_PARAMS * MAX_PARAMS}];\n    float scale2[{MAX_PARAMS}];\n"
          "    float error;\n    float v_prev;\n    float i_prev;\n    float k_hat;\n"
          "    float m_o_hat;\n    int held;\n    int recorded;\n    float settle;\n"
          "    fric_adapt_flags_t flags;\n} fric_adapt_t;\n"
        + "fric_adapt_status_t fric_adapt_init(fric_adapt_t *a, const fric_adapt_params_t *p);\n"
          "void fric_adapt_reset(fric_adapt_t *a);\n"
          "float fric_adapt_force(const fric_adapt_t *a, fric_adapt_regressor_fn reg, float v);\n"
          "fric_adapt_flags_t fric_adapt_rls(fric_adapt_t *a, fric_adapt_regressor_fn reg, "
          "float v, float force, int hold);\n"
          "fric_adapt_flags_t fric_adapt_lyapunov(fric_adapt_t *a, fric_adapt_regressor_fn reg, "
          "float v, float e2, int hold);\n"
          "fric_ctrl_flags_t fric_adapt_ctrl_step(fric_adapt_t *a, fric_ctrl_t *c, "
          "fric_adapt_regressor_fn reg, float x, float v, float xd, float xd_dot, float xd_ddot, "
          "float *current);\n"
          "fric_ctrl_flags_t fric_adapt_ctrl_step_sample(fric_adapt_t *a, fric_ctrl_t *c, "
          "fric_adapt_regressor_fn reg, const fric_ctrl_sample_t *s, float *current);\n"
          "unsigned int fric_adapt_export(const fric_adapt_t *a, const char *model_hash, "
          "char *buf, unsigned int size);\n"
          "unsigned int fric_adapt_save(const fric_adapt_t *a, const char *model_hash, "
          "unsigned char *buf, unsigned int size);\n"
          "fric_adapt_status_t fric_adapt_restore(fric_adapt_t *a, const char *model_hash, "
          "const unsigned char *buf, unsigned int size);\n")


def adapt_params(adapter) -> dict:
    """The fric_adapt_params_t of a ``FrictionAdapter`` (validated first): field -> float,
    list of n floats, or for ``rule`` the enumerator."""
    adapter.validate()
    lo, hi = adapter.bounds()
    theta0 = trained_parameters(adapter.model)
    values = {"n": theta0.size, "rule": RULE.member(adapter.rule),
              "n_leak": adapter.n_leak(), "hold_at_rest": int(adapter.hold_at_rest),
              "theta0": list(theta0),
              "lo": list(lo), "hi": list(hi), "scale": list(parameter_scale(adapter.model))}
    values.update({"forgetting": adapter.forgetting_factor(), "p0": adapter.p0,
                   "trace_max": adapter.trace_max, "gain": adapter.gain(),
                   "leak": adapter.leakage(), "v_dead": adapter.v_dead, "e_dead": adapter.e_dead,
                   "e_max": adapter.input_limit(), "band": adapter.force_band(),
                   "v_max": adapter.speed_limit()})
    return values


def rule_scalars(adapter) -> dict:
    """The one-float fields of ``adapt_params(adapter)`` (``SCALAR_FIELDS``), by name."""
    params = adapt_params(adapter)
    return {f: params[f] for f in SCALAR_FIELDS}


def c_params(module, adapter):
    """A fric_adapt_params_t (cffi, of ``module``) holding ``adapt_params(adapter)``."""
    p = module.ffi.new("fric_adapt_params_t *")
    for field, value in adapt_params(adapter).items():
        if isinstance(value, list):
            getattr(p, field)[0:len(value)] = value
        else:
            setattr(p, field, getattr(value, "value", value))
    return p


def render_adapt(model: FrictionModel, name: str, activation_impl: str = "libm") -> Dict[str, str]:
    """NAME_adapt.h, NAME_adapt.c (for ``FrictionAdapter(model)``'s defaults), the runtime
    fric_adapt.{h,c} and fric_bytes.{h,c} (its saved state's bytes), and the controller's
    fric_ctrl.{h,c}, by file name: what ``emit --adapt`` adds to ``codegen.render``'s files.
    ``ModelError`` for a model that cannot adapt."""
    Regressor(model, "float32", activation_impl)                 # refuses what cannot adapt
    adapter = FrictionAdapter(model, activation_impl=activation_impl)
    params = adapt_params(adapter)
    curves = [_curve_context(curve, activation_impl) for curve in model.directions]
    if len(curves) == 2:
        for c, suffix, what in zip(curves, ("_pos", "_neg"), ("v > 0", "v < 0")):
            c.update(suffix=suffix, what=f"the curve for {what}")
    ctx = {**identity_context(model, name), "GUARD": f"FRICGEN_{name.upper()}_ADAPT_H",
           "names": parameter_names(model), "n": params["n"], "n_leak": params["n_leak"],
           "offset": adapts_offset(model),
           "band": f"{adapter.force_band():.4g}", "box": f"{adapter.box:g}",
           "rule": adapter.rule, "rule_enum": params["rule"].name, "curves": curves,
           "describe": curves[0]["describe"] if len(curves) == 1 else
           f"v > 0: {curves[0]['describe']}; v < 0: {curves[1]['describe']}",
           "header": '"fric_fast.h"' if activation_impl == "fast" else '"fric_kernel.h"',
           "theta0": c_array(params["theta0"]), "lo": c_array(params["lo"]),
           "hi": c_array(params["hi"]), "scale": c_array(params["scale"]),
           "rules": [(RULE.member(rule).name,
                      [(f, c_float(v)) for f, v in rule_scalars(adapter.clone(rule=rule)).items()])
                     for rule in RULE.keys],
           "ts_ref": c_float(adapter.ts)}
    env = template_environment()
    return {f"{name}_adapt.h": env.get_template("model_adapt.h.j2").render(ctx),
            f"{name}_adapt.c": env.get_template("model_adapt.c.j2").render(ctx),
            **{fname: runtime_text(fname) for fname in ADAPT_FILES},
            **controller_files()}


def _curve_context(curve, activation_impl: str) -> dict:
    """The template's fields of one curve (a ``Direction``) of the regressor."""
    net = curve.aim
    ctx = {"suffix": "_curve", "what": "the curve", "kind": net.kind,
           "k_in": c_float(curve.scaling.k_in), "v_sat": c_float(curve.v_sat),
           "inv_k_out": c_float(1.0 / curve.scaling.k_out)}
    if isinstance(net, StribeckCurve):
        return {**ctx, "n_basis": net.n_sources, "n": net.n_sources + 2,
                "inv_stribeck": c_array(stribeck_table(net)), "slope": c_float(net.slope),
                "g_expr": STRIBECK_C_SHAPES[activation_impl][net.shape],
                "describe": f"grey-box [F1], {net.n_sources} {net.shape} Stribeck sources"}
    return {**ctx, "n_basis": net.n_hidden, "n": net.n_hidden + 1,
            "input_weights": c_array(net.input_weights), "biases": c_array(net.biases),
            "act_expr": ACTIVATION_C[activation_impl][net.activation],
            "describe": f"{net.n_hidden} {net.activation} neurons"}


def adapt_cdef(name: str) -> str:
    """The cffi declarations of an emitted NAME_adapt.h."""
    return (f"float {name}_regressor(float v, float *phi);\n"
            f"fric_adapt_status_t {name}_adapt_default_params(fric_adapt_params_t *p, "
            "fric_adapt_rule_t rule, float ts);\n")


def build_adapted(model: FrictionModel, name: str = "fm", activation_impl: str = "libm",
                  folder=None):
    """Emit ``model`` with ``--adapt`` into ``folder`` (default: a temporary one, removed after
    the build), compile it and return the cffi module."""
    tmp = folder is None
    folder = Path(tempfile.mkdtemp(prefix="fricgen_adapt_") if tmp else folder)
    try:
        write_all_atomic(folder, {**render(model, name, activation_impl),
                                  **render_adapt(model, name, activation_impl)})
        return build_module(folder, [f"{name}.h", "fric_ctrl.h", "fric_adapt.h", f"{name}_adapt.h"],
                            model_cdef(name, model) + CTRL_CDEF + CDEF + adapt_cdef(name),
                            build_dir=folder / "build")
    finally:
        if tmp:
            shutil.rmtree(folder, ignore_errors=True)


class CAdaptedController:
    """``fric_adapt_ctrl_step`` driven from Python with the settings of ``twin`` (an
    ``AdaptedController``), for the model emitted as ``name``; the interface of
    ``AdaptedController`` (``ts``, ``reset``, ``step``, ``adaptive_parameters``, ``theta_``)."""

    def __init__(self, module, twin: AdaptedController, name: str = "fm"):
        self.module, self.twin, self.name = module, twin, name

    @property
    def ts(self) -> float:
        return self.twin.ts

    def reset(self) -> "CAdaptedController":
        ffi, lib = self.module.ffi, self.module.lib
        self._ctrl = CController(self.module, self.twin.controller).reset()
        self._a = ffi.new("fric_adapt_t *")
        code = lib.fric_adapt_init(self._a, c_params(self.module, self.twin.adapter))
        if code != 0:
            raise ValueError(f"fric_adapt_init rejected the parameters ({code})")
        self._reg = ffi.addressof(lib, f"{self.name}_regressor")
        self._current = ffi.new("float *")
        self.flags_ = 0
        return self

    def step(self, x, v, xd, xd_dot, xd_ddot) -> float:
        self.flags_ = self.module.lib.fric_adapt_ctrl_step(self._a, self._ctrl._c, self._reg, x, v,
                                                           xd, xd_dot, xd_ddot, self._current)
        return self._current[0]

    @property
    def theta_(self):
        return list(self._a.theta)[:self._a.p.n]

    @property
    def adaptive_parameters(self):
        return self._ctrl.adaptive_parameters
