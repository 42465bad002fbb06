"""Independent references: [F1]-[F2], [F3] and [F7] against numbers typed in by hand
from Table 1 of the paper, in float64, in the float32 and integer twins and in the emitted C.

No expected value here is computed with the code under test: each literal is written out with
the arithmetic it comes from (e^-1 = 0.36787944117144233, ...), so a formula changed in one
place (friction.py, the twin, a template) no longer meets it."""
import numpy as np
import pytest

from conftest import CTYPES, emit_impl, force_fn, impl_inputs
from fricgen.codegen import cbuild, fixedpoint as fx
from fricgen.codegen.cbuild import build_model
from fricgen.codegen.fast_sigmoid import error_bound as sigmoid_fast_bound
from fricgen.codegen.fast_sigmoid import exp_neg_error_bound
from fricgen.codegen.parity import c_forces
from fricgen.codegen.twin import force_f32, stribeck_aim_f32
from fricgen.friction import SHAPES, preset
from fricgen.model import FrictionModel, Scaling
from fricgen.networks import ElmNetwork, StribeckCurve

EPS32 = float(np.finfo(np.float32).eps)

#: e^-1, e^-2, e^-4, e^-1/4, e^-1/2 to 17 digits.
E1, E2, E4, E_QUARTER, E_HALF = (0.36787944117144233, 0.1353352832366127, 0.01831563888873418,
                                 0.7788007830714049, 0.6065306597126334)

#: g(v, v_s) of [F2] at v = v_s and v = 2 v_s: e^-(1)^2, e^-(2)^2; e^-1, e^-2; 1/2, 1/3.
G_AT_VS = {"gauss": (E1, E4), "exponential": (E1, E2), "rational": (0.5, 1.0 / 3.0)}

#: Table 1 (f_c, f_s, v_s, B per source): sum f_c = 15, sum (f_s - f_c) = 29, B = 57.5.
TABLE1 = ((4.0, 8.0, 0.01, 2.5), (6.0, 16.0, 0.005, 50.0), (5.0, 20.0, 0.02, 5.0))

#: F(v) of [F1] with Table 1, by shape, at v = 0.005, 0.01, 0.02, 0.06 m/s. At 0.01, e.g.:
#: gauss 15 + 4 e^-1 + 10 e^-4 + 15 e^-1/4 + 57.5 * 0.01 = 28.911685899644183;
#: exponential 15 + 4 e^-1 + 10 e^-2 + 15 e^-1/2 + 0.575 = 27.4978304927414;
#: rational 15 + 4/2 + 10/3 + 15/1.5 + 0.575 = 30.908333...
TABLE1_SPEEDS = (0.005, 0.01, 0.02, 0.06)
TABLE1_FORCES = {
    "gauss": (36.17269348620218, 28.911685899644183, 21.741455298478318, 18.4518511470613),
    "exponential": (33.07442879663603, 27.4978304927414, 22.392689139405427, 19.206782476348156),
    "rational": (34.954166666666666, 30.90833333333333, 26.983333333333334, 23.540659340659342),
}
V_SAT = 0.06


def table1_curve(shape, sources=TABLE1, k_out=1.0 / 44.0, v_sat=V_SAT, slope_viscous=0.0) -> FrictionModel:
    """[F1] with the given sources as a grey-box model of [F3], written out in the
    coordinates of [F9]: c = K_out sum f_c, a_k = K_out (f_s - f_c), xs_k = K_in v_s; of
    the total B, ``slope_viscous`` N s/m goes into the slope d = K_out v_sat slope_viscous
    (d x / K_out = slope_viscous v up to v_sat, held beyond)."""
    k_in = 1.0 / v_sat
    curve = StribeckCurve(shape, k_out * sum(s[0] for s in sources),
                          np.array([k_out * (s[1] - s[0]) for s in sources]),
                          np.array([k_in * s[2] for s in sources]), k_out * v_sat * slope_viscous)
    return FrictionModel(curve, Scaling(k_in, k_out), sum(s[3] for s in sources) - slope_viscous, v_sat,
                         name="ref")


def _reference_points(shape, viscous=57.5):
    """(v, F) by hand: Table 1's speeds, their negatives, and two speeds beyond v_sat, where
    [F3] holds all but the model's B v at its v_sat value: F = F(0.06) + B (v - 0.06)."""
    forces = TABLE1_FORCES[shape]
    v = np.array([*TABLE1_SPEEDS, *(-s for s in TABLE1_SPEEDS), 0.075, -0.1])
    f = np.array([*forces, *(-f for f in forces), forces[-1] + viscous * (0.075 - 0.06),
                  -(forces[-1] + viscous * (0.1 - 0.06))])
    return v, f


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_each_shape_takes_its_hand_values_at_one_and_two_stribeck_velocities(shape):
    at_vs, at_2vs = G_AT_VS[shape]
    g = SHAPES[shape]
    for vs in (0.005, 0.02, 1.0):
        assert float(g(np.array(vs), vs)) == pytest.approx(at_vs, rel=1e-14)
        assert float(g(np.array(-vs), vs)) == pytest.approx(at_vs, rel=1e-14)   # even in v
        assert float(g(np.array(2 * vs), vs)) == pytest.approx(at_2vs, rel=1e-14)


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_table1_forces_are_the_hand_computed_values(shape):
    f = preset("paper3", shape)
    v = np.array(TABLE1_SPEEDS)
    np.testing.assert_allclose(f(v), TABLE1_FORCES[shape], rtol=1e-14)
    np.testing.assert_allclose(f(-v), -np.array(TABLE1_FORCES[shape]), rtol=1e-14)
    assert float(f.stribeck(0.0)) == 44.0                    # sum f_s = 8 + 16 + 20


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_grey_box_model_of_table1_gives_the_hand_values_and_saturates_at_v_sat(shape):
    v, f = _reference_points(shape)
    np.testing.assert_allclose(table1_curve(shape).force(v), f, rtol=1e-13)


def float32_bound(model, impl, v_max=0.12):
    """What float32 may cost against the exact force up to |v| = v_max, in N: (S + 4)
    roundings of each term of [F1] (c, a_k g, B v and the products), each at least the
    smallest normal float32 (a term below it underflows), and with the fast exp its derived
    error on each a_k g."""
    net = model.aim
    terms = (abs(net.offset) + abs(net.slope) + np.abs(net.amplitudes).sum()) / model.scaling.k_out \
        + model.viscous * v_max
    bound = (net.n_sources + 4) * (EPS32 * terms + np.finfo(np.float32).tiny / model.scaling.k_out)
    if impl == "fast" and net.shape != "rational":
        bound += exp_neg_error_bound() * np.abs(net.amplitudes).sum() / model.scaling.k_out
    return bound


@pytest.mark.parametrize("impl", ["libm", "fast"])
@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_emitted_c_and_its_twin_give_the_hand_values(shape, impl, tmp_path):
    """The templates hold their own copy of [F2] (``g_expr``): it meets the same literals.
    7.5 of Table 1's 57.5 N s/m go into the curve's slope d, so c + d x is exercised too."""
    model = table1_curve(shape, slope_viscous=7.5)
    v, f = _reference_points(shape, viscous=50.0)
    bound = float32_bound(model, impl)
    twin = force_f32(model, v, impl).astype(float)
    assert np.max(np.abs(twin - f)) <= bound
    emit_impl(model, tmp_path, "ref", impl)
    c = c_forces(build_model(tmp_path, "ref", build_dir=tmp_path / "build"), "ref", v).astype(float)
    assert np.max(np.abs(c - f)) <= bound
    if impl == "fast":                                        # no libm: the twin bit for bit
        assert np.array_equal(c, twin)


@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_grey_box_aim_takes_a_negative_or_nan_input_as_zero_in_c_and_the_twin(impl, tmp_path):
    """NAME_aim(x) of [F1] for x < 0, -inf or NaN is its value at 0: c + sum_k a_k g(0) =
    K_out sum f_s = 44 / 44 = 1 with Table 1 and K_out = 1/44 (float32, a few roundings)."""
    model = table1_curve("gauss")
    x = np.array([-0.5, -np.inf, np.nan, 0.0], dtype=np.float32)
    twin = stribeck_aim_f32(model.aim, x, impl).astype(float)
    emit_impl(model, tmp_path, "ref", impl)
    lib = build_model(tmp_path, "ref", build_dir=tmp_path / "build")
    c = np.array([lib.ref_aim(float(u)) for u in x])
    for values in (twin, c):
        np.testing.assert_allclose(values, 1.0, rtol=8 * EPS32)


#: A hand-built ELM of [F7]: 1.5 (sigma(4x - 2) + 0.5 sigma(-4x + 2)) = 1.5 (0.5 + 0.5 sigma(4x - 2)),
#: since sigma(-z) = 1 - sigma(z); with K_out = 1.5/40 N^-1 (the network's output reaches 1.41,
#: beyond 1), B = 57.5 N s/m and v_sat = 0.06 m/s.
HAND_ELM = ElmNetwork("sigmoid", np.array([4.0, -4.0]), np.array([-2.0, 2.0]), np.array([1.5, 0.75]))
#: sigma(2) = 1 / (1 + e^-2), sigma(-1) = 1 / (1 + e).
SIGMOID_2, SIGMOID_M1 = 0.8807970779778823, 0.2689414213699951
#: (v, F): x = v / 0.06, F = 40 (0.5 + 0.5 sigma(4x - 2)) sgn(v) + 57.5 v, x held at 1 beyond v_sat.
HAND_ELM_POINTS = np.array([
    (0.0, 0.0),
    (0.015, 40 * (0.5 + 0.5 * SIGMOID_M1) + 57.5 * 0.015),       # x = 1/4
    (0.03, 40 * 0.75 + 57.5 * 0.03),                              # x = 1/2: sigma(0) = 1/2
    (0.06, 40 * (0.5 + 0.5 * SIGMOID_2) + 57.5 * 0.06),           # x = 1
    (0.09, 40 * (0.5 + 0.5 * SIGMOID_2) + 57.5 * 0.09),           # saturated network input
    (-0.03, -(40 * 0.75 + 57.5 * 0.03)),
    (-0.075, -(40 * (0.5 + 0.5 * SIGMOID_2) + 57.5 * 0.075)),
])


def hand_elm_model() -> FrictionModel:
    return FrictionModel(HAND_ELM, Scaling(1.0 / V_SAT, 1.5 / 40.0), 57.5, V_SAT, name="ref")


def test_hand_elm_model_gives_the_hand_values():
    v, f = HAND_ELM_POINTS.T
    np.testing.assert_allclose(hand_elm_model().force(v), f, rtol=1e-14, atol=0)


@pytest.mark.parametrize("impl", ["libm", "fast", "q15", "q31"])
def test_every_c_implementation_of_the_hand_elm_gives_the_hand_values(impl, tmp_path):
    """Float: (M + 4) roundings of each term, plus the fast sigmoid's derived error per neuron;
    fixed point: its integer twin within ``error_bound``, and the C equal to the twin."""
    model = hand_elm_model()
    v, f = HAND_ELM_POINTS.T
    emit_impl(model, tmp_path, "ref", impl)
    inputs = impl_inputs(model, impl, v)
    if CTYPES[impl] == "float":
        lib = build_model(tmp_path, "ref", build_dir=tmp_path / "build")
        c = np.array([getattr(lib, "ref_force")(float(u)) for u in inputs])
        terms = np.abs(HAND_ELM.output_weights).sum() / model.scaling.k_out + 57.5 * np.abs(v)
        bound = 6 * EPS32 * terms
        if impl == "fast":
            bound += sigmoid_fast_bound() * np.abs(HAND_ELM.output_weights).sum() / model.scaling.k_out
        twin = force_f32(model, v, impl)
        assert np.all(np.abs(twin - f) <= bound) and np.all(np.abs(c - f) <= bound)
        if impl == "fast":
            assert np.array_equal(c, twin)
        return
    spec = fx.FixedSpec.of(model, impl)
    twin = fx.force_q(spec, inputs)
    bound = fx.error_bound(spec, model)
    assert bound < 1e-2 * 44                                  # the bound itself says something
    # the literals hold at v; the input is v rounded to 2^-f_v, which moves F by at most the
    # slope sum |beta_k w_k| / 4 K_in / K_out + B (sigma' <= 1/4) times half an LSB
    slope = np.abs(HAND_ELM.output_weights * HAND_ELM.input_weights).sum() / 4 / V_SAT / model.scaling.k_out \
        + 57.5
    assert np.all(np.abs(twin * 2.0 ** -spec.f_f - f) <= bound + slope * 2.0 ** -(spec.f_v + 1))
    lib = cbuild.build(tmp_path, "ref.h", f"{CTYPES[impl]} {force_fn('ref', impl)}({CTYPES[impl]} v_q);",
                       build_dir=tmp_path / "build")
    c = np.array([getattr(lib, force_fn("ref", impl))(int(u)) for u in inputs])
    assert np.array_equal(c, twin)


@pytest.mark.parametrize("impl, viscous", [("q15", 1e-3), ("q31", 1e-8)])
def test_fixed_point_c_equals_its_twin_with_a_constant_at_the_end_of_its_range(impl, viscous, tmp_path):
    """A B this small (N s/m) is below 2^-(bits + 1) of the output LSB per input LSB: its
    multiplier takes the longest right shift that ConstMul allows, which the C's shifts of a
    2 bits-wide word must stay below (a longer one is undefined in C)."""
    model = FrictionModel(HAND_ELM, Scaling(1.0 / V_SAT, 1.5 / 40.0), viscous, V_SAT, name="ref")
    spec = fx.FixedSpec.of(model, impl)
    emit_impl(model, tmp_path, "ref", impl)
    lib = cbuild.build(tmp_path, "ref.h", f"{CTYPES[impl]} {force_fn('ref', impl)}({CTYPES[impl]} v_q);",
                       build_dir=tmp_path / "build")
    top = 2 ** (spec.bits - 1)
    v_q = np.unique(np.round(np.linspace(-top, top - 1, 4001))).astype(np.int64)
    c = np.array([getattr(lib, force_fn("ref", impl))(int(u)) for u in v_q])
    assert np.array_equal(c, fx.force_q(spec, v_q))
