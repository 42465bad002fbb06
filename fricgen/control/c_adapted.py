"""The adaptation runtime (c_runtime/fric_adapt.c) with an emitted model's regressor, through
cffi: ``CAdaptedController`` runs ``fric_adapt_ctrl_step`` in the closed loops of
``fricgen.control.loop.simulate``, beside its float32 twin ``AdaptedController``."""
from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

from .._io import write_all_atomic
from ..codegen.cbuild import build_module, model_cdef
from ..codegen.render import render
from ..model import FrictionModel
from .adaptation import FLAGS, MAX_PARAMS, RULE, AdaptedController
from .c_abi import CDEF as CTRL_CDEF
from .c_controller import CController
from ..codegen.adapt import adapt_params

#: The cffi declarations of fric_adapt.h (tests/test_adaptation_c.py checks them against it).
CDEF = (RULE.cdef() + FLAGS.cdef()
        + "typedef enum { FRIC_ADAPT_OK_INIT = 0, FRIC_ADAPT_ERR_NULL = -1, "
          "FRIC_ADAPT_ERR_PARAM = -2 } fric_adapt_status_t;\n"
        + "typedef float (*fric_adapt_regressor_fn)(float v, float *phi);\n"
        + "typedef struct {\n    unsigned int n;\n    fric_adapt_rule_t rule;\n"
        + "".join(f"    float {a}[{MAX_PARAMS}];\n" for a in ("theta0", "lo", "hi", "scale"))
        + "".join(f"    float {s};\n" for s in ("forgetting", "p0", "trace_max", "gain", "leak",
                                                 "v_dead", "e_dead"))
        + "} fric_adapt_params_t;\n"
        + f"typedef struct {{\n    fric_adapt_params_t p;\n    float theta[{MAX_PARAMS}];\n"
          f"    float P[{MAX_PARAMS * MAX_PARAMS}];\n    float scale2[{MAX_PARAMS}];\n"
          "    float error;\n    float v_prev;\n    float i_prev;\n    int held;\n"
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
          "float *current);\n")


def adapt_cdef(name: str) -> str:
    """The cffi declarations of an emitted NAME_adapt.h."""
    return (f"float {name}_regressor(float v, float *phi);\n"
            f"void {name}_adapt_default_params(fric_adapt_params_t *p);\n")


def build_adapted(model: FrictionModel, name: str = "fm", activation_impl: str = "libm",
                  folder=None):
    """Emit ``model`` with ``--adapt`` into ``folder`` (default: a temporary one, removed after
    the build), compile it and return the cffi module."""
    tmp = folder is None
    folder = Path(tempfile.mkdtemp(prefix="fricgen_adapt_") if tmp else folder)
    try:
        write_all_atomic(folder, render(model, name, activation_impl, adapt=True))
        return build_module(folder, [f"{name}.h", "fric_ctrl.h", "fric_adapt.h", f"{name}_adapt.h"],
                            model_cdef(name) + CTRL_CDEF + CDEF + adapt_cdef(name),
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
        p = ffi.new("fric_adapt_params_t *")
        for field, value in adapt_params(self.twin.adapter).items():
            if isinstance(value, list):
                getattr(p, field)[0:len(value)] = value
            else:
                setattr(p, field, getattr(value, "value", value))
        self._a = ffi.new("fric_adapt_t *")
        code = lib.fric_adapt_init(self._a, p)
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
