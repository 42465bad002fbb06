"""The fast sigmoid (--activation-impl fast): derived error bound, exact C parity, no libm."""
import shutil
import subprocess

import numpy as np
import pytest

from fricgen import codegen
from fricgen._io import resource_dir
from fricgen.c_literal import c_array
from fricgen.codegen import cbuild, fast_sigmoid as fs
from fricgen.codegen.parity import c_forces, parity_velocities
from fricgen.codegen.twin import force_f32

f32 = np.float32
SPECIALS = np.array([0.0, -0.0, 1e-45, -1e-45, 1e-38, 1.0, -1.0, 41.5, -41.5, 41.6, -41.6, 88.0,
                     -88.0, 1e30, -1e30, 3.4e38, -3.4e38, np.inf, -np.inf, np.nan], dtype=f32)


def probe_inputs(n_random=1_000_000):
    """Random z over the whole useful range, a dense grid near 0, and the special values."""
    rng = np.random.default_rng(7)
    return np.concatenate([rng.uniform(-45, 45, n_random).astype(f32),
                           np.linspace(-4, 4, 400_001, dtype=f32), SPECIALS])


def test_fast_sigmoid_error_stays_within_derived_bound():
    z = probe_inputs()
    finite = np.isfinite(z)
    err = np.abs(fs.sigmoid_fast_f32(z[finite]) - fs.sigmoid_exact(z[finite]))
    bound = fs.error_bound()
    assert bound < 8.7e-7, bound          # the figure documented in fric_fast.h and README
    assert fs.kernel_error_bound() < 8.5e-7
    assert err.max() <= bound, (err.max(), z[finite][err.argmax()])
    assert err.max() > 0.0                # the probe does exercise the approximation


def test_fast_sigmoid_defined_for_nan_and_infinities():
    out = fs.sigmoid_fast_f32(np.array([np.nan, np.inf, -np.inf, 0.0], dtype=f32))
    assert np.isnan(out[0]) and out[1] == 1.0 and out[3] == 0.5
    assert 0.0 < out[2] < 1e-37
    z = probe_inputs(10_000)
    y = fs.sigmoid_fast_f32(z[~np.isnan(z)])
    assert np.all((y >= 0.0) & (y <= 1.0))


def test_fast_emit_refuses_neurons_beyond_the_kernel_range(default_model):
    import dataclasses
    from fricgen.fit.elm import ElmNetwork
    from fricgen.model import ModelError
    net = default_model.aim
    steep = ElmNetwork("sigmoid", net.input_weights * 0 + 90.0, net.biases, net.output_weights)
    with pytest.raises(ModelError, match="fast needs"):
        codegen.render(dataclasses.replace(default_model, aim=steep), "fm", activation_impl="fast")


def _relative_error(coef, grid):
    return np.polyval(np.asarray(coef, dtype=float)[::-1], grid) / 2.0 ** grid - 1.0


def test_minimax_exp2_iterates_to_an_equioscillating_error():
    # Chebyshev's theorem: the minimax Q of degree 3 has a weighted error |f| (Q - h) / 2^f =
    # sgn(f) (P / 2^f - 1) that reaches its maximum with alternating signs at 5 points; a Remez
    # exchange that stops early does not.
    grid = np.linspace(-0.5, 0.5, 400_000)
    coef = fs.minimax_exp2()
    err = np.sign(grid) * _relative_error(coef, grid)
    peaks = fs._alternating_extrema(err, 5)
    assert peaks.size == 5
    assert np.all(np.sign(err[peaks[1:]]) == -np.sign(err[peaks[:-1]]))
    level = np.abs(err[peaks])
    assert level.max() - level.min() <= 1e-6 * level.max()
    assert np.max(np.abs(err)) <= level.max() * (1 + 1e-6)
    assert coef[0] == 1.0                                   # P(0) = 1: 2^t exact at integers
    one_exchange = np.max(np.abs(_relative_error(fs.minimax_exp2(iterations=1), grid)))
    assert one_exchange > 1.5 * level.max()                 # the exchange does improve on it


def test_shipped_c_coefficients_reach_the_minimax_error():
    # rounding the coefficients to float moves them by < 6e-8 relative: < 1 % of the error
    grid = np.linspace(-0.5, 0.5, 400_000)
    level = np.max(np.abs(_relative_error(fs.minimax_exp2(), grid)))
    shipped = np.max(np.abs(_relative_error(fs.coefficients().astype(float), grid)))
    assert shipped <= 1.01 * level
    assert fs.coefficients()[0] == 1.0
    assert fs.polynomial_error() < 3.0e-6                    # with float32 Horner rounding


@pytest.fixture(scope="module")
def fast_lib(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fast_rt")
    for fname in codegen.FAST_RUNTIME_FILES:
        shutil.copy(resource_dir("c_runtime") / fname, folder / fname)
    return cbuild.build(folder, "fric_fast.h", "float fric_sigmoid_fast_f32(float z);",
                        build_dir=folder / "build")


def test_c_fast_sigmoid_is_bit_equal_to_twin(fast_lib):
    z = np.concatenate([np.random.default_rng(3).uniform(-50, 50, 100_000).astype(f32), SPECIALS])
    c = np.array([fast_lib.fric_sigmoid_fast_f32(float(v)) for v in z], dtype=f32)
    twin = fs.sigmoid_fast_f32(z)
    assert np.array_equal(c, twin, equal_nan=True)
    assert np.array_equal(c[~np.isnan(c)].view(np.uint32), twin[~np.isnan(twin)].view(np.uint32))


def test_emitted_fast_model_matches_twin_exactly_and_float64_within_bound(default_model, tmp_path):
    codegen.emit(default_model, tmp_path, "fm", activation_impl="fast")
    assert not (tmp_path / "fric_kernel.h").exists()     # the libm runtime is not copied
    lib = cbuild.build_model(tmp_path, "fm", build_dir=tmp_path / "build")
    v = parity_velocities(default_model.v_sat)
    c = c_forces(lib, "fm", v)
    assert np.array_equal(c, force_f32(default_model, v, "fast"))
    beta_l1 = np.abs(default_model.aim.output_weights).sum()
    # sigmoid error times ||beta||_1, plus float32 rounding of the sum (libm-grade), in newtons
    bound = (beta_l1 * fs.error_bound() + 64 * np.finfo(f32).eps * beta_l1) / default_model.scaling.k_out
    err = np.abs(c.astype(float) - default_model.force(v.astype(float)))
    inside = np.abs(v) <= 2 * default_model.v_sat
    assert err[inside].max() <= bound, (err[inside].max(), bound)


def test_fast_runtime_links_no_libm(tmp_path):
    src = resource_dir("c_runtime") / "fric_fast.c"
    assert "math.h" not in src.read_text()
    obj = tmp_path / "fric_fast.o"
    subprocess.run(["cc", "-std=c99", "-O2", "-c", str(src), "-o", str(obj)] + cbuild.STRICT_WARNINGS,
                   check=True)
    undefined = subprocess.run(["nm", "-u", str(obj)], capture_output=True, text=True, check=True).stdout
    assert undefined.split() == [], undefined


def test_fast_kernel_neuron_stays_within_its_bound_over_the_whole_t_range():
    t = np.concatenate([np.random.default_rng(5).uniform(-125, 125, 1_000_000),
                        np.linspace(-6, 6, 200_001), [-125.0, 125.0, 0.0]]).astype(f32)
    beta = f32(-3.0)
    neuron = beta / fs._one_plus_exp2(t)
    with np.errstate(over="ignore"):
        exact = -3.0 / (1.0 + 2.0 ** t.astype(np.float64))
    err = np.abs(neuron - exact) / 3.0
    assert 0.0 < err.max() <= fs.kernel_error_bound(), err.max()


def test_fast_tables_are_premultiplied_once_in_float64(default_model):
    w, b, beta = fs.fast_tables(default_model.aim)
    assert np.array_equal(w, (-fs.LOG2E * default_model.aim.input_weights).astype(f32))
    assert np.array_equal(b, (-fs.LOG2E * default_model.aim.biases).astype(f32))
    text = codegen.render(default_model, "fm", activation_impl="fast")["fm.c"]
    assert c_array(w) in text and c_array(b) in text
