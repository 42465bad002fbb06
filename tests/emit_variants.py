"""Every kind of C folder ``fricgen emit`` writes, for the static checks of tests/test_static_c.py:
an ELM and a grey-box [F1] model in each implementation (float with libm or the fast sigmoid,
q15 and q31), an asymmetric model, a model with effects, two models in one folder, a model with
pre-sliding and a compensation band (libm, and fast asymmetric), a model with a cogging map (its
RAM map and blob), the controller, the adaptation runtime (--adapt), and the whole runtime
c_runtime/ with every kernel."""
import shutil
from dataclasses import replace

from fricgen import codegen
from fricgen._io import resource_dir
from fricgen.control.c_adapted import render_adapt
from fricgen.effects import CoggingMap, with_effects
from fricgen.effects.presliding import Bristles
from fricgen.firmware.flag_matrix import table1_greybox
from fricgen.model import FrictionModel

from test_diagnose_tables import TABLE_EFFECTS
from test_effects import OTHER_EFFECTS, XV_EFFECTS


def _emit_adapt(model, folder, impl):
    """What ``fricgen emit --adapt --activation-impl IMPL`` writes (the C files)."""
    codegen.emit(model, folder, "fm", activation_impl=impl, with_controller=True)
    for fname, text in render_adapt(model, "fm", impl).items():
        (folder / fname).write_text(text)


def emit_every_variant(root, bench, model10, axis2_model):
    """Emit every variant into a folder of its own under ``root``; return {variant: folder}."""
    grey = table1_greybox(bench, "gauss")
    grey_exp = table1_greybox(bench, "exponential", name="gx")
    grey_rat = table1_greybox(bench, "rational", name="gr")
    asym = FrictionModel.from_directions(model10.positive, grey.positive, name="fa")
    slow = replace(grey, presliding=Bristles(1e5, 300.0, 2e-3), velocity_band=1e-3)    # --dynamic
    cogging = replace(model10, cogging_map=CoggingMap(
        period=0.032, harmonics=(1, 2, 6), sine=(0.3, 0.1, 0.05), cosine=(0.1, 0.0, 0.02),
        sine_se=(0.01,) * 3, cosine_se=(0.01,) * 3))                                  # --cogging
    jobs = {
        "elm_libm": lambda d: codegen.emit(model10, d, "fm", activation_impl="libm"),
        "elm_fast": lambda d: codegen.emit(model10, d, "fm", activation_impl="fast"),
        "elm_q15": lambda d: codegen.emit(model10, d, "fm", dtype="q15"),
        "elm_q31": lambda d: codegen.emit(model10, d, "fm", dtype="q31"),
        "grey_libm": lambda d: [codegen.emit(m, d, m.name, activation_impl="libm")
                                for m in (grey, grey_exp, grey_rat)],
        "grey_fast": lambda d: [codegen.emit(m, d, m.name, activation_impl="fast")
                                for m in (grey, grey_exp, grey_rat)],
        "grey_q15": lambda d: codegen.emit(grey, d, "gb", dtype="q15"),
        "grey_q31": lambda d: codegen.emit(grey_exp, d, "gx", dtype="q31"),
        "asym_q15": lambda d: codegen.emit(replace(FrictionModel.from_directions(
            grey.positive, grey_exp.positive, name="ga"), velocity_band=1e-3), d, "ga", dtype="q15"),
        "asym_libm": lambda d: codegen.emit(asym, d, "fa", activation_impl="libm"),
        "asym_fast": lambda d: codegen.emit(asym, d, "fa", activation_impl="fast"),
        "effects": lambda d: [codegen.emit(with_effects(model10, XV_EFFECTS + OTHER_EFFECTS), d, "fx"),
                              codegen.emit(with_effects(grey, TABLE_EFFECTS), d, "tx", activation_impl="fast")],
        "two_axes_float": lambda d: [codegen.emit(model10, d, "fm", activation_impl="fast"),
                                     codegen.emit(axis2_model, d, "axis2", activation_impl="libm")],
        "two_axes_fixed": lambda d: [codegen.emit(model10, d, "fm", dtype="q15"),
                                     codegen.emit(axis2_model, d, "axis2", dtype="q31")],
        "controller_libm": lambda d: codegen.emit(model10, d, "fm", with_controller=True),
        "controller_fast": lambda d: codegen.emit(grey, d, "gb", activation_impl="fast",
                                                  with_controller=True),
        "adapt_elm": lambda d: _emit_adapt(model10, d, "libm"),
        "adapt_grey": lambda d: _emit_adapt(grey, d, "fast"),
        "slow_speeds": lambda d: [codegen.emit(slow, d, "sl", activation_impl="libm", sample_time=1e-4),
                                  codegen.emit(replace(slow, negative=grey_exp.positive), d, "sf",
                                               activation_impl="fast", sample_time=1e-4)],
        "cogging": lambda d: [codegen.emit(cogging, d, "cg", activation_impl="libm"),
                              codegen.emit(cogging, d, "cf", activation_impl="fast")],
        "runtime": lambda d: shutil.copytree(resource_dir("c_runtime"), d),
    }
    folders = {}
    for variant, job in jobs.items():
        folder = root / variant
        if variant != "runtime":
            folder.mkdir(parents=True)
        job(folder)
        folders[variant] = folder
    return folders
