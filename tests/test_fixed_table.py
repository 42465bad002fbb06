"""Fixed-point grey-box models (--dtype q15|q31 of [F1]): the AIM table, LSB-exact parity of
the C with its integer twin, and the documented error bound on every input."""
import shutil

import numpy as np
import pytest

from fricgen import codegen
from fricgen.codegen import cbuild, fixed_table as ft
from fricgen.errors import ModelError
from fricgen.model import FrictionModel, Scaling
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
    model = greybox(shape)
    folder = tmp_path_factory.mktemp(f"{dtype}_{shape}")
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


def test_an_asymmetric_grey_box_model_is_refused_in_fixed_point(tmp_path):
    from fricgen.model import Direction
    model = greybox("gauss")
    two = FrictionModel(model.aim, model.scaling, model.viscous, model.v_sat, name="gb",
                        negative=Direction(greybox("exponential").aim, model.scaling, 50.0, V_SAT))
    with pytest.raises(ModelError, match="symmetric"):
        codegen.render(two, "gb", dtype="q15")
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_table_c_builds_without_a_warning_under_the_strict_flags(table_lib, cc):
    if shutil.which(cc) is None:
        pytest.skip(f"{cc} not installed")
    _, _, folder, _ = table_lib
    assert_builds_strictly(folder, "gb.c", cc)
