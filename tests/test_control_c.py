"""The C controller c_runtime/fric_ctrl.c: strict build, parameter checks, closed-loop parity.

Parity tolerances. The C controller and its float32 twin (``AdaptiveBackstepping(dtype=
"float32")`` with ``fricgen.twin.force_f32``) perform the same IEEE float operations in the same
order, so they agree bit for bit except where libm's expf differs from the correctly rounded
value (at most 1 ULP per activation, see fricgen.twin): the model force then differs by ~1e-6 N,
the current by ~1e-7 A at single samples, and the closed loop (contracting: the gains pull x
towards x_d) keeps the position difference below phi/m * di * Ts^2 per sample, ~1e-11 m. We
allow 1e-8 m. Against the float64 controller the difference is float32 rounding of the inputs:
|x| <= 0.1 m is held to ~6e-9 m, which the gains turn into ~1e-5 A of current noise; the loop
filters that to < 1e-8 m of position. We allow 1e-7 m and 1e-5 relative on rms(e1). With the
friction at v_d, the compensation switches sign where v_d crosses zero at a reversal, while the
axis sticks and breaks away: the position then differs most just after a reversal (measured
1.4e-7 m at t = 0.76 s for the default model of the benchmark, 3e-9 to 3e-8 m for others). We
allow 5e-7 m then.
"""
import json
import shutil
import subprocess

import numpy as np
import pytest

from fricgen.codegen.cbuild import CFLAGS, STRICT_WARNINGS
from fricgen.cli import main
from fricgen.codegen import CONTROLLER_FILES, emit
from fricgen.codegen.render import controller_files
from fricgen.errors import UsageError
from fricgen.control.backstepping import AdaptiveBackstepping
from fricgen.control.c_controller import CController, build_controller, float32_twin
from fricgen.control.loop import default_axis, simulate
from test_control import ONE_STEP, one_step_expected

CC = shutil.which("cc") or shutil.which("gcc")
pytestmark = pytest.mark.skipif(CC is None, reason="no C compiler")


@pytest.fixture(scope="module")
def ctrl_module(default_model):
    return build_controller({"fm": default_model})


def test_emit_copies_the_controller_and_the_folder_builds_warning_free(default_model, tmp_path):
    written = emit(default_model, tmp_path, "fm", with_controller=True)
    assert set(CONTROLLER_FILES) <= set(written)
    sources = sorted(str(p) for p in tmp_path.glob("*.c"))
    result = subprocess.run([CC, *CFLAGS, *STRICT_WARNINGS, "-c", *sources],
                            cwd=tmp_path, capture_output=True, text=True)
    assert result.returncode == 0 and result.stderr == "", result.stderr


def test_c_default_parameters_are_the_python_defaults(ctrl_module):
    ffi, lib = ctrl_module.ffi, ctrl_module.lib
    p = ffi.new("fric_ctrl_params_t *")
    lib.fric_ctrl_default_params(p)
    c_params = CController(ctrl_module, AdaptiveBackstepping()).params()
    for field in ("k1", "k2", "delta", "ts", "phi_n", "i_max", "m_o_hat0", "k_hat0", "law",
                  "friction_at"):
        assert getattr(p, field) == getattr(c_params, field), field
    assert list(p.gamma) == list(c_params.gamma)


@pytest.mark.parametrize("field, value", [
    ("k1", 0.0), ("k2", 0.5), ("ts", 0.0), ("ts", float("nan")), ("delta", -1.0),
    ("phi_n", 0.0), ("i_max", float("inf")), ("law", 3), ("friction_at", 3), ("k_hat0", float("nan")),
])
def test_c_init_rejects_each_bad_parameter(ctrl_module, field, value):
    ffi, lib = ctrl_module.ffi, ctrl_module.lib
    p = ffi.new("fric_ctrl_params_t *")
    lib.fric_ctrl_default_params(p)
    c = ffi.new("fric_ctrl_t *")
    assert lib.fric_ctrl_init(c, p) == 0
    setattr(p, field, value)
    assert lib.fric_ctrl_init(c, p) == -2


@pytest.mark.parametrize("gamma", [(1.0, 2.0, 2.0, 1.0), (1.0, 0.1, 0.0, 1.0), (-1.0, 0.0, 0.0, 1.0)])
def test_c_init_rejects_gamma_that_is_not_symmetric_positive_definite(ctrl_module, gamma):
    ffi, lib = ctrl_module.ffi, ctrl_module.lib
    p = ffi.new("fric_ctrl_params_t *")
    lib.fric_ctrl_default_params(p)
    p.gamma = list(gamma)
    assert lib.fric_ctrl_init(ffi.new("fric_ctrl_t *"), p) == -2
    assert lib.fric_ctrl_init(ffi.NULL, p) == -1


@pytest.mark.parametrize("law, friction_input", [("a", "v"), ("b", "v"), ("c", "v"), ("c", "vd"),
                                                 ("c", "reference")])
def test_closed_loop_c_equals_float32_twin_and_float64_controller(ctrl_module, default_model,
                                                                 law, friction_input):
    axis = default_axis()
    settings = AdaptiveBackstepping(compensation=default_model, law=law,
                                    friction_input=friction_input)
    c_run, twin_run, py_run = simulate(
        axis, [CController(ctrl_module, settings, "fm_force"), float32_twin(settings, default_model),
               settings], duration=2.0, substeps=4)
    assert c_run.finite and twin_run.finite
    assert np.max(np.abs(c_run.x - twin_run.x)) <= 1e-8
    assert np.max(np.abs(c_run.k_hat - twin_run.k_hat)) <= 1e-5
    # float32 against float64: the twin's gap is numpy's float32, the same on every platform
    # (1.4e-7 m reached with friction_input "vd"); the C's adds at most its gap to the twin
    twin_gap = np.max(np.abs(twin_run.x - py_run.x))
    assert twin_gap <= (1e-7 if friction_input == "v" else 5e-7)
    assert np.max(np.abs(c_run.x - py_run.x)) <= twin_gap + 1e-8
    c_m, py_m = c_run.metrics(), py_run.metrics()
    assert c_m["rms_e1"] == pytest.approx(py_m["rms_e1"], rel=1e-5)
    assert c_m["k_hat"] == pytest.approx(py_m["k_hat"], rel=1e-4)


@pytest.mark.parametrize("friction_input", ["v", "vd", "reference"])
def test_the_friction_velocity_is_v_vd_or_the_reference_in_c_and_python(ctrl_module, friction_input):
    settings = AdaptiveBackstepping(friction_input=friction_input, dtype="float32").reset()
    c = CController(ctrl_module, settings)
    c.reset()
    x, v, xd, xd_dot = 0.01, 0.2, 0.012, 0.15
    expected = {"v": v, "vd": xd_dot + settings.k1 * (xd - x), "reference": xd_dot}[friction_input]
    got = ctrl_module.lib.fric_ctrl_friction_velocity(c._c, x, v, xd, xd_dot)
    assert got == pytest.approx(expected, rel=1e-6)
    assert got == settings.friction_velocity(*(np.float32(a) for a in (x, v, xd, xd_dot)))


@pytest.mark.parametrize("law", ["a", "b", "c"])
def test_one_c_step_implements_eqs_3_to_14(ctrl_module, law):
    """fric_ctrl_step against [C3]-[C14] computed directly (tests/test_control.py), to float32
    rounding: a one-token change of any coefficient of the laws moves a result far more."""
    settings, inputs = ONE_STEP
    c = CController(ctrl_module, AdaptiveBackstepping(compensation=lambda v: 10.0, law=law,
                                                      **settings)).reset()
    i = c.step(**inputs)
    current, A = one_step_expected(law)
    assert i == pytest.approx(current, rel=1e-6)
    assert c.adaptive_parameters == pytest.approx(A, rel=1e-6)
    # the three laws differ in A_hat by more than the tolerance: the test tells them apart
    assert abs(one_step_expected("c")[1][1] - one_step_expected("b")[1][1]) > 1e-4 * abs(A[1])


def test_c_step_with_the_force_as_argument_equals_the_function_pointer(ctrl_module, default_model):
    axis = default_axis()
    settings = AdaptiveBackstepping(compensation=default_model, law="c")
    ptr, arg = simulate(axis, [CController(ctrl_module, settings, "fm_force"),
                               CController(ctrl_module, settings.clone(
                                   compensation=lambda v: ctrl_module.lib.fm_force(float(v))))],
                        duration=0.5, substeps=2)
    assert np.array_equal(ptr.x, arg.x) and np.array_equal(ptr.i, arg.i)


def test_the_sample_step_is_the_positional_step_bit_for_bit(ctrl_module, default_model):
    """fric_ctrl_step_sample takes the five values in a fric_ctrl_sample_t: the same currents,
    flags and states as fric_ctrl_step_fn over random samples (faults and saturation included);
    a NULL sample writes nothing."""
    ffi, lib = ctrl_module.ffi, ctrl_module.lib
    settings = AdaptiveBackstepping(law="c", friction_input="vd").validate()
    a, b = (CController(ctrl_module, settings, "fm_force") for _ in range(2))
    for c in (a, b):
        c.reset()
    force = ffi.addressof(lib, "fm_force")
    rng = np.random.default_rng(5)
    current = ffi.new("float[2]")
    sample = ffi.new("fric_ctrl_sample_t *")
    for row in rng.normal(0.0, [0.01, 0.2, 0.01, 0.2, 5.0], (300, 5)):
        row[rng.integers(5)] *= 1e4 if rng.random() < 0.1 else 1.0      # saturating demands
        if rng.random() < 0.05:
            row[rng.integers(5)] = np.nan
        sample.x, sample.v, sample.xd, sample.xd_dot, sample.xd_ddot = (float(r) for r in row)
        flags = lib.fric_ctrl_step_fn(a._c, *(float(r) for r in row), force, current)
        assert lib.fric_ctrl_step_sample(b._c, sample, force, current + 1) == flags
        assert bytes(ffi.buffer(current, 4)) == bytes(ffi.buffer(current + 1, 4))
        assert bytes(ffi.buffer(a._c)) == bytes(ffi.buffer(b._c))
    before = bytes(ffi.buffer(b._c))
    current[1] = 7.0
    assert lib.fric_ctrl_step_sample(b._c, ffi.NULL, force, current + 1) == 1     # FAULT_NULL
    assert bytes(ffi.buffer(b._c)) == before and current[1] == 7.0


def test_cli_simulate_c_backend_runs_the_emitted_model_in_c(capsys):
    assert main(["simulate", "--backend", "c", "--json", "--duration", "0.3"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["backend"] == "c"
    assert report["variants"]["elm"]["friction_in"] == "c"
    assert report["variants"]["exact"]["friction_in"] == "python"
    assert all(m["finite"] for m in report["variants"].values())


def test_cli_simulate_c_backend_runs_a_grey_box_model_in_c(tmp_path, capsys):
    sweep, model = tmp_path / "sweep.csv", tmp_path / "m.json"
    assert main(["synth", "--preset", "paper3", "-o", str(sweep)]) == 0
    assert main(["train", str(sweep), "-o", str(model), "--vs-max", "0.02", "--method", "stribeck"]) == 0
    capsys.readouterr()
    training = json.loads(model.read_text())["training"]      # what emit checks: all determined
    for errors in training["standard_errors"].values():
        assert len(errors) == training["n_sources"] and all(e is not None and e > 0 for e in errors)
    reports = {}
    for backend in ("c", "python"):
        assert main(["simulate", "--model", str(model), "--backend", backend, "--json",
                     "--duration", "0.5"]) == 0
        reports[backend] = json.loads(capsys.readouterr().out)["variants"]
    c = reports["c"]
    assert (c["model"]["friction_in"], c["exact"]["friction_in"], c["none"]["friction_in"]) == (
        "c", "python", "none")
    # float32 C against the float64 Python loop: the same tracking to a percent
    assert c["model"]["rms_e1"] == pytest.approx(reports["python"]["model"]["rms_e1"], rel=0.01)


@pytest.mark.parametrize("spoil", ["read-only", "foreign"])
def test_build_controller_refuses_a_runtime_file_it_may_not_replace(default_model, tmp_path, spoil):
    target = tmp_path / "fric_ctrl.c"
    if spoil == "read-only":
        target.write_text(controller_files()["fric_ctrl.c"])
        target.chmod(0o444)
    else:
        target.write_text("/* the user's own controller */\n")
    before = target.read_text()
    with pytest.raises(UsageError, match="fric_ctrl.c"):
        build_controller({"fm": default_model}, tmp_path)
    assert target.read_text() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fric_ctrl.c"]     # nothing written
    target.chmod(0o644)
    module = build_controller({"fm": default_model}, tmp_path, force=True)
    assert module.lib.fm_force(0.1) == pytest.approx(float(default_model.force(0.1)), rel=1e-5)


SQRT_CHECK = r"""
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <string.h>
#include "fric_sqrt.h"
static float from_bits(uint32_t u) { float x; memcpy(&x, &u, sizeof x); return x; }
static uint32_t to_bits(float x) { uint32_t u; memcpy(&u, &x, sizeof u); return u; }
/* the bit patterns [lo, hi) whose fric_sqrt_f32 differs from sqrtf (NaN: both NaN) */
static unsigned long differ(uint32_t lo, uint32_t hi)
{
    unsigned long n = 0;
    uint32_t u;
    for (u = lo; u < hi; ++u) {
        const float x = from_bits(u), a = fric_sqrt_f32(x), b = sqrtf(x);
        n += (a != a) ? !(b != b) : to_bits(a) != to_bits(b);
    }
    return n;
}
int main(void)
{
    printf("subnormal %lu\n", differ(0x00000000u, 0x00800000u));
    printf("one_to_four %lu\n", differ(0x3f800000u, 0x40800000u));
    printf("top %lu\n", differ(0x7f000000u, 0x7f800001u));
    printf("negative %lu\n", differ(0x80000001u, 0x80000400u) + differ(0xff7ffc00u, 0xff800001u));
    printf("nan %lu\n", differ(0x7f800001u, 0x7f800400u));
    return 0;
}
"""


def test_the_controllers_square_root_is_sqrtf_bit_for_bit_without_libm(tmp_path):
    """fric_sqrt_f32 (law c's sqrt(e1^2 + e2^2), so the controller links without libm) against
    the correctly rounded sqrtf: tolerance 0, since the digit-by-digit integer root rounded by
    its remainder is the correctly rounded root. Every float of [1, 4) (the other normal binade
    pairs give the same mantissas: x 4^k -> root 2^k), every subnormal (normalized first), the
    top binade, +inf, NaN and negative numbers (NaN)."""
    for fname, text in controller_files().items():
        (tmp_path / fname).write_text(text)
    (tmp_path / "check.c").write_text(SQRT_CHECK)
    subprocess.run([CC, *CFLAGS, "check.c", "fric_sqrt.c", "-o", "check", "-lm"], cwd=tmp_path,
                   check=True)
    out = subprocess.run(["./check"], cwd=tmp_path, capture_output=True, text=True, check=True).stdout
    counts = dict(line.split() for line in out.splitlines())
    assert counts == {"subnormal": "0", "one_to_four": "0", "top": "0", "negative": "0", "nan": "0"}
