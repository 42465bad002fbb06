"""Fixed-point models (--dtype q15|q31): exact-LSB parity with the integer twin, error bound."""
import subprocess

import numpy as np
import pytest

from fricgen import codegen
from fricgen.codegen import cbuild, fixedpoint as fx
from fricgen.fit.elm import ELMRegressor
from fricgen.model import FrictionModel, ModelError
from fricgen.networks import ElmNetwork

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
    """The scales of the hand ELM of tests/test_references.py (w = 4, -4; b = -2, 2;
    beta = 1.5, 0.75; K_in = 1/0.06, K_out = 1.5/40, B = 57.5, v_sat = 0.06), each by its rule,
    and error_bound as its docstring's sum with those numbers; only the sigmoid table's
    measured error and output_error are taken from the code. With n = bits - 1 (15, 31):
    V_RANGE = 2^-3 (2 v_sat = 0.12), F_v = n + 3; |F| <= 40 (0.5 + 0.5 sigma(2)) + 57.5 / 8 =
    44.8, 1.1 x that < 2^6: F_f = n - 6; |AIM| <= 1.41, 1.1 x that < 2^1: F_aim = n - 1;
    |w| = 4 (4 2^(n-2) = 2^n is one too many): F_w = n - 3, F_b = n - 2, F_beta = n - 1;
    |z| <= 4: F_z = 2 n - 1 - 3. v_sat 2^F_v and K_in 2^(n - F_v) = 2.0833.. (mantissa 2^(n-3)
    times that) by hand."""
    from test_references import hand_elm_model
    model = hand_elm_model()
    hand = {"q15": (15, 0, 15729, 8533), "q31": (31, 16, 1030792151, 559240533)}
    for dtype, (n, term_shift, v_sat_q, k_in_mant) in hand.items():
        spec = fx.FixedSpec.of(model, dtype)
        assert fx.input_range(model, dtype) == 0.125
        assert (spec.f_v, spec.f_f, spec.f_aim, spec.f_w, spec.f_b, spec.f_beta, spec.f_z) == \
            (n + 3, n - 6, n - 1, n - 3, n - 2, n - 1, 2 * n - 4)
        assert spec.w.tolist() == [4 << (n - 3), -4 << (n - 3)] and spec.b.tolist() == [-2 << (n - 2), 2 << (n - 2)]
        assert spec.beta.tolist() == [3 << (n - 2), 3 << (n - 3)] and spec.term_shift == term_shift
        assert spec.v_sat_q == round(0.06 * 2 ** (n + 3)) == v_sat_q
        assert (spec.k_in.mant, spec.k_in.shift) == (k_in_mant, n - 3) and k_in_mant == round(2 ** (n - 3) * 50 / 24)
        x_err = 2.0 ** -n * (0.5 + v_sat_q * abs(k_in_mant / 2 ** (n - 3) - 50 / 24)) + (50 / 3) * 2.0 ** -(n + 4)
        dz = 4 * x_err + 2.0 ** -(n - 2) + 2.0 ** -(n - 1) + 2.0 ** -(2 * n - 4)   # |w| x_err, w / 2, b / 2, z
        sig = fx.sigmoid_table_error(spec) + 2.0 ** -n
        aim = (1.5 + 0.75) * (sig + dz / 4) + 2 * 2.0 ** -n + 2 * 2.0 ** -(2 * n - 1 - term_shift) + 2.0 ** -(n - 1)
        assert fx.error_bound(spec, model) == pytest.approx(aim * 40 / 1.5 + fx.output_error(spec, model),
                                                            rel=1e-12), dtype
        assert fx.sigmoid_table_error(spec) > 0               # measured, not assumed exact


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


def test_the_scale_rules_give_their_hand_values():
    """_frac_for: the finest F with round(|x| 2^F) < 2^(bits-1) (1 - 2^-17 rounds up to 2^15 at
    F = 15, 1 - 2^-14 does not; 4 2^13 = 2^15 is one too many); _quantize refuses 2^(bits-1);
    ConstMul.of: the shift that puts |c| 2^S in [2^(bits-3), 2^(bits-2)], at least 1 (refused
    below) and at most 2 bits - 2; input_range: the power of two above 2 v_sat and above
    v_max by a margin (v_max itself representable)."""
    cases = {0.3: (16, 32), 0.75: (15, 31), 1 - 2.0 ** -14: (15, 31), 1 - 2.0 ** -17: (14, 31),
             1.5: (14, 30), 4.0: (12, 28), 64 - 2.0 ** -8: (9, 25)}   # (64 - 2^-8) 2^9 = 2^15 - 2
    for x, (f16, f32) in cases.items():
        assert (fx._frac_for(x, 16), fx._frac_for(x, 32)) == (f16, f32), x
    assert fx._quantize([0.5, -1 + 2.0 ** -15], 15, 16, "w").tolist() == [16384, -32767]
    with pytest.raises(ModelError, match="w does not fit 16-bit storage at scale 2"):
        fx._quantize([1.0], 15, 16, "w")
    for c, (mant, shift) in {1.0: (2 ** 14, 14), 3.0: (3 << 12, 12), 5000.0: (10000, 1),
                             2.0 ** -20: (1024, 30)}.items():
        assert fx.ConstMul.of(c, 0, 0, 16, "c") == fx.ConstMul(mant, shift), c
    assert fx.ConstMul.of(2.0 ** -20, 0, 0, 16, "c").apply([2 ** 15, -2 ** 15]).tolist() == [0, 0]
    assert fx.ConstMul.of(0.0, 0, 0, 16, "c").apply(np.arange(-5, 6)).tolist() == [0] * 11
    with pytest.raises(ModelError, match="the constant 9000 is too large for 16-bit"):
        fx.ConstMul.of(9000.0, 0, 0, 16, "c")
    from test_references import hand_elm_model                  # v_sat = 0.06 m/s
    model = hand_elm_model()
    # 0.25 (1 - 2^-17) 2^17 rounds to 2^15, one too many; 0.25 (1 - 1.5 2^-14) 2^17 = 2^15 - 3 fits
    for v_max, v_range in ((None, 0.125), (0.05, 0.125), (0.2, 0.25), (0.25, 0.5), (0.25 * (1 - 2.0 ** -17), 0.5),
                           (0.25 * (1 - 1.5 * 2.0 ** -14), 0.25)):
        assert fx.input_range(model, "q15", v_max) == v_range, v_max
    assert fx.input_range(model, "q31", 0.25) == 0.5


def _one_neuron(w, b, beta=1.0):
    from fricgen.model import Scaling
    net = ElmNetwork("sigmoid", np.atleast_1d(np.array(w, dtype=float)), np.atleast_1d(np.array(b, dtype=float)),
                     np.atleast_1d(np.array(beta, dtype=float)))
    return FrictionModel(net, Scaling(1.0 / 0.06, 1.5 / 40.0), 57.5, 0.06, name="fm")


def test_the_z_scale_covers_w_x_plus_b_on_0_1_and_refuses_only_beyond_q15():
    """z = w x + b on [0, 1] reaches max(|b|, |w + b|) (and |w| is kept): 1.01 x that below
    2^c gives F_z = 2 bits - 3 - max(c, 1), so w = 3, b = -3 (|z| <= 3): 29 - 2; w = 1,
    b = -1/2 (|z| <= 1): 29 - 1. q15 needs F_z - 2 >= 15: |z| = 4000 (1.01 x 4000 < 2^12) is
    taken, 4100 is not."""
    assert fx.FixedSpec.of(_one_neuron([3.0, -1.0], [-3.0, 0.5], [1.0, 1.0]), "q15").f_z == 27
    assert fx.FixedSpec.of(_one_neuron(1.0, -0.5), "q15").f_z == 28
    assert fx.FixedSpec.of(_one_neuron(4000.0, -1.0), "q15").f_z == 17
    # b = 2^-14 (2^-14 2^29 = 2^15 is one too many: F_b = 28) meets F_z = 28: b still fits z's scale
    tiny_b = fx.FixedSpec.of(_one_neuron(1.0, 2.0 ** -14), "q15")
    assert tiny_b.f_z == tiny_b.f_b == 28
    with pytest.raises(ModelError, match="network weights too large for q15: .w x . b. reaches 4100"):
        fx.FixedSpec.of(_one_neuron(4100.0, -1.0), "q15")


def test_an_elm_with_zero_biases_is_emitted_in_fixed_point(tmp_path):
    """b = 0 (sigma(4x) and sigma(-4x)): every bias quantizes to 0 at any scale, and the model
    is emitted, its C equal to its twin on every q15 input; at rest the force is
    (1.5 + 0.75) sigma(0) 40 / 1.5 = 30 N from the right (hand value)."""
    model = _one_neuron([4.0, -4.0], [0.0, 0.0], [1.5, 0.75])
    spec = fx.FixedSpec.of(model, "q15")
    assert spec.b.tolist() == [0, 0] and spec.f_b == 15
    codegen.emit(model, tmp_path, "fm", dtype="q15")
    lib = cbuild.build(tmp_path, "fm.h", "int16_t fm_force_q15(int16_t v_q);", build_dir=tmp_path / "build")
    v_q = probe("q15")
    assert np.array_equal(np.array([lib.fm_force_q15(int(u)) for u in v_q]), fx.force_q(spec, v_q))
    assert fx.force_q(spec, [1])[0] * 2.0 ** -spec.f_f == pytest.approx(30.0, abs=fx.error_bound(spec, model) + 0.01)


def test_q15_sigmoid_table_is_within_its_derived_error():
    """Degree 2 on segments h = 1/4 wide, fitted on Chebyshev nodes: (h/2)^3 / (2^2 3!) max|sigma'''|
    (1/8) = 0.33 LSB of Q15, 3 coefficients rounded (1/2 LSB each, r < 1) and 2 rounding shifts
    (1/2 LSB each): at most 2.83 LSB. Its last segment, z = 11.75..12, is the constant
    sigma(11.75) 2^15 = 32767.74, which rounds to 2^15 and is clipped to 2^15 - 1."""
    from test_references import hand_elm_model
    spec = fx.FixedSpec.of(hand_elm_model(), "q15")
    assert fx.sigmoid_table_error(spec) * 2 ** 15 <= (0.125 ** 3 / 24 / 8) * 2 ** 15 + 2.5
    assert spec.sig_coeffs.shape == (48, 3) and spec.sig_coeffs[-1].tolist() == [32767, 0, 0]
