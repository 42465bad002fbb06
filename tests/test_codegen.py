"""Emitted C: exact literals, strict-warning builds, and parity with Python through cffi."""
import re
import shutil
import subprocess

import numpy as np
import pytest

from conftest import (AXIS_PAIRS, CTYPES, assert_builds_strictly, emit_impl, fit_model, force_fn,
                      impl_inputs, impl_twin)
from fricgen import codegen
from fricgen.c_literal import c_float
from fricgen.codegen import parity
from fricgen.codegen.cbuild import STRICT_WARNINGS, build, build_model
from fricgen.codegen.context import GENERATED_MARKER
from fricgen.networks.elm import ACTIVATIONS
from fricgen.fit.elm import PARITY, float32_error
from fricgen.model import FrictionModel, ModelError
from fricgen.networks import ElmNetwork
from fricgen.codegen.twin import force_f32

EPS32 = float(np.finfo(np.float32).eps)
CC = shutil.which("gcc") or shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler")

#: The model kinds of the parity proof: scheme x solver, over M in {1, 6, 10, 50}.
KINDS = {
    "standard": dict(scheme="standard", solver="pinv"),
    "enlarged": dict(scheme="enlarged", solver="pinv"),
    "regularized": dict(scheme="enlarged", solver="ridge", C=1e5),
    "loo": dict(scheme="enlarged", solver="loo"),
}
SIZES = (1, 6, 10, 50)


def test_float_literals_round_trip_exactly():
    rng = np.random.default_rng(0)
    values = np.concatenate([rng.normal(size=2000) * 10.0 ** rng.integers(-30, 30, 2000),
                             [0.0, 1.0, -2.0, 1e10, 3.4e38, 1e-40, 0.1, 16.6666667]])
    for v in values.astype(np.float32):
        text = c_float(v)
        assert text.endswith("f") and re.fullmatch(r"-?\d+\.\d*(e[+-]\d+)?f|-?\d+\.\d+f|-?\d\.\d*e[+-]\d+f", text), text
        assert np.float32(float(text[:-1])) == v


def test_float_overflow_is_refused():
    with pytest.raises(ModelError, match="not representable"):
        c_float(1e39)


def test_generated_files_follow_the_firmware_rules(default_model):
    files = codegen.render(default_model, "fm", with_controller=True)
    assert set(files) == {"fm.h", "fm.c", *codegen.RUNTIME_FILES, *codegen.CONTROLLER_FILES}
    c, h = files["fm.c"], files["fm.h"]
    n = default_model.aim.n_hidden
    assert f"#define FM_N_HIDDEN {n}" in h and "#ifndef FRICGEN_FM_H" in h
    assert f'#define FM_MODEL_HASH "{default_model.model_hash}"' in h
    assert "#define FM_FORMAT_VERSION 1" in h and '#define FM_FRICGEN_VERSION "' in h
    assert c.count("static const float") == 6
    everything = "\n".join(files.values())
    for banned in ("malloc", "stdio", "printf", "double"):
        assert banned not in everything
    assert default_model.model_hash in c


def test_hostile_emit_name_never_reaches_the_output(default_model, tmp_path):
    with pytest.raises(ModelError, match="C identifier"):
        codegen.emit(default_model, tmp_path / "out", "x;system(1)")
    assert not (tmp_path / "out").exists()


@needs_cc
@pytest.mark.parametrize("activation", sorted(ACTIVATIONS))
def test_emitted_c_builds_without_a_single_warning(bench, tmp_path, activation):
    model = fit_model(bench, n_hidden=10, activation=activation, scheme="standard", solver="loo")
    codegen.emit(model, tmp_path, "fm")
    sources = sorted(p.name for p in tmp_path.glob("*.c"))
    kernels = [s for s in sources if s.startswith("fric_elm_")]
    assert kernels == [f"fric_elm_{activation}.c"]      # only the kernel the model calls
    for src in sources:
        assert_builds_strictly(tmp_path, src, CC)


def _twin_tolerance(model, v):
    """Bound on |C - twin| per velocity.

    The twin performs the same float32 operations in the same order as the C code; only the libm
    results (expf, sinf, sqrtf) may differ, by at most 1 ULP each. Perturbing each of the n
    summed terms by 1 ULP changes a float sum by at most gamma_{n+2} * sum |terms| (Higham's
    bound for recursive summation, with the two further roundings of the scaling and of B v).
    """
    net = model.aim
    x = model.network_input(v)
    terms = np.abs(net.hidden(x) * net.output_weights).sum(axis=1) / model.scaling.k_out
    gamma = (net.n_hidden + 3) * EPS32
    return gamma * (terms + np.abs(model.viscous * v)) + 1e-30


@needs_cc
@pytest.mark.parametrize("kind", sorted(KINDS))
@pytest.mark.parametrize("n_hidden", SIZES)
def test_c_matches_float32_twin_and_float64_model(bench, tmp_path, kind, n_hidden):
    model = fit_model(bench, n_hidden=n_hidden, **KINDS[kind])
    d = parity.float32_deviation(model)
    if d["deviation"] > parity.FLOAT32_TOLERANCE * d["max_force"]:
        # output weights float32 cannot follow (pinv on an ill-conditioned H): refused, not emitted
        with pytest.raises(ModelError, match="output weights cancel"):
            codegen.emit(model, tmp_path / "out", "fm")
        assert not (tmp_path / "out").exists() and kind != "loo"
        return
    codegen.emit(model, tmp_path, "fm")
    lib = build_model(tmp_path, "fm", build_dir=tmp_path / "build")
    v = parity.parity_velocities(model.v_sat)
    assert v.size >= 10_000
    c = parity.c_forces(lib, "fm", v).astype(float)
    twin = force_f32(model, v).astype(float)
    assert np.all(np.abs(c - twin) <= _twin_tolerance(model, v.astype(float)))
    assert np.mean(c == twin) > 0.99          # almost always bit-equal
    exact = model.force(v.astype(float))
    beta_l1 = np.abs(model.aim.output_weights).sum()
    if float32_error(model.aim.hidden(np.linspace(0, 1, 1001)), model.aim.output_weights) <= PARITY:
        # within the parity bound of the fit (max |t| = 1): within 1e-5 of max |F| of the float64 model
        assert np.max(np.abs(c - exact)) <= PARITY * np.max(np.abs(exact))
    else:
        # huge output weights (pinv on an ill-conditioned H): float32 cancellation error grows as
        # eps32 * ||beta||_1 / K_out; the C code is still within that honest bound
        bound = 4 * n_hidden * EPS32 * beta_l1 / model.scaling.k_out + 1e-5 * np.max(np.abs(exact))
        assert np.max(np.abs(c - exact)) <= bound


@needs_cc
def test_c_api_edges(default_model, tmp_path):
    codegen.emit(default_model, tmp_path, "fm")
    lib = build_model(tmp_path, "fm", build_dir=tmp_path / "build")
    assert lib.fm_force(0.0) == 0.0
    assert lib.fm_force(-0.01) == -lib.fm_force(0.01)
    x = np.linspace(0, 1, 11)
    aim = np.array([lib.fm_aim(float(xi)) for xi in x])
    assert np.allclose(aim, default_model.aim(x), atol=1e-5)


def test_a_model_whose_float32_output_would_overflow_is_refused(default_model):
    import dataclasses
    net = default_model.aim
    huge = dataclasses.replace(net, output_weights=np.where(np.arange(net.n_hidden) == 0, 3e38,
                                                            net.output_weights))
    with pytest.raises(ModelError, match="beyond the float32 C's range"):
        codegen.render(dataclasses.replace(default_model, aim=huge), "fm")


@pytest.mark.parametrize("options", [{}, dict(activation_impl="fast"), dict(dtype="q15"), dict(dtype="q31")])
def test_every_generated_file_carries_the_marker_and_its_own_guard(model10, options):
    files = codegen.render(model10, "axis_b", **options)
    for fname in ("axis_b.h", "axis_b.c"):
        assert files[fname].splitlines()[1].startswith(GENERATED_MARKER)
    header = files["axis_b.h"].splitlines()
    assert [line for line in header if line.startswith(("#ifndef", "#define FRICGEN_", "#endif /*"))] == \
        ["#ifndef FRICGEN_AXIS_B_H", "#define FRICGEN_AXIS_B_H", "#endif /* FRICGEN_AXIS_B_H */"]
    # the runtime keeps its own prefix, which no model name may take
    for fname in set(files) - {"axis_b.h", "axis_b.c"}:
        if fname.endswith(".h"):
            assert f"#ifndef {fname[:-2].upper()}_H\n" in files[fname] and fname.startswith("fric_")


@needs_cc
def test_model_guard_stays_clear_of_a_user_guard_named_like_the_model(model10, tmp_path):
    # a firmware header guarded by MOTOR_H used to hide motor.h (guard MOTOR_H) from the same file
    codegen.emit(model10, tmp_path, "motor")
    (tmp_path / "board.h").write_text("#ifndef MOTOR_H\n#define MOTOR_H\n#define BOARD_AXES 1\n#endif\n")
    (tmp_path / "main.c").write_text('#include "board.h"\n#include "motor.h"\n'
                                     "float axis(float v) { return motor_force(v) * BOARD_AXES; }\n")
    assert_builds_strictly(tmp_path, "main.c", CC)


@pytest.mark.parametrize("name", ["fric_ctrl", "fric_kernel", "fric_fast", "FRIC_KERNEL", "_math", "math"])
def test_names_that_collide_with_the_runtime_or_libc_are_refused_before_writing(model10, tmp_path, name):
    with pytest.raises(ModelError, match="name must not"):
        codegen.emit(model10, tmp_path / "out", name)
    assert not (tmp_path / "out").exists()


def test_generated_models_are_told_apart_by_their_marker_line(model10, tmp_path):
    codegen.emit(model10, tmp_path, "fm", with_controller=True)
    codegen.emit(model10, tmp_path, "axis2", dtype="q15")
    (tmp_path / "Board.h").write_text("/* Board.h: pins.\n * Generated by hand, not by fricgen. */\n")
    (tmp_path / "notes.h").mkdir()
    assert codegen.generated_models(tmp_path) == ["axis2", "fm"]
    codegen.emit(model10, tmp_path, "fm", activation_impl="fast")  # the same name again: regenerated
    codegen.emit(model10, tmp_path, "board")                      # a hand-written Board.h is no model
    with pytest.raises(ModelError, match="'fm', whose name differs from 'FM' only by case"):
        codegen.emit(model10, tmp_path, "FM", dtype="q31")


TWO_AXES_MAIN = r"""
#include <stdio.h>
#include "fm.h"
#include "axis2.h"
int main(void) { printf("%%g %%g\n", (double)%(fm)s(%(arg_fm)s), (double)%(axis2)s(%(arg_axis2)s)); return 0; }
"""


def runtime_of(impl):
    return {"libm": codegen.RUNTIME_FILES, "fast": codegen.FAST_RUNTIME_FILES}.get(impl, ())


@needs_cc
@pytest.mark.parametrize("impls", AXIS_PAIRS, ids="+".join)
def test_two_axes_in_one_folder_each_equal_their_own_twin(model10, axis2_model, tmp_path, impls):
    axes = [("fm", model10, impls[0]), ("axis2", axis2_model, impls[1])]
    for name, model, impl in axes:
        emit_impl(model, tmp_path, name, impl)
    build_files = {f.split("/")[0] for f in codegen.PACKAGE_FILES}   # zephyr/module.yml: zephyr
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        {"fm.h", "fm.c", "axis2.h", "axis2.c", *runtime_of(impls[0]), *runtime_of(impls[1]),
         *build_files})
    # both headers in one translation unit, every source in one program, not a single warning
    (tmp_path / "check").mkdir()
    (tmp_path / "check" / "main.c").write_text(TWO_AXES_MAIN % {
        "fm": force_fn("fm", impls[0]), "axis2": force_fn("axis2", impls[1]),
        "arg_fm": "0.01f" if CTYPES[impls[0]] == "float" else "1000",
        "arg_axis2": "0.01f" if CTYPES[impls[1]] == "float" else "1000"})
    proc = subprocess.run([CC, "-std=c99", *STRICT_WARNINGS, "-I.", "check/main.c",
                           *sorted(p.name for p in tmp_path.glob("*.c")), "-o", "check/axes", "-lm"],
                          cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    cdef = "".join(f"{CTYPES[impl]} {force_fn(name, impl)}({CTYPES[impl]} v);\n" for name, _, impl in axes)
    lib = build(tmp_path, ["fm.h", "axis2.h"], cdef, build_dir=tmp_path / "build")
    v = parity.parity_velocities(model10.v_sat)
    for (name, model, impl), (_, other, _) in zip(axes, axes[::-1]):
        inputs = impl_inputs(model, impl, v)
        fn = getattr(lib, force_fn(name, impl))
        c = np.array([fn(x) for x in inputs.tolist()], dtype=inputs.dtype)
        twin = impl_twin(model, impl, inputs)
        if impl == "libm":
            assert np.all(np.abs(c.astype(float) - twin) <= _twin_tolerance(model, v.astype(float)))
            assert np.mean(c == twin) > 0.99
        else:
            assert np.array_equal(c, twin), (name, impl)
        assert np.mean(c == impl_twin(other, impl, inputs)) < 0.1  # this axis's model, not the other's


def test_the_header_states_instructions_per_call_where_the_cost_model_applies(model10):
    from fricgen.codegen.cost import instructions_max
    header = codegen.render(model10, "fm")["fm.h"]
    stated = instructions_max([model10.aim], "libm")
    assert set(stated) == {"cortex-m4f", "cortex-m0plus"}
    assert f"#define FM_INSTR_MAX_CORTEX_M4F {stated['cortex-m4f']}\n" in header
    assert f"#define FM_INSTR_MAX_CORTEX_M0PLUS {stated['cortex-m0plus']}\n" in header
    assert "a model, not measured on this" in header
    fast = instructions_max([model10.aim], "fast")
    assert fast["cortex-m4f"] < stated["cortex-m4f"] and fast["cortex-m0plus"] < stated["cortex-m0plus"]
    sine = FrictionModel(ElmNetwork("sine", model10.aim.input_weights, model10.aim.biases,
                                    model10.aim.output_weights), model10.scaling, model10.viscous,
                         model10.v_sat, name="fs")
    assert "INSTR_MAX" not in codegen.render(sine, "fs")["fs.h"]
