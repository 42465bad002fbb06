"""Fixed-point models (--dtype q15|q31): exact-LSB parity with the integer twin, error bound."""
import subprocess

import numpy as np
import pytest

from fricgen import codegen
from fricgen.codegen import cbuild, fixedpoint as fx
from fricgen.fit.elm import ELMRegressor
from fricgen.model import FrictionModel, ModelError

CTYPE = {"q15": "int16_t", "q31": "int32_t"}


def probe(dtype):
    if dtype == "q15":
        return np.arange(-32768, 32768)                      # every representable input
    rng = np.random.default_rng(0)
    edges = [-2 ** 31, -2 ** 31 + 1, -1, 0, 1, 2 ** 31 - 1]
    return np.concatenate([rng.integers(-2 ** 31, 2 ** 31, 60_000), rng.integers(-2 ** 27, 2 ** 27, 20_000),
                           edges])


@pytest.fixture(scope="module", params=["q15", "q31"])
def fixed_lib(request, model10, tmp_path_factory):
    dtype = request.param
    folder = tmp_path_factory.mktemp(dtype)
    codegen.emit(model10, folder, "fm", dtype=dtype)
    lib = cbuild.build(folder, "fm.h", f"{CTYPE[dtype]} fm_force_{dtype}({CTYPE[dtype]} v_q);",
                       build_dir=folder / "build")
    return dtype, folder, getattr(lib, f"fm_force_{dtype}")


def test_fixed_c_is_lsb_exact_with_integer_twin(fixed_lib, model10):
    dtype, _, fn = fixed_lib
    v_q = probe(dtype)
    c = np.array([fn(int(v)) for v in v_q], dtype=np.int64)
    assert np.array_equal(c, fx.force_q(fx.FixedSpec.of(model10, dtype), v_q))


def test_fixed_error_stays_within_documented_bound(fixed_lib, model10):
    dtype, folder, _ = fixed_lib
    spec = fx.FixedSpec.of(model10, dtype)
    v_q = probe(dtype)
    v = v_q * 2.0 ** -spec.f_v
    err = np.abs(fx.force_q(spec, v_q) * 2.0 ** -spec.f_f - model10.force(v))
    bound = fx.error_bound(spec, model10)
    assert err.max() <= bound, (err.max(), bound)
    # and the bound is no looser than it was derived to be: a sum of worst cases of every
    # rounding, 12.8x (q15) and 2.6x (q31) the error reached on every input; 1.5 times that
    assert err.max() >= bound / {"q15": 19.0, "q31": 3.9}[dtype], (err.max(), bound)
    assert f"<= {bound:.3g} N" in (folder / "fm.h").read_text()
    # the figures the README quotes for this 10-neuron model
    assert bound < {"q15": 0.25, "q31": 5e-5}[dtype]


def test_fixed_output_saturates_and_stays_odd(fixed_lib, model10):
    dtype, _, fn = fixed_lib
    top = 2 ** (16 if dtype == "q15" else 32) // 2 - 1
    assert fn(top) > 0 and fn(-top) < 0 and fn(0) == 0
    assert fn(top) == -fn(-top)


def test_fixed_emit_compiles_clean_under_strict_warnings(fixed_lib):
    _, folder, _ = fixed_lib
    subprocess.run(["cc", "-std=c99", "-O2", "-c", str(folder / "fm.c"), "-o", str(folder / "fm.o")]
                   + cbuild.STRICT_WARNINGS + ["-Wmissing-braces"], check=True)
    undefined = subprocess.run(["nm", "-u", str(folder / "fm.o")], capture_output=True, text=True).stdout
    assert undefined.split() == []                       # no libm, no soft-float helpers on the host


def test_q15_refuses_a_model_whose_weights_break_the_bound(bench):
    est = ELMRegressor(n_hidden=50, scheme="standard", solver="pinv", random_state=0)
    wild = FrictionModel.fit(bench.dataset, est, name="wild")
    assert np.abs(wild.aim.output_weights).sum() > 1e4
    with pytest.raises(ModelError, match="q15"):
        codegen.render(wild, "wild", dtype="q15")


def test_fixed_force_is_exactly_odd_at_every_input(fixed_lib, model10):
    # the header promises F(-v) = -F(v): every q15 input, and the probe set for q31
    dtype, _, fn = fixed_lib
    v_q = np.arange(-2 ** 15 + 1, 2 ** 15) if dtype == "q15" else probe(dtype)
    v_q = v_q[np.abs(v_q) < 2 ** (15 if dtype == "q15" else 31)]
    twin = fx.force_q(fx.FixedSpec.of(model10, dtype), v_q)
    assert np.array_equal(twin, -fx.force_q(fx.FixedSpec.of(model10, dtype), -v_q))
    if dtype == "q15":
        c = np.array([fn(int(v)) for v in v_q], dtype=np.int64)
        assert np.array_equal(c, twin) and np.array_equal(c, -c[::-1])


def test_viscous_rounding_ties_stay_odd(model10):
    # B v lands exactly halfway between two LSBs for some v when the multiplier is even:
    # rounding |v| B and then signing keeps F(-v) = -F(v) there too
    import dataclasses
    spec = dataclasses.replace(fx.FixedSpec.of(model10, "q15"), viscous=fx.ConstMul(14856, 16))
    v_q = np.arange(1, 2 ** 15)
    ties = (v_q * 14856) % (1 << 16) == 1 << 15
    assert ties.sum() > 0
    assert np.array_equal(fx.force_q(spec, -v_q), -fx.force_q(spec, v_q))
