"""Fixed-point grey-box models (--dtype q15|q31 of [F1]): the AIM table, LSB-exact parity of
the C with its integer twin, and the documented error bound on every input."""
import shutil

import numpy as np
import pytest

from fricgen import codegen
from fricgen.codegen import cbuild, fixed_table as ft
from fricgen.errors import ModelError
from fricgen.model import Direction, FrictionModel, Scaling
from fricgen.networks.stribeck import StribeckCurve

from conftest import assert_builds_strictly
from test_fixedpoint import CTYPE, probe

V_SAT = 0.06


def greybox(shape, stribeck=(0.005, 0.02), name="gb"):
    """Two sources of Table 1's size (forces 4 + 6 N Coulomb, 10 and 15 N Stribeck drops),
    B = 57.5 N s/m, normalized as [F9] does."""
    k_out = 1.0 / 36.0
    curve = StribeckCurve(shape, k_out * 10.0, np.array([k_out * 10.0, k_out * 15.0]),
                          np.array(stribeck) / V_SAT, 0.01)
    return FrictionModel(curve, Scaling(1.0 / V_SAT, k_out), 57.5, V_SAT, name=name)


@pytest.fixture(scope="module", params=[("q15", "gauss"), ("q31", "exponential"),
                                        ("q15", "rational")])
def table_lib(request, tmp_path_factory):
    dtype, shape = request.param
    return built(greybox(shape), dtype, tmp_path_factory.mktemp(f"{dtype}_{shape}"))


def built(model, dtype, folder):
    """(dtype, model, folder, gb_force_DTYPE) of ``model`` emitted as gb in ``dtype`` and built."""
    codegen.emit(model, folder, "gb", dtype=dtype)
    lib = cbuild.build(folder, "gb.h", f"{CTYPE[dtype]} gb_force_{dtype}({CTYPE[dtype]} v_q);",
                       build_dir=folder / "build")
    return dtype, model, folder, getattr(lib, f"gb_force_{dtype}")


def test_table_c_is_lsb_exact_with_its_integer_twin(table_lib):
    dtype, model, _, fn = table_lib
    v_q = probe(dtype)
    c = np.array([fn(int(v)) for v in v_q], dtype=np.int64)
    assert np.array_equal(c, ft.force_table_q(ft.TableSpec.of(model, dtype), v_q))


def test_table_error_stays_within_its_documented_bound(table_lib):
    dtype, model, folder, _ = table_lib
    spec = ft.TableSpec.of(model, dtype)
    v_q = probe(dtype)
    err = np.abs(ft.force_table_q(spec, v_q) * 2.0 ** -spec.f_f - model.force(v_q * 2.0 ** -spec.f_v))
    bound = ft.table_error_bound(spec, model)
    assert err.max() <= bound, (err.max(), bound)
    assert err.max() >= bound / 20, (err.max(), bound)                  # a bound, not a blanket
    assert f"<= {bound:.3g} N" in (folder / "gb.h").read_text()
    # within 0.1 % of the force range: a grey-box model on an M0+ without soft float
    assert bound <= 1e-3 * 2.0 ** (spec.bits - 1 - spec.f_f)


def test_table_output_is_odd_zero_at_rest_and_saturates(table_lib):
    dtype, _, _, fn = table_lib
    top = 2 ** (16 if dtype == "q15" else 32) // 2 - 1
    assert fn(0) == 0 and fn(top) > 0 and fn(-top) == -fn(top)


def test_a_steep_drop_gets_finer_knots_near_standstill():
    """A drop 1/120 of v_sat wide (v_s = 0.5 mm/s) needs more octaves than a broad one; both
    tables meet TABLE_TOLERANCE of the force range, and the uniform table of as many points
    would not (the octaves put the knots where the curve bends)."""
    steep_model, broad_model = greybox("gauss", (0.0005, 0.02)), greybox("gauss", (0.01, 0.02))
    steep, broad = ft.TableSpec.of(steep_model, "q15"), ft.TableSpec.of(broad_model, "q15")
    assert steep.octaves > broad.octaves
    for spec, model in ((steep, steep_model), (broad, broad_model)):
        tolerance = ft.TABLE_TOLERANCE * 2.0 ** (spec.bits - 1 - spec.f_f) * model.scaling.k_out
        assert spec.interpolation_error <= tolerance
    uniform = np.linspace(0.0, 1.0, steep.table.size)
    tolerance = ft.TABLE_TOLERANCE * 2.0 ** (steep.bits - 1 - steep.f_f) * steep_model.scaling.k_out
    assert ft.interpolation_error(steep_model.aim, uniform) > 10 * tolerance


def test_knots_are_octaves_of_equal_intervals():
    x = ft.knots(2, 1)                       # base [0, 1/4) and octaves [1/4, 1/2), [1/2, 1)
    assert x.tolist() == [0.0, 0.125, 0.25, 0.375, 0.5, 0.75, 1.0]


def test_interpolation_error_of_a_parabola_is_h_squared_over_eight():
    """Linear interpolation of x^2 between knots h apart errs by h^2 f'' / 8 = h^2 / 4 at
    every mid-interval (f'' = 2): the widest interval decides."""
    for n in (4, 16):
        assert ft.interpolation_error(lambda x: x ** 2, np.linspace(0, 1, n + 1)) == \
            pytest.approx(0.25 / n ** 2, rel=1e-12)
    assert ft.interpolation_error(lambda x: x ** 2, ft.knots(2, 1)) == pytest.approx(0.25 / 16, rel=1e-12)


def asymmetric(shape):
    """``greybox(shape)`` for v > 0; for v < 0 a curve of its own: other sources, v_sat,
    K_out and B (a drive's two directions)."""
    k_out = 1.0 / 30.0
    negative = Direction(StribeckCurve(shape, k_out * 8.0, np.array([k_out * 6.0, k_out * 11.0]),
                                       np.array([0.003, 0.03]) / 0.08, 0.01),
                         Scaling(1.0 / 0.08, k_out), 40.0, 0.08)
    return FrictionModel.from_directions(greybox(shape).positive, negative, name="gb")


@pytest.fixture(scope="module", params=[("q15", "gauss"), ("q31", "exponential")])
def asymmetric_lib(request, tmp_path_factory):
    dtype, shape = request.param
    return built(asymmetric(shape), dtype, tmp_path_factory.mktemp(f"asym_{dtype}_{shape}"))


def test_an_asymmetric_models_tables_are_lsb_exact_and_within_their_bound(asymmetric_lib):
    """Each direction's table: the C equals the integer twin on every probed input, and the
    error against the float64 model (its own curve in each direction) is within the bound."""
    dtype, model, folder, fn = asymmetric_lib
    specs = ft.table_specs(model, dtype)
    assert len(specs) == 2 and specs[0].f_v == specs[1].f_v and specs[0].f_f == specs[1].f_f
    v_q = probe(dtype)
    c = np.array([fn(int(v)) for v in v_q], dtype=np.int64)
    assert np.array_equal(c, ft.force_tables_q(specs, v_q))
    err = np.abs(c * 2.0 ** -specs[0].f_f - model.force(v_q * 2.0 ** -specs[0].f_v))
    bound = ft.tables_error_bound(specs, model)
    assert err.max() <= bound and err.max() >= bound / 20, (err.max(), bound)
    assert f"<= {bound:.3g} N" in (folder / "gb.h").read_text()
    for side in (v_q > 0, v_q < 0):                 # each direction is held to the bound
        assert err[side].max() <= bound


def test_an_asymmetric_models_c_follows_each_directions_curve(asymmetric_lib):
    """At the same speed the two directions give their own forces (not -F(v)), each within the
    bound of its curve's; 0 at rest."""
    dtype, model, _, fn = asymmetric_lib
    spec = ft.table_specs(model, dtype)[0]
    bound = ft.tables_error_bound(ft.table_specs(model, dtype), model)
    assert fn(0) == 0
    for speed in (0.002, 0.02, 0.05):
        q = int(round(speed * 2.0 ** spec.f_v))
        up, down = fn(q) * 2.0 ** -spec.f_f, fn(-q) * 2.0 ** -spec.f_f
        true_up, true_down = model.force(np.array([q, -q]) * 2.0 ** -spec.f_v)
        assert abs(up - true_up) <= bound and abs(down - true_down) <= bound
        assert abs(up + down) > 10 * bound            # the curves differ: not an odd model


def test_a_symmetric_models_table_spec_refuses_an_asymmetric_model():
    with pytest.raises(ModelError, match="table_specs"):
        ft.TableSpec.of(asymmetric("gauss"), "q15")


def test_an_asymmetric_model_with_an_elm_curve_is_refused_in_fixed_point(tmp_path):
    """q15 emits an asymmetric model's two tables only where both curves are grey-box."""
    from fricgen.networks import ElmNetwork
    model = greybox("gauss")
    elm = ElmNetwork("sigmoid", np.array([1.0, -2.0]), np.array([0.5, 1.0]), np.array([0.2, 0.1]))
    two = FrictionModel.from_directions(model.positive, Direction(elm, model.scaling, 50.0, V_SAT),
                                        name="gb")
    with pytest.raises(ModelError, match="both grey-box"):
        codegen.emit(two, tmp_path / "c", "gb", dtype="q15")
    assert not (tmp_path / "c").exists() or not any((tmp_path / "c").iterdir())


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_table_c_builds_without_a_warning_under_the_strict_flags(table_lib, cc):
    if shutil.which(cc) is None:
        pytest.skip(f"{cc} not installed")
    _, _, folder, _ = table_lib
    assert_builds_strictly(folder, "gb.c", cc)


def test_asymmetric_table_c_builds_without_a_warning_under_the_strict_flags(asymmetric_lib):
    if shutil.which("gcc") is None:
        pytest.skip("gcc not installed")
    assert_builds_strictly(asymmetric_lib[2], "gb.c", "gcc")


def _layouts(bits):
    """Every (K, m) the module allows: 2^m intervals per segment, m in LOG2_INTERVALS, at most
    MAX_TABLE intervals, the narrowest 2^-(K + m) at least 2 LSB of Q(bits-1) wide."""
    return [(k, m) for m in ft.LOG2_INTERVALS for k in range(0, bits - 1)
            if (k + 1) * 2 ** m <= ft.MAX_TABLE and k + m <= bits - 2]


def _tolerance(spec, model):
    return ft.TABLE_TOLERANCE * 2.0 ** (spec.bits - 1 - spec.f_f) * model.scaling.k_out


def test_the_table_is_the_smallest_within_the_tolerance():
    """Of every allowed layout, none with fewer intervals than the chosen one meets
    TABLE_TOLERANCE of the force range (exhaustive search)."""
    model = greybox("gauss")
    spec = ft.TableSpec.of(model, "q15")
    tolerance = _tolerance(spec, model)
    assert spec.interpolation_error <= tolerance
    smaller = [(k, m) for k, m in _layouts(16) if (k + 1) * 2 ** m < spec.table.size - 1]
    assert len(smaller) >= 10
    for k, m in smaller:
        assert ft.interpolation_error(model.aim, ft.knots(k, m)) > tolerance, (k, m)


def test_a_drop_too_steep_for_any_table_gets_the_most_accurate_allowed_one():
    """v_s = 10 um/s in q15: no allowed layout meets the tolerance; the one chosen is the most
    accurate of them all, its narrowest interval 2 LSB of x wide (K + m = bits - 2)."""
    model = greybox("gauss", (0.00001, 0.02))
    spec = ft.TableSpec.of(model, "q15")
    errors = {(k, m): ft.interpolation_error(model.aim, ft.knots(k, m)) for k, m in _layouts(16)}
    assert min(errors.values()) > _tolerance(spec, model)
    assert spec.interpolation_error == min(errors.values())
    assert spec.octaves + spec.log2_m == 14 and spec.base_shift == 1


def test_a_linear_aim_takes_the_first_table_of_nine_hand_values():
    """AIM = 1/2 + x/4 (no Stribeck drop: amplitude 0) is interpolated exactly by the
    smallest layout, K = 0 and 2^3 intervals; 1.1 max |AIM| = 0.825 < 1 gives F_aim = 15, so
    the table is (1/2 + k/32) 2^15 = 16384 + 1024 k, k = 0..8."""
    curve = StribeckCurve("gauss", 0.5, np.array([0.0]), np.array([0.1]), 0.25)
    model = FrictionModel(curve, Scaling(1.0 / V_SAT, 1.0 / 36.0), 57.5, V_SAT, name="gb")
    spec = ft.TableSpec.of(model, "q15")
    assert (spec.octaves, spec.log2_m, spec.f_aim) == (0, 3, 15)
    assert spec.table.tolist() == [16384 + 1024 * k for k in range(9)]


def test_interpolation_error_finds_a_maximum_between_its_probes():
    """x^3 against its chord on [0, 1]: r - r^3 peaks at r = 1/sqrt(3), between the probes
    k/64, at 2 / (3 sqrt(3)) = 0.3849001794597505; the bounded search reaches it."""
    assert ft.interpolation_error(lambda x: x ** 3, np.array([0.0, 1.0])) == \
        pytest.approx(0.3849001794597505, rel=1e-12)


def test_table_error_bound_of_a_linear_aim_is_its_hand_sum():
    """AIM = 1/2 + x/4 (slope 1/4, interpolated exactly, F_aim = 15), K_out = 1/36: the bound
    is (0 + 1.5 LSB of the AIM + 1/4 the input's rounding) 36 N + what follows the AIM."""
    from fricgen.codegen.fixedpoint import input_rounding, output_error
    curve = StribeckCurve("gauss", 0.5, np.array([0.0]), np.array([0.1]), 0.25)
    model = FrictionModel(curve, Scaling(1.0 / V_SAT, 1.0 / 36.0), 57.5, V_SAT, name="gb")
    spec = ft.TableSpec.of(model, "q15")
    assert spec.interpolation_error < 1e-15
    hand = (1.5 * 2.0 ** -15 + 0.25 * input_rounding(spec, model)) * 36.0 + output_error(spec, model)
    assert ft.table_error_bound(spec, model) == pytest.approx(hand, rel=1e-9)
