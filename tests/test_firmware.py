"""Cross builds for Cortex-M0+ / Cortex-M4F and runs on QEMU's emulated MCUs (examples/firmware/)."""
import shutil
import subprocess

import numpy as np
import pytest

from conftest import AXIS_PAIRS, CTYPES, emit_impl, force_fn, impl_inputs, impl_twin
from fricgen import codegen
from fricgen.firmware import build as fw
from fricgen.firmware import closed_loop as cl
from fricgen.codegen.twin import force_f32

pytestmark = pytest.mark.skipif(fw.missing_tools() is not None,
                                reason=f"cross toolchain or QEMU absent: {fw.missing_tools()}")


def velocities(model, n=101):
    v = np.linspace(-2 * model.v_sat, 2 * model.v_sat, n, dtype=np.float32)
    return np.concatenate([v, np.array([0.0, -0.0, model.v_sat, 1e3, -1e3], dtype=np.float32)])


def build(model, impl, target, tmp_path, inputs, gc_sections=True):
    out = tmp_path / f"{impl}_{target}"
    codegen.emit(model, out / "model", "fm", activation_impl=impl, with_controller=True)
    cfg = fw.config_float("fm.h", "fm_force", inputs, n_bench=4)
    return fw.build_firmware(out / "model", cfg, target, out / "build", gc_sections=gc_sections)


def newlib_tolerance(model, twin):
    """Bound on |C - twin| of a libm model on newlib, whose expf is not correctly rounded: a few
    float32 ulps per neuron, summed."""
    beta_l1 = np.abs(model.aim.output_weights).sum()
    return 8 * np.finfo(np.float32).eps * beta_l1 / model.scaling.k_out + 1e-6 * np.abs(twin)


@pytest.mark.parametrize("target", sorted(fw.TARGETS))
@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_model_cross_builds_clean_under_strict_warnings(model10, impl, target, tmp_path):
    elf = build(model10, impl, target, tmp_path, velocities(model10), gc_sections=False)
    sizes = fw.section_sizes(elf)
    print(f"{impl} {target}: {sizes}")
    assert 0 < sizes["flash"] < 64 * 1024
    linked = set(fw.symbols(elf))
    assert "fm_force" in linked
    # the fast build links no libm code at all, even without --gc-sections
    assert (impl == "fast") == ({"expf", "__ieee754_expf"}.isdisjoint(linked))


@pytest.mark.parametrize("target", sorted(fw.TARGETS))
def test_emulated_fast_model_is_bit_equal_to_python_twin(model10, target, tmp_path):
    v = velocities(model10)
    out = fw.parse_float_bits(fw.run(build(model10, "fast", target, tmp_path, v), target))
    assert out.size == v.size
    assert np.array_equal(out.view(np.uint32), force_f32(model10, v, "fast").view(np.uint32))


def test_emulated_libm_model_matches_python_within_newlib_expf_accuracy(model10, tmp_path):
    v = velocities(model10)
    out = fw.parse_float_bits(fw.run(build(model10, "libm", "cortex-m4f", tmp_path, v), "cortex-m4f"))
    twin = force_f32(model10, v, "libm").astype(float)
    assert np.all(np.abs(out - twin) <= newlib_tolerance(model10, twin)), np.max(np.abs(out - twin))
    exact = model10.force(v.astype(float))
    inside = np.abs(v) <= 2 * model10.v_sat
    assert np.max(np.abs(out - exact)[inside]) < 1e-3


def test_instruction_count_is_deterministic_and_counts_the_model(model10, tmp_path):
    elf = build(model10, "fast", "cortex-m4f", tmp_path, velocities(model10))
    first, second = fw.count_instructions(elf, "cortex-m4f"), fw.count_instructions(elf, "cortex-m4f")
    assert first == second
    assert first.get("fric_elm_sigmoid_fast_f32", 0) > 4 * 10 * 10  # 4 calls x 10 neurons


@pytest.mark.parametrize("dtype", ["q15", "q31"])
def test_emulated_fixed_point_model_is_lsb_equal_to_integer_twin_on_m0plus(model10, dtype, tmp_path):
    from fricgen.codegen import fixedpoint as fx
    spec = fx.FixedSpec.of(model10, dtype)
    ctype = "int16_t" if dtype == "q15" else "int32_t"
    v_q = fx.to_fixed(velocities(model10), spec.f_v, spec.bits)
    codegen.emit(model10, tmp_path / "model", "fm", dtype=dtype)
    cfg = fw.config_int("fm.h", f"fm_force_{dtype}", ctype, v_q, n_bench=1)
    elf = fw.build_firmware(tmp_path / "model", cfg, "cortex-m0plus", tmp_path / "build")
    assert {"expf", "__aeabi_fadd", "__aeabi_fmul"}.isdisjoint(fw.symbols(elf))  # integers only
    out = fw.parse_int_bits(fw.run(elf, "cortex-m0plus"))
    assert np.array_equal(out, fx.force_q(spec, v_q))


@pytest.mark.parametrize("target", sorted(fw.TARGETS))
@pytest.mark.parametrize("impls", AXIS_PAIRS, ids="+".join)
def test_emulated_two_axes_from_one_folder_each_equal_their_own_twin(model10, axis2_model, impls,
                                                                      target, tmp_path):
    models = {"fm": model10, "axis2": axis2_model}
    axes = []
    for (name, model), impl in zip(models.items(), impls):
        emit_impl(model, tmp_path / "model", name, impl)
        axes.append(fw.Axis(f"{name}.h", force_fn(name, impl), CTYPES[impl],
                            impl_inputs(model, impl, velocities(model))))
    elf = fw.build_firmware(tmp_path / "model", fw.config_axes(axes, n_bench=1), target, tmp_path / "build")
    results = fw.parse_axes(fw.run(elf, target), axes)
    for (name, model), impl, axis, out in zip(models.items(), impls, axes, results):
        twin = impl_twin(model, impl, axis.inputs)
        if impl == "libm":
            assert np.all(np.abs(out - twin) <= newlib_tolerance(model, twin)), name
        else:
            assert np.array_equal(out, twin), name
    if CTYPES[impls[0]] == CTYPES[impls[1]]:
        assert np.mean(results[0] == results[1]) < 0.1  # two models, not one twice


# Closed loop on the MCU: fric_ctrl_step_fn with the emitted fm_force as compensation against
# the float32 plant of examples/firmware/fw_plant.c, N samples of the reversing reference,
# compared row by row (x, v, i, m_o_hat, k_hat) with fricgen.firmware.closed_loop.closed_loop_f32 (the
# float32 controller twin, the model twin and the plant twin). With the fast sigmoid every
# operation is a basic IEEE float operation or sqrtf (correctly rounded by the M4F's vsqrt and
# by newlib's soft-float sqrtf), so the runs are bit-equal. With libm, newlib's expf is not
# correctly rounded: the force moves by at most dF = 8 eps sum|beta| / k_out (the model test's
# bound, 1.1e-4 N here), the current by k_hat dF / phi_n ~ 6e-6 A plus the gains' response to
# the perturbed state, and the loop pulls the states back together each sample (a kick of at
# most phi/m di Ts ~ 5e-8 m/s in v, 5e-11 m in x; measured on both targets: 7.3e-12 m,
# 6.5e-9 m/s, 1.1e-6 A, 7.5e-9 on m_o_hat over 2000 samples, 1910 of the 2000 rows bit-equal).
# We allow 1e-8 m (as the host parity test), 1e-5 m/s, 1e-4 A and 1e-5 on the adaptive
# parameters.
N_LOOP = 2000


def run_closed_loop(model, impl, target, tmp_path):
    from fricgen.control.backstepping import AdaptiveBackstepping
    from fricgen.control.c_controller import float32_twin
    from fricgen.sim.trajectory import reversing, sampled

    settings = AdaptiveBackstepping(compensation=model, law="c")
    plant = cl.Float32Plant()
    ref = sampled(reversing(), np.arange(N_LOOP) * settings.ts).astype(np.float32)
    out = tmp_path / f"loop_{impl}_{target}"
    codegen.emit(model, out / "model", "fm", activation_impl=impl, with_controller=True)
    cfg = fw.config_float("fm.h", "fm_force", [0.0],
                          extra=cl.config_closed_loop(settings, plant, ref, "fm_force"))
    elf = fw.build_firmware(out / "model", cfg, target, out / "build",
                            extra_sources=cl.plant_sources(), strict_extra=True)
    c_rows = cl.parse_closed_loop(fw.run(elf, target))
    py_rows = cl.closed_loop_f32(float32_twin(settings, model, impl), plant, ref)
    return ref, c_rows, py_rows


@pytest.mark.parametrize("target", sorted(fw.TARGETS))
def test_emulated_closed_loop_with_fast_model_is_bit_equal_to_python(model10, target, tmp_path):
    ref, c_rows, py_rows = run_closed_loop(model10, "fast", target, tmp_path)
    assert c_rows.shape == (N_LOOP, len(cl.LOOP_COLUMNS))
    equal = np.all(c_rows.view(np.uint32) == py_rows.view(np.uint32), axis=1)
    print(f"fast {target}: {int(equal.sum())}/{N_LOOP} rows bit-equal")
    assert equal.all()
    # the loop really tracks and adapts (not a trivially equal run)
    x, i, k_hat = (c_rows[:, cl.LOOP_COLUMNS.index(k)] for k in ("x", "i", "k_hat"))
    assert np.all(np.isfinite(c_rows))
    assert np.sqrt(np.mean((ref[:, 0] - x) ** 2)) < 1e-3 < np.abs(ref[:, 0]).max()
    assert 1.0 < np.abs(i).max() < 10.0 and k_hat[-1] != k_hat[0]


@pytest.mark.parametrize("target", sorted(fw.TARGETS))
def test_emulated_closed_loop_with_libm_model_matches_python_within_tolerance(model10, target,
                                                                              tmp_path):
    _, c_rows, py_rows = run_closed_loop(model10, "libm", target, tmp_path)
    assert c_rows.shape == py_rows.shape and np.all(np.isfinite(c_rows))
    diff = np.abs(c_rows.astype(float) - py_rows.astype(float)).max(axis=0)
    equal = np.all(c_rows.view(np.uint32) == py_rows.view(np.uint32), axis=1)
    print(f"libm {target}: max diff {dict(zip(cl.LOOP_COLUMNS, diff))}, "
          f"{int(equal.sum())}/{N_LOOP} rows bit-equal")
    tol = np.array([1e-8, 1e-5, 1e-4, 1e-5, 1e-5])
    assert np.all(diff <= tol), dict(zip(cl.LOOP_COLUMNS, diff))


@pytest.mark.parametrize("impl", ["libm", "fast"])
@pytest.mark.parametrize("target", ["cortex-m4f", "cortex-m0plus"])
def test_one_call_stays_within_the_instruction_count_the_header_states(axis2_model, tmp_path,
                                                                       impl, target):
    """NAME_INSTR_MAX_<TARGET> (a model fitted on other networks) against a 6-neuron ELM it
    never saw, one call at each of three speeds."""
    from fricgen.codegen.cost import TARGETS
    codegen.emit(axis2_model, tmp_path / "src", "axis2", activation_impl=impl)
    header = (tmp_path / "src" / "axis2.h").read_text()
    macro = f"#define AXIS2_INSTR_MAX_{TARGETS[target]} "
    stated = int(header.split(macro)[1].split()[0])
    for k, s in enumerate((0.0, 0.3, 2.0)):
        cfg = fw.config_float("axis2.h", "axis2_force", [s * axis2_model.v_sat], 1)
        elf = fw.build_firmware(tmp_path / "src", cfg, target, tmp_path / f"b{k}")
        count = sum(fw.count_instructions(elf, target).values())
        assert 0.5 * stated < count <= stated, (s, count, stated)


@pytest.mark.skipif(shutil.which("cmake") is None, reason="cmake not installed")
def test_cmake_build_of_the_firmware_example_runs_on_the_emulated_m4f(model10, axis2_model, tmp_path):
    """examples/firmware as a CMake project with the cross toolchain file: the emitted folder
    (two axes, libm and fast) joins as its library, and on QEMU the fast axis equals its twin
    bit for bit."""
    axes = tmp_path / "axes"
    codegen.emit(model10, axes, "fm")
    codegen.emit(axis2_model, axes, "axis2", activation_impl="fast")
    v = np.linspace(-2 * axis2_model.v_sat, 2 * axis2_model.v_sat, 41).astype(np.float32)
    config = tmp_path / "config"
    config.mkdir()
    (config / "fw_config.h").write_text(fw.config_float("axis2.h", "axis2_force", v, n_bench=1))
    example = fw.firmware_dir()
    build_dir = tmp_path / "build"
    for cmd in (["cmake", "-S", str(example), "-B", str(build_dir),
                 f"-DCMAKE_TOOLCHAIN_FILE={example / 'cortex-m4f.cmake'}",
                 f"-DFRICGEN_MODEL_DIR={axes}", f"-DFRICGEN_CONFIG_DIR={config}"],
                ["cmake", "--build", str(build_dir)]):
        proc = subprocess.run(cmd, capture_output=True, text=True)
        assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    out = fw.parse_float_bits(fw.run(build_dir / "fw.elf", "cortex-m4f"))
    assert np.array_equal(out.view(np.uint32), force_f32(axis2_model, v, "fast").view(np.uint32))
