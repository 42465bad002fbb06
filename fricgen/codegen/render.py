"""Render a FrictionModel as fixed-size C (templates/ + c_runtime/): [F3], curves of [F7] or [F1]."""
from __future__ import annotations

import math
from pathlib import Path
from typing import Dict, List, Optional, Tuple, Union


import numpy as np

from .._io import read_only
from ..c_literal import c_array, c_float
from ..effects.presliding import least_level
from ..errors import ModelError, UsageError
from .cogging_table import CoggingTable
from ..model import FrictionModel
from ..networks import ElmNetwork, StribeckCurve
from .context import (GENERATED_MARKER, PACKAGE_MARKER, PACKAGE_NAMES, RUNTIME_MARKER,
                      VERSION_HEADER, axis_context, effects_context, emit_options, identity_context,
                      render_source_and_header, runtime_text)
from .cost import INSTRUCTIONS_MARGIN, TARGETS, instructions_max
from .fast_sigmoid import check_fast_model, fast_tables
from .fixed_table import render_fixed_table
from .fixedpoint import render_fixed
from .parity import check_float32
from .twin import stribeck_table

#: The one header that fixes the float semantics (no -ffast-math, no contraction), included by
#: every float NAME.c and every runtime source; part of each runtime below.
FLOAT_HEADER = "fric_float.h"
#: The runtime headers every float model with libm needs beside NAME.h and NAME.c.
RUNTIME_HEADERS = (FLOAT_HEADER, VERSION_HEADER, "fric_kernel.h")
#: The libm sources (one per kernel, see fric_kernel.h) each activation of [F8] or shape of
#: [F2] calls: a model's folder gets only those it uses.
KERNEL_SOURCES = {"sigmoid": ("fric_elm_sigmoid.c",), "sine": ("fric_elm_sine.c",),
                  "rbf": ("fric_elm_rbf.c",), "multiquadric": ("fric_elm_multiquadric.c",),
                  "gauss": ("fric_exp_neg.c",), "exponential": ("fric_exp_neg.c",), "rational": ()}
#: The runtime of a sigmoid ELM (the default model) with libm; ``runtime_files`` for any model.
RUNTIME_FILES = RUNTIME_HEADERS + KERNEL_SOURCES["sigmoid"]
#: The runtime of ``--activation-impl fast`` in place of the libm one, see fric_fast.h: no libm.
FAST_RUNTIME_FILES = (FLOAT_HEADER, VERSION_HEADER, "fric_fast.h", "fric_fast.c")
#: The bytes of a saved blob (CRC-32, little-endian words), see fric_bytes.h: the cogging map's
#: and the adaptation's.
BYTES_FILES = ("fric_bytes.h", "fric_bytes.c")
#: The float controller runtime (section 6) copied beside every float model, see fric_ctrl.h;
#: its square root is fric_sqrt.c's (no libm, the bits of sqrtf).
CONTROLLER_FILES = (FLOAT_HEADER, VERSION_HEADER, "fric_sqrt.h", "fric_sqrt.c", "fric_ctrl.h",
                    "fric_ctrl.c")


def runtime_files(model: FrictionModel, activation_impl: str = "libm") -> Tuple[str, ...]:
    """The runtime files the float C of ``model`` calls: FAST_RUNTIME_FILES, or RUNTIME_HEADERS
    and the kernel sources of its curves' activations or shapes (KERNEL_SOURCES); BYTES_FILES
    beside them for a model with a cogging map (NAME_cogging_map_save and _restore).

    Parameters
    ----------
    model : FrictionModel
        A model with ELM or grey-box curves.
    activation_impl : str
        "libm" or "fast" (``--activation-impl``).

    Returns
    -------
    tuple of str
        File names in c_runtime/.

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.codegen import runtime_files
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5, random_state=0))
    >>> "fric_elm_sigmoid.c" in runtime_files(model), "fric_elm_sine.c" in runtime_files(model)
    (True, False)
    """
    blob = BYTES_FILES if model.cogging_map is not None else ()
    if activation_impl == "fast":
        return FAST_RUNTIME_FILES + blob
    sources = [f for curve in model.directions for f in KERNEL_SOURCES[
        curve.aim.shape if isinstance(curve.aim, StribeckCurve) else curve.aim.activation]]
    return RUNTIME_HEADERS + tuple(dict.fromkeys(sources)) + blob


#: The shape g(u) of [F2] at u = x / xs in the emitted grey-box C, by implementation.
STRIBECK_C_SHAPES = {
    "libm": {"gauss": "fric_exp_neg_f32(u * u)", "exponential": "fric_exp_neg_f32(u)",
             "rational": "1.0f / (1.0f + u)"},
    "fast": {"gauss": "fric_exp_neg_fast_f32(u * u)", "exponential": "fric_exp_neg_fast_f32(u)",
             "rational": "1.0f / (1.0f + u)"},
}
#: The header each kind of curve needs in NAME.c, by implementation.
CURVE_HEADERS = {("elm", "libm"): '"fric_kernel.h"', ("elm", "fast"): '"fric_fast.h"',
                 ("stribeck", "libm"): '"fric_kernel.h"', ("stribeck", "fast"): '"fric_fast.h"'}


def curve_context(curve, name: str, activation_impl: str, negative: bool = False) -> dict:
    """What templates/curve.c.j2 needs for one curve of [F3] (a model, or a ``Direction``):
    its C symbols (``NAME_negative_...``, ``NAME_aim_negative`` and ``..._NEGATIVE`` macros for
    the curve for v < 0) and its tables and constants, every number a checked C literal; an
    ELM [F7] or the grey-box [F1]."""
    net, suffix = curve.aim, "_NEGATIVE" if negative else ""
    ctx = {"kind": net.kind, "sym": f"{name}_negative" if negative else name,
           "aim_fn": f"{name}_aim_negative" if negative else f"{name}_aim",
           "v_sat_macro": f"{name.upper()}_V_SAT{suffix}",
           "header": CURVE_HEADERS[net.kind, activation_impl],
           "k_in": c_float(curve.scaling.k_in), "inv_k_out": c_float(1.0 / curve.scaling.k_out),
           "viscous": c_float(curve.viscous), "v_sat": c_float(curve.v_sat)}
    if isinstance(net, StribeckCurve):
        return {**ctx, "size": f"{name.upper()}_N_SOURCES{suffix}", "n": net.n_sources,
                "shape": net.shape, "what": "grey-box", "equation": "[F1]",
                "describe": f"grey-box [F1], {net.n_sources} {net.shape} Stribeck sources",
                "g_expr": STRIBECK_C_SHAPES[activation_impl][net.shape],
                "inv_stribeck": c_array(stribeck_table(net)), "amplitudes": c_array(net.amplitudes),
                "offset": c_float(net.offset), "slope": c_float(net.slope)}
    ctx.update(size=f"{name.upper()}_N_HIDDEN{suffix}", n=net.n_hidden, what="network",
               equation="[F7]", describe=f"{net.n_hidden} {net.activation} neurons",
               kernel=f"fric_elm_{net.activation}_f32", tables_note="",
               input_weights=c_array(net.input_weights), biases=c_array(net.biases),
               output_weights=c_array(net.output_weights))
    if activation_impl == "fast":
        check_fast_model(curve)
        w, b, _ = fast_tables(net)  # t = w' x + b' = -log2(e) (w x + b), see fric_fast.h
        ctx.update(kernel="fric_elm_sigmoid_fast_f32", input_weights=c_array(w), biases=c_array(b),
                   tables_note="w and b times -log2(e): t = w x + b, sigma = 1 / (1 + 2^t)")
    return ctx


def template_context(model: FrictionModel, name: str, activation_impl: str = "libm") -> dict:
    """Everything templates/model.c.j2 and model.h.j2 need: the curve for v >= 0 (``positive``, the
    only one of a symmetric model) and the curve for v < 0 (``negative``, None unless the model is
    asymmetric), each an ELM or the grey-box [F1], with the constants of [F3].

    Parameters
    ----------
    model : FrictionModel
        The model to emit.
    name : str
        The C name (NAME.h, NAME_force).
    activation_impl : {"libm", "fast"}
        How the C evaluates the activation.

    Returns
    -------
    dict

    Examples
    --------
    >>> import fricgen
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5, random_state=0),
    ...                                   name="axis_x")
    >>> from fricgen.codegen import template_context
    >>> context = template_context(model, "axis_x")
    >>> context["positive"]["kind"], context["negative"] is None
    ('elm', True)
    """
    curves = [curve_context(c, name, activation_impl, negative=k == 1)
              for k, c in enumerate(model.directions)]
    cost = instructions_max([c.aim for c in model.directions], activation_impl)
    return {**identity_context(model, name), "positive": curves[0],
            "instr_max": [(TARGETS[target], n) for target, n in cost.items()],
            "instr_margin": f"{INSTRUCTIONS_MARGIN:.0%}",
            "negative": curves[1] if len(curves) == 2 else None,
            "includes": list(dict.fromkeys(c["header"] for c in curves)),
            **axis_context(model),
            **effects_context(model, name),  # effects, effects_not_in_c: NAME_force_xv
            "cogging": None if model.cogging_map is None else CoggingTable.of(model.cogging_map).context(),
            "band": band_context(model), "presliding": None,
            "inputs": inputs_context(model, activation_impl)}


#: exp(-y) in the pre-sliding update, by ``--activation-impl``, and the header that declares it.
PRESLIDING_EXP = {"libm": ("fric_exp_neg_inline_f32", '"fric_kernel.h"'),
                  "fast": ("fric_exp_neg_fast_f32", '"fric_fast.h"')}


def inputs_context(model: FrictionModel, activation_impl: str) -> Optional[dict]:
    """NAME_force_lt's constants (None for a model without ``inputs``)."""
    inputs = model.inputs
    if inputs is None:
        return None
    units = model.units
    exp_fn, header = PRESLIDING_EXP[activation_impl]
    load = temperature = None
    if inputs.load is not None:
        load = {"driving": c_float(inputs.load.driving), "back_driving": c_float(inputs.load.back_driving),
                "largest": c_float(inputs.load.largest)}
    if inputs.temperature is not None:
        t = inputs.temperature
        temperature = {"reference": c_float(t.reference), "levels": c_float(t.levels),
                       "viscous": c_float(t.viscous), "low": c_float(t.span[0]),
                       "high": c_float(t.span[1])}
    return {"load": load, "temperature": temperature, "exp_fn": exp_fn, "header": header,
            "force_unit": units.force, "speed_unit": units.speed,
            "load_word": units.effort}


def band_context(model: FrictionModel) -> Optional[dict]:
    """NAME_compensation's band (None for a model without ``velocity_band``, and for one with
    inputs, whose compensation would need them: ``NAME_force_lt``)."""
    if model.velocity_band is None or model.inputs is not None:
        return None
    source = model.training.get("velocity_band_from", "model.json velocity_band")
    return {"value": c_float(model.velocity_band), "inverse": c_float(1.0 / model.velocity_band),
            "twice": c_float(2.0 * model.velocity_band),
            "source": source}


def presliding_context(model: FrictionModel, activation_impl: str, sample_time: Optional[float]) -> Optional[dict]:
    """NAME_step's constants at the sample time (default: the training log's), or None for a
    model without bristles; ``ModelError`` for a sample time given to one without."""
    bristles = model.presliding
    if bristles is None:
        if sample_time is not None:
            raise ModelError("a sample time sets NAME_step of a model with pre-sliding "
                             "(train --dynamic); this model has none")
        return None
    dt = sample_time if sample_time is not None else model.training.get("log", {}).get("sample_time")
    if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
        raise ModelError("the model's pre-sliding needs the controller's sample time: give "
                         "--sample-time (s); the model records no log sample time")
    exp_fn, header = PRESLIDING_EXP[activation_impl]
    return {"stiffness": c_float(bristles.stiffness), "damping": c_float(bristles.damping),
            "stiffness_dt": c_float(bristles.stiffness * dt), "dt": c_float(dt),
            "damping_per_dt": c_float(bristles.damping / dt),
            "least_level": c_float(max(least_level(model.stribeck), 1e-30)), "exp_fn": exp_fn,
            "inv_fade": None if bristles.damping_speed is None else c_float(1.0 / bristles.damping_speed),
            "header": header, "sample_time": float(dt)}


#: ``--activation-impl``: libm's expf (the default) or the fast sigmoid without libm (fric_fast.c).
ACTIVATION_IMPLS = ("libm", "fast")
#: ``--dtype``: float, or the fixed-point models of fricgen.fixedpoint (no FPU needed).
DTYPES = ("float", "q15", "q31")


#: The largest |value| the emitted float32 C may meet inside [F7] and [F3]: 1 % of FLT_MAX.
FLOAT32_HEADROOM = 3.4e36


def check_float32_range(model: FrictionModel) -> None:
    """``ModelError`` unless [F7] cannot overflow float32 for any input: the bound
    sum_k |beta_k| max |act| over x in [0, 1], and that bound over K_out, stay below
    FLOAT32_HEADROOM (a table of 3e38 would give inf in C but finite forces in Python);
    for each curve of an asymmetric model."""
    for curve in model.directions:
        _check_curve_float32_range(curve)


def _check_curve_float32_range(model) -> None:
    net = model.aim
    if isinstance(net, StribeckCurve):                   # 0 < g <= 1 for x >= 0
        bound = abs(net.offset) + abs(net.slope) + float(np.sum(np.abs(net.amplitudes)))
        force = bound / model.scaling.k_out
        if not (bound <= FLOAT32_HEADROOM and force <= FLOAT32_HEADROOM):
            raise ModelError(f"the curve's output can reach {max(bound, force):.3g}, beyond the "
                             f"float32 C's range ({FLOAT32_HEADROOM:.3g}); it cannot be emitted")
        return
    z_ends = np.abs(np.stack([net.biases, net.input_weights + net.biases]))
    largest = np.sqrt(1.0 + z_ends.max(axis=0) ** 2) if net.activation == "multiquadric" else 1.0
    with np.errstate(over="ignore"):
        bound = float(np.sum(np.abs(net.output_weights) * largest))
        force = bound / model.scaling.k_out
    if not (bound <= FLOAT32_HEADROOM and force <= FLOAT32_HEADROOM):
        raise ModelError(f"the network's output can reach {max(bound, force):.3g}, beyond the "
                         f"float32 C's range ({FLOAT32_HEADROOM:.3g}); it cannot be emitted")


#: The fields of a grey-box curve's training record (``training.standard_errors``, and
#: ``training.negative.standard_errors``) that hold each source's standard errors.
SOURCE_ERRORS = (("amplitudes_newton", "f_s - f_c"), ("stribeck_m_per_s", "v_s"))


def check_determined(model: FrictionModel) -> None:
    """``ModelError`` naming the first source of [F1] whose amplitude or Stribeck velocity the
    training data did not determine: its standard error in the model's training record is
    infinite (null in model.json). Such a term is noise in the ISR, and its exponential can
    underflow on every call; training drops it (``fricgen.fit.stribeck.drop_undetermined``)."""
    records = [model.training, model.training.get("negative")]
    for side, curve, record in zip(("", "v < 0 "), model.directions, records):
        net = curve.aim
        if not isinstance(net, StribeckCurve) or not isinstance(record, dict):
            continue
        errors = record.get("standard_errors")
        if not isinstance(errors, dict):
            continue
        for field_name, what in SOURCE_ERRORS:
            values = errors.get(field_name)
            values = values if isinstance(values, list) else []
            for k, se in enumerate(values[:net.n_sources]):
                if not (isinstance(se, (int, float)) and math.isfinite(se)):
                    raise ModelError(
                        f"source {k + 1} of the {side}grey-box curve (v_s = "
                        f"{net.stribeck[k] / curve.scaling.k_in:.3g} m/s) has a {what} that the "
                        "training data did not determine (no finite standard error in its "
                        "training record); it cannot be emitted: retrain, which drops such sources")


def controller_files() -> Dict[str, str]:
    """The float controller runtime of section 6 (CONTROLLER_FILES: fric_ctrl.{h,c}, its square
    root fric_sqrt.{h,c} and the headers they include), by file name.

    Returns
    -------
    dict of str to str
        File name -> C text.

    Examples
    --------
    >>> from fricgen.codegen import controller_files
    >>> sorted(controller_files())
    ['fric_ctrl.c', 'fric_ctrl.h', 'fric_float.h', 'fric_sqrt.c', 'fric_sqrt.h', 'fric_version.h']
    """
    return {fname: runtime_text(fname) for fname in CONTROLLER_FILES}


def render(model: FrictionModel, name: Optional[str] = None, activation_impl: str = "libm",
           dtype: str = "float", with_controller: bool = False,
           v_max: Optional[float] = None, adapt: bool = False,
           sample_time: Optional[float] = None) -> Dict[str, str]:
    """All files of the emitted C folder, by file name: NAME.h, NAME.c and the runtime, plus the
    controller runtime (fric_ctrl.h, fric_ctrl.c) ``with_controller``. Nothing is written.

    Parameters
    ----------
    model : FrictionModel
        The model whose [F3] the C evaluates.
    name : str, optional
        The C name (default: the model's).
    activation_impl : {"libm", "fast"}
        The activation: the C library's, or the fast approximation.
    dtype : {"float", "q15", "q31"}
        float32, or fixed point.
    with_controller : bool
        Add the controller runtime of section 6 (float only).
    v_max : float, optional
        The speed (m/s) a fixed-point input must cover (default: the model's training speeds);
        fixed point only.
    adapt : bool
        Record in NAME_EMIT_OPTIONS that online adaptation is emitted beside the model (its
        files come from ``fricgen.control.render_adapt``; float only).
    sample_time : float, optional
        The sample time (s) of NAME_step, for a model with pre-sliding (default: its training
        log's).

    Returns
    -------
    dict of str to str
        File name -> text; ``ModelError`` for an option that does not apply.

    Examples
    --------
    >>> import fricgen
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5, random_state=0),
    ...                                   name="axis_x")
    >>> sorted(fricgen.render(model))
    ['axis_x.c', 'axis_x.h', 'fric_elm_sigmoid.c', 'fric_float.h', 'fric_kernel.h', 'fric_version.h']
    """
    name = model.name if name is None else name
    if v_max is not None and dtype == "float":
        raise ModelError("v_max sets the input range of fixed point (--dtype q15 or q31); float "
                         "takes any speed")
    if with_controller and dtype != "float":
        raise ModelError(f"the controller runtime is float; it cannot be emitted with --dtype {dtype}")
    if activation_impl not in ACTIVATION_IMPLS:
        raise ModelError(f"activation_impl must be one of {list(ACTIVATION_IMPLS)}, got {activation_impl!r}")
    if dtype not in DTYPES:
        raise ModelError(f"dtype must be one of {list(DTYPES)}, got {dtype!r}")
    if model.inputs is not None and (dtype != "float" or with_controller or adapt):
        what = f"--dtype {dtype}" if dtype != "float" else ("--adapt" if adapt else "the controller runtime")
        raise ModelError(f"{what} runs the friction of v alone; this model depends on the "
                         f"{' and the '.join(model.inputs.names)} (emit it with --dtype float: "
                         "NAME_force_lt)")
    if dtype != "float":
        grey_box = all(isinstance(c.aim, StribeckCurve) for c in model.directions)
        if model.negative is not None and not grey_box:
            raise ModelError(f"--dtype {dtype} emits an asymmetric model whose curves are both "
                             "grey-box [F1]; one of this one's is not (emit it with --dtype float)")
        if model.cogging_map is not None:
            raise ModelError(f"--dtype {dtype} does not emit the cogging map; --dtype float "
                             "emits it in float, q15 and q31 (NAME_cogging, NAME_cogging_q15, "
                             "NAME_cogging_q31)")
        if model.presliding is not None:
            raise ModelError(f"--dtype {dtype} does not emit pre-sliding; --dtype float does "
                             "(NAME_step)")
        if model.effects:
            raise ModelError(f"--dtype {dtype} does not emit effects; this model has "
                             f"{len(model.effects)} (emit it with --dtype float)")
        if grey_box:
            check_determined(model)
            return render_fixed_table(model, name, dtype, v_max=v_max)
        return render_fixed(model, name, dtype, v_max=v_max)
    for curve in model.directions:
        if not isinstance(curve.aim, (ElmNetwork, StribeckCurve)):
            raise ModelError(f"emit supports ELM and grey-box models; this model's AIM is "
                             f"{type(curve.aim).__name__}")
    check_float32_range(model)
    check_determined(model)
    ctx = template_context(model, name, activation_impl)
    ctx["presliding"] = presliding_context(model, activation_impl, sample_time)
    for part in ("presliding", "inputs"):
        if ctx[part] is not None and ctx[part]["header"] not in ctx["includes"]:
            ctx["includes"].append(ctx[part]["header"])
    if ctx["cogging"] is not None:                  # the map's blob (NAME_cogging_map_save)
        ctx["includes"] += ['"fric_bytes.h"', "<stddef.h>"]
    ctx["emit_options"] = emit_options(dtype=dtype, activation_impl=activation_impl,
                                       with_controller=with_controller, adapt=adapt,
                                       **({} if ctx["presliding"] is None else
                                          {"sample_time": ctx["presliding"]["sample_time"]}))
    check_float32(model, activation_impl)
    files = render_source_and_header(ctx, name, "model")
    for fname in runtime_files(model, activation_impl):   # also for grey-box curves
        files[fname] = runtime_text(fname)
    if with_controller:
        files.update(controller_files())
    return files


def _head(path: Path) -> List[str]:
    """The first four lines of the file ``path`` (none if it cannot be read)."""
    try:
        with open(path, errors="replace") as fh:
            return [line for _, line in zip(range(4), fh)]
    except OSError:
        return []


def _generated(head: List[str]) -> bool:
    return any(line.startswith(GENERATED_MARKER) for line in head)


def generated_models(folder: Union[str, Path]) -> List[str]:
    """The names of the models generated into ``folder`` before: each NAME.h whose head comment holds
    the ``GENERATED_MARKER`` line.

    Parameters
    ----------
    folder : str or pathlib.Path
        The folder to look in.

    Returns
    -------
    list of str

    Examples
    --------
    >>> import fricgen
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5, random_state=0),
    ...                                   name="axis_x")
    >>> from fricgen.codegen import generated_models
    >>> _ = fricgen.emit(model, tmp / "gen")
    >>> generated_models(tmp / "gen")
    ['axis_x']
    """
    return [header.stem for header in sorted(Path(folder).glob("*.h"))
            if header.is_file() and _generated(_head(header))]


def written_by_fricgen(path: Union[str, Path]) -> bool:
    """Whether the file ``path`` is one fricgen emits: generated (its head comment holds the
    ``GENERATED_MARKER`` line), a copy of the C runtime (it begins with ``RUNTIME_MARKER``), or
    one of the build files of ``fricgen.codegen.package`` (a head line holds PACKAGE_MARKER)."""
    path = Path(path)
    head = _head(path)
    return (_generated(head) or (bool(head) and head[0].startswith(RUNTIME_MARKER))
            or (path.name in PACKAGE_NAMES and any(PACKAGE_MARKER in line for line in head)))


def check_overwrite(paths, force: bool = False, option: str = "-o", written=None) -> None:
    """``UsageError`` naming the first of ``paths`` that exists and that fricgen did not write, or
    that is read-only, unless ``force``: the C is emitted over its own files only.

    Parameters
    ----------
    paths : iterable of str or pathlib.Path
        The files about to be written.
    force : bool
        Skip the check.
    option : str
        The command-line option the message names.
    written : callable, optional
        path -> bool, whether fricgen wrote the file (default: ``written_by_fricgen``).

    Returns
    -------
    None

    Examples
    --------
    >>> from fricgen.codegen import check_overwrite
    >>> _ = (tmp / "mine.h").write_text("/* my own */")
    >>> try:
    ...     check_overwrite([tmp / "mine.h"])
    ... except ValueError:
    ...     print("refused")
    refused
    >>> check_overwrite([tmp / "mine.h"], force=True) is None
    True
    """
    written = written or written_by_fricgen
    if force:
        return
    for path in map(Path, paths):
        if not path.is_file():
            continue
        if not written(path):
            why = ("was not written by fricgen (no 'Generated by fricgen' line)"
                   if written is written_by_fricgen else "was not written by fricgen")
        elif read_only(path):
            why = "is read-only"
        else:
            continue
        raise UsageError(f"{option} {path}: {why}; refusing to overwrite it (--force to do so)")


def check_name_in_folder(out_dir: Union[str, Path], name: str) -> None:
    """Refuse ``name`` where a model generated before has a name that differs only by case: where
    the file system ignores case one NAME.h overwrites the other, and everywhere their include
    guards and NAME_ macros coincide.

    Parameters
    ----------
    out_dir : str or pathlib.Path
        The folder to emit into.
    name : str
        The new model's C name.

    Returns
    -------
    None
        ``ModelError`` when the folder holds such a model.

    Examples
    --------
    >>> import fricgen
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5, random_state=0),
    ...                                   name="axis_x")
    >>> from fricgen.codegen import check_name_in_folder
    >>> _ = fricgen.emit(model, tmp / "case")
    >>> try:
    ...     check_name_in_folder(tmp / "case", "AXIS_X")
    ... except fricgen.ModelError:
    ...     print("refused")
    refused
    """
    if not Path(out_dir).is_dir():
        return
    for other in generated_models(out_dir):
        if other != name and other.lower() == name.lower():
            raise ModelError(f"{out_dir} already holds the generated model {other!r}, whose name "
                             f"differs from {name!r} only by case; choose another name or folder")
