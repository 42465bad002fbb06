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


def test_hand_elm_scales_and_error_bound_are_the_hand_worked_values():
    """The q15 scales of the hand ELM of tests/test_references.py (w = 4, -4; b = -2, 2;
    beta = 1.5, 0.75; K_in = 1/0.06, K_out = 1.5/40, B = 57.5, v_sat = 0.06), each by its rule,
    and error_bound as its docstring's sum with those numbers; only the sigmoid table's
    measured error and output_error are taken from the code."""
    from test_references import hand_elm_model
    model = hand_elm_model()
    spec = fx.FixedSpec.of(model, "q15")
    assert fx.input_range(model, "q15") == 0.125            # 2 v_sat = 0.12 -> 2^-3
    # F_v = 15 + 3; |F| <= 40 (0.5 + 0.5 sigma(2)) + 57.5 * 0.125 = 44.8, 1.1 x that < 2^6: F_f = 15 - 6;
    # |AIM| <= 1.41, 1.1 x that < 2^1: F_aim = 14; F_w = 15 - 3 (|w| = 4, 4 2^12 < 2^15),
    # F_b = 15 - 2, F_beta = 15 - 1; |z| <= 4: F_z = 29 - 3
    assert (spec.f_v, spec.f_f, spec.f_aim, spec.f_w, spec.f_b, spec.f_beta, spec.f_z) == \
        (18, 9, 14, 12, 13, 14, 26)
    assert spec.w.tolist() == [4 << 12, -4 << 12] and spec.b.tolist() == [-2 << 13, 2 << 13]
    assert spec.beta.tolist() == [3 << 13, 3 << 12]
    # v_sat 2^18 = 15728.64; K_in 2^(15 - 18) = 2.0833.. < 2^2: shift 14 - 2, mantissa 2.0833.. 2^12
    assert spec.v_sat_q == 15729 and (spec.k_in.mant, spec.k_in.shift) == (8533, 12)
    x_err = 2.0 ** -15 * (0.5 + 15729 * abs(8533 / 2 ** 12 - 50 / 24)) + (50 / 3) * 2.0 ** -19
    dz = 4 * x_err + 2.0 ** -13 + 2.0 ** -14 + 2.0 ** -26            # |w| x_err, w / 2, b / 2, z
    sig = fx.sigmoid_table_error(spec) + 2.0 ** -15
    aim = (1.5 + 0.75) * (sig + dz / 4) + 2 * 2.0 ** -15 + 2 * 2.0 ** -29 + 2.0 ** -14
    assert fx.error_bound(spec, model) == pytest.approx(aim * 40 / 1.5 + fx.output_error(spec, model),
                                                        rel=1e-12)
    assert 0 < fx.sigmoid_table_error(spec) < 2.0 ** -12          # the table itself: a few LSB


def test_an_aim_below_zero_keeps_its_sign_in_c_and_the_twin(tmp_path):
    """beta = 1.5, -1.5 on the hand ELM's units: AIM = 1.5 (sigma(4x - 2) - sigma(2 - 4x))
    = 1.5 tanh(2x - 1), negative below x = 1/2. F = 40 tanh(2x - 1) sgn(v) + 57.5 v by hand
    (tanh(1/2) = 0.46211715726000974, tanh(1) = 0.7615941559557649), and the C equals its twin
    on every q15 input."""
    from test_references import V_SAT
    from fricgen.model import Scaling
    from fricgen.networks import ElmNetwork
    net = ElmNetwork("sigmoid", np.array([4.0, -4.0]), np.array([-2.0, 2.0]), np.array([1.5, -1.5]))
    model = FrictionModel(net, Scaling(1.0 / V_SAT, 1.5 / 40.0), 57.5, V_SAT, name="fm")
    spec = fx.FixedSpec.of(model, "q15")
    v = np.array([0.015, 0.03, 0.06, -0.015])
    f = np.array([-40 * 0.46211715726000974 + 57.5 * 0.015, 57.5 * 0.03,
                  40 * 0.7615941559557649 + 57.5 * 0.06, 40 * 0.46211715726000974 - 57.5 * 0.015])
    v_q = np.round(v * 2.0 ** spec.f_v).astype(np.int64)
    slope = 1.5 * 2 * 4 / 4 / V_SAT * 40 / 1.5 + 57.5                  # |dF/dv|, sigma' <= 1/4
    tolerance = fx.error_bound(spec, model) + slope * 2.0 ** -(spec.f_v + 1)
    assert np.all(np.abs(fx.force_q(spec, v_q) * 2.0 ** -spec.f_f - f) <= tolerance)
    codegen.emit(model, tmp_path, "fm", dtype="q15")
    lib = cbuild.build(tmp_path, "fm.h", "int16_t fm_force_q15(int16_t v_q);", build_dir=tmp_path / "build")
    v_all = probe("q15")
    assert np.array_equal(np.array([lib.fm_force_q15(int(u)) for u in v_all]), fx.force_q(spec, v_all))
