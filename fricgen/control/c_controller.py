"""The C controller (c_runtime/fric_ctrl.c) with an emitted model, loaded through cffi.

``CController`` has the interface of ``AdaptiveBackstepping`` (``ts``, ``reset``, ``step``,
``flags_``, ``adaptive_parameters``), so ``fricgen.simulation.simulate`` runs the C firmware code in the
same closed loop as the Python controller.
"""
from __future__ import annotations

import shutil
import tempfile
from pathlib import Path
from typing import Dict, Optional, Tuple

from .._io import write_all_atomic
from ..codegen import emit
from ..codegen.render import check_overwrite, controller_files
from ..codegen.cbuild import build_module, model_cdef
from ..codegen.twin import force_f32
from ..model import FrictionModel
from ..networks import ElmNetwork, StribeckCurve
from .backstepping import AdaptiveBackstepping
from .c_abi import CDEF, STATUS, param_values


def build_controller(models: Optional[Dict[str, FrictionModel]] = None, folder=None,
                     force: bool = False, sample_time: Optional[float] = None):
    """Emit each model under its C name (the key) and the controller runtime into ``folder``, compile
    them all with cffi, and return the module (``module.lib.NAME_force``,
    ``module.lib.fric_ctrl_step``, ``module.ffi``).

    Files in ``folder`` that fricgen did not write, or read-only ones, are refused before anything
    is written, unless ``force``. Needs a C compiler (``BuildError`` otherwise).

    Parameters
    ----------
    models : dict of str to FrictionModel, optional
        Models to emit, by C name.
    folder : str or pathlib.Path, optional
        Where to emit (default: a temporary folder, removed after the build).
    force : bool
        Overwrite files fricgen did not write.
    sample_time : float, optional
        The controller's sample time, s: NAME_step's of a model with bristles (its NAME_force,
        the steady-state curve, is what the controller calls).

    Returns
    -------
    cffi module

    Examples
    --------
    >>> from fricgen.control import build_controller
    >>> _ = (tmp / "fric_ctrl.c").write_text("/* my own */")
    >>> try:
    ...     build_controller(folder=tmp)
    ... except ValueError:
    ...     print("refused")
    refused
    """
    tmp = folder is None
    folder = Path(tempfile.mkdtemp(prefix="fricgen_ctrl_") if tmp else folder)
    try:
        runtime = controller_files()
        check_overwrite([folder / fname for fname in runtime], force)
        headers, cdefs = [], []
        for name, model in (models or {}).items():
            emit(model, folder, name, force=force,
                 sample_time=sample_time if model.presliding is not None else None)
            headers.append(f"{name}.h")
            cdefs.append(model_cdef(name, model))
        write_all_atomic(folder, runtime)
        return build_module(folder, headers + ["fric_ctrl.h"], "".join(cdefs) + CDEF,
                            build_dir=folder / "build")
    finally:
        if tmp:
            shutil.rmtree(folder, ignore_errors=True)


class CController:
    """The C controller ``fric_ctrl_t`` driven from Python with the parameters of ``settings``; it has
    the interface of ``AdaptiveBackstepping``, so ``simulate`` runs the firmware code in the same
    closed loop.

    The compensation force comes from the C function ``c_friction`` (e.g. "fm_force", through
    ``fric_ctrl_step_fn``), or else from ``settings.compensation`` evaluated in Python at the
    float32 velocity (as the float32 twin does).

    Parameters
    ----------
    module : cffi module
        From ``build_controller``.
    settings : AdaptiveBackstepping
        The controller's parameters.
    c_friction : str, optional
        The emitted model's force function, e.g. "NAME_force".

    Examples
    --------
    >>> from fricgen import AdaptiveBackstepping
    >>> from fricgen.control import CController
    >>> CController(module=None, settings=AdaptiveBackstepping(ts=2e-3)).ts   # before building
    0.002
    """

    def __init__(self, module, settings: AdaptiveBackstepping, c_friction: Optional[str] = None):
        self.module = module
        self.settings = settings
        self.c_friction = c_friction

    @property
    def ts(self) -> float:
        return self.settings.ts

    def params(self):
        """The ``fric_ctrl_params_t`` of ``settings`` (validated in Python first)."""
        p = self.module.ffi.new("fric_ctrl_params_t *")
        for name, value in param_values(self.settings).items():
            setattr(p, name, value)
        return p

    def reset(self) -> "CController":
        ffi, lib = self.module.ffi, self.module.lib
        self._twin = self.settings.clone(dtype="float32").reset()
        self._c = ffi.new("fric_ctrl_t *")
        code = lib.fric_ctrl_init(self._c, self.params())
        if code != STATUS.member("ok").value:
            raise ValueError(f"fric_ctrl_init rejected the parameters: {STATUS.key_of(code)}")
        self._fn = ffi.addressof(lib, self.c_friction) if self.c_friction else None
        self._current = ffi.new("float *")
        self.flags_ = 0
        return self

    def step(self, x, v, xd, xd_dot, xd_ddot) -> float:
        """One ``fric_ctrl_step_fn`` (or ``fric_ctrl_step``): the current; ``flags_`` holds the
        flags it returned."""
        if self._fn is None:
            return self.step_with_force(x, v, xd, xd_dot, xd_ddot,
                                        self.compensation_force(x, v, xd, xd_dot))
        self.flags_ = self.module.lib.fric_ctrl_step_fn(self._c, x, v, xd, xd_dot, xd_ddot,
                                                        self._fn, self._current)
        return self._current[0]

    def compensation_force(self, x, v, xd, xd_dot):
        """F_Fm as the float32 twin evaluates ``settings.compensation`` (in Python)."""
        return self._twin.compensation_force(x, v, xd, xd_dot)

    def step_with_force(self, x, v, xd, xd_dot, xd_ddot, friction) -> float:
        """One ``fric_ctrl_step`` with the force given: the current; ``flags_`` as ``step``."""
        self.flags_ = self.module.lib.fric_ctrl_step(self._c, x, v, xd, xd_dot, xd_ddot,
                                                     float(friction), self._current)
        return self._current[0]

    @property
    def adaptive_parameters(self):
        return float(self._c.m_o_hat), float(self._c.k_hat)


def float32_twin(settings: AdaptiveBackstepping, model: Optional[FrictionModel] = None,
                 activation_impl: str = "libm") -> AdaptiveBackstepping:
    """The float32 Python twin of ``CController(module, settings, "NAME_force")``: the controller
    in float32 with the model evaluated as the emitted ``NAME_force`` (``fricgen.twin``;
    ``activation_impl`` as given to ``emit``)."""
    if model is None:
        return settings.clone(dtype="float32")
    return settings.clone(dtype="float32",
                          compensation=lambda v: force_f32(model, v, activation_impl))


def c_controllers(compensation: Dict[str, Optional[object]], settings: AdaptiveBackstepping,
                  folder=None) -> Dict[str, CController]:
    """One C controller per compensation variant (as ``compare`` makes Python ones): friction models
    (ELM or [F1]) are emitted as C (``VARIANT_force``, through a function pointer); other
    compensations (none, the true friction, a fuzzy model) are evaluated in Python and passed to
    ``fric_ctrl_step`` as a float.

    Parameters
    ----------
    compensation : dict of str to callable or None
        Variant -> F_Fm(v) in N.
    settings : AdaptiveBackstepping
        The parameters shared by every variant.
    folder : str or pathlib.Path, optional
        Where to emit and build (default: a temporary folder).

    Returns
    -------
    dict of str to CController

    Examples
    --------
    >>> from fricgen import AdaptiveBackstepping
    >>> from fricgen.control import c_controllers
    >>> _ = (tmp / "fric_ctrl.h").write_text("/* my own */")
    >>> try:                                   # refused before anything is written or compiled
    ...     c_controllers({"none": None}, AdaptiveBackstepping(), folder=tmp)
    ... except ValueError:
    ...     print("refused")
    refused
    """

    emitted = {name: c_function(comp) for name, comp in compensation.items()}
    models = {name: e[0] for name, e in emitted.items() if e is not None}
    module = build_controller(models, folder, sample_time=settings.ts)
    return {name: CController(module, settings.clone(compensation=comp),
                              f"{name}_{emitted[name][1]}" if name in models else None)
            for name, comp in compensation.items()}


def c_function(compensation) -> Optional[Tuple[FrictionModel, str]]:
    """The model a compensation computes in C and the suffix of its function: a model (ELM or
    [F1]) itself, "force", or its bound ``force_with_offset``, "force_with_offset"; None for
    anything else."""
    model = getattr(compensation, "__self__", compensation)
    if not (isinstance(model, FrictionModel) and isinstance(model.aim, (ElmNetwork, StribeckCurve))):
        return None
    if compensation is model:
        return model, "force"
    if getattr(compensation, "__func__", None) is FrictionModel.force_with_offset:
        return model, "force_with_offset"
    return None
