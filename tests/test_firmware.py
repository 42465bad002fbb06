"""Cross builds for Cortex-M0+ / Cortex-M4F and runs on QEMU's emulated MCUs (examples/firmware/)."""
import numpy as np
import pytest

from fricgen import codegen, firmware as fw
from fricgen.elm import ELMRegressor, EnlargedScheme
from fricgen.model import FrictionModel
from fricgen.twin import force_f32

pytestmark = pytest.mark.skipif(fw.missing_tools() is not None,
                                reason=f"cross toolchain or QEMU absent: {fw.missing_tools()}")


@pytest.fixture(scope="module")
def model10(bench):
    est = ELMRegressor(n_hidden=10, scheme=EnlargedScheme(w_max=30.0), solver="loo", random_state=0)
    return FrictionModel.fit(bench.dataset, est, name="fm")


def velocities(model, n=101):
    v = np.linspace(-2 * model.v_sat, 2 * model.v_sat, n, dtype=np.float32)
    return np.concatenate([v, np.array([0.0, -0.0, model.v_sat, 1e3, -1e3], dtype=np.float32)])


def build(model, impl, target, tmp_path, inputs, gc_sections=True):
    out = tmp_path / f"{impl}_{target}"
    codegen.emit(model, out / "model", "fm", activation_impl=impl)
    cfg = fw.config_float("fm.h", "fm_force", inputs, n_bench=4)
    return fw.build_firmware(out / "model", cfg, target, out / "build", gc_sections=gc_sections)


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
    # newlib's expf is not correctly rounded: allow a few float32 ulps per neuron, summed
    beta_l1 = np.abs(model10.aim.output_weights).sum()
    tol = 8 * np.finfo(np.float32).eps * beta_l1 / model10.scaling.k_out + 1e-6 * np.abs(twin)
    assert np.all(np.abs(out - twin) <= tol), np.max(np.abs(out - twin))
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
    from fricgen import fixedpoint as fx
    spec = fx.FixedSpec.of(model10, dtype)
    ctype = "int16_t" if dtype == "q15" else "int32_t"
    v_q = fx.to_fixed(velocities(model10), spec.f_v, spec.bits)
    codegen.emit(model10, tmp_path / "model", "fm", dtype=dtype)
    cfg = fw.config_int("fm.h", f"fm_force_{dtype}", ctype, v_q, n_bench=1)
    elf = fw.build_firmware(tmp_path / "model", cfg, "cortex-m0plus", tmp_path / "build")
    assert {"expf", "__aeabi_fadd", "__aeabi_fmul"}.isdisjoint(fw.symbols(elf))  # integers only
    out = fw.parse_int_bits(fw.run(elf, "cortex-m0plus"))
    assert np.array_equal(out, fx.force_q(spec, v_q))
