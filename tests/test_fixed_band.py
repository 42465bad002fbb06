"""NAME_compensation_q15/q31: the float NAME_compensation's velocity band in fixed point (0 in
the band, a ramp to the force at twice it, the force beyond), LSB-exact with its integer twin
and within its stated bound of the float64 model's ``compensation`` on every input."""
import shutil
from dataclasses import replace

import numpy as np
import pytest

from fricgen import codegen
from fricgen.cli import main
from fricgen.codegen import cbuild, fixed_table as ft, fixedpoint as fx

from conftest import assert_builds_strictly
from test_fixed_table import asymmetric, greybox
from test_fixedpoint import CTYPE, probe


def _elm_twin(model, dtype):
    spec = fx.FixedSpec.of(model, dtype)
    return spec, (lambda v_q: fx.force_q(spec, v_q)), fx.error_bound(spec, model)


def _table_twin(model, dtype):
    specs = ft.table_specs(model, dtype)
    return specs[0], (lambda v_q: ft.force_tables_q(specs, v_q)), ft.tables_error_bound(specs, model)


@pytest.fixture(scope="module", params=[("elm", "q15", 0.004), ("asymmetric", "q15", 0.0015),
                                        ("greybox", "q31", 0.001), ("greybox", "q15", 1e-7)])
def band_lib(request, model10, tmp_path_factory):
    kind, dtype, band = request.param
    base = {"elm": model10, "asymmetric": asymmetric("gauss"), "greybox": greybox("exponential")}[kind]
    model = replace(base, velocity_band=band, name="gb")
    spec, force, bound = (_elm_twin if kind == "elm" else _table_twin)(model, dtype)
    folder = tmp_path_factory.mktemp(f"band_{kind}_{dtype}")
    codegen.emit(model, folder, "gb", dtype=dtype)
    ct = CTYPE[dtype]
    lib = cbuild.build(folder, "gb.h", f"{ct} gb_force_{dtype}({ct} v_q); {ct} gb_compensation_{dtype}({ct} v_q);",
                       build_dir=folder / "build")
    return model, dtype, spec, force, bound, folder, getattr(lib, f"gb_compensation_{dtype}")


def test_the_c_compensation_is_lsb_exact_with_its_twin_and_within_its_bound(band_lib):
    model, dtype, spec, force, force_bound, folder, fn = band_lib
    band = fx.BandSpec.of(model, spec)
    v_q = probe(dtype)
    c = np.array([fn(int(v)) for v in v_q], dtype=np.int64)
    assert np.array_equal(c, fx.compensation_q(force, band, spec.bits, v_q))
    err = np.abs(c * 2.0 ** -spec.f_f - model.compensation(v_q * 2.0 ** -spec.f_v))
    bound = fx.compensation_error_bound(force_bound, spec, model)
    assert err.max() <= bound, (err.max(), bound)
    assert err.max() >= (bound - force_bound) / 5, (err.max(), bound)     # the band's part is no blanket
    assert f"within {bound:.3g} N" in (folder / "gb.h").read_text()
    assert f"VELOCITY_BAND_Q {band.band_q}" in (folder / "gb.h").read_text()


def test_the_compensation_is_zero_in_the_band_a_ramp_then_the_force(band_lib):
    model, dtype, spec, force, _, _, fn = band_lib
    band_q = fx.BandSpec.of(model, spec).band_q
    assert band_q == max(round(model.velocity_band * 2.0 ** spec.f_v), 1)
    for sign in (1, -1):
        inside = sign * np.arange(0, band_q + 1)
        assert all(fn(int(v)) == 0 for v in inside)                     # no sign switch at rest
        beyond = sign * np.arange(2 * band_q, 2 * band_q + 50)
        assert np.array_equal([fn(int(v)) for v in beyond], force(beyond))
        ramp = np.array([fn(int(v)) for v in sign * np.arange(band_q + 1, 2 * band_q)])
        assert np.all(np.abs(ramp) <= np.abs(force(np.array([sign * 2 * band_q]))))
        assert np.all(np.sign(ramp[ramp != 0]) == sign) and np.all(np.diff(sign * ramp) >= 0)


def test_the_compensation_builds_without_a_warning_under_the_strict_flags(band_lib):
    if shutil.which("gcc") is None:
        pytest.skip("gcc not installed")
    assert_builds_strictly(band_lib[5], "gb.c", "gcc")


@pytest.mark.parametrize("band, noted", [(1e-7, True), (1e-3, False)])
def test_emit_says_when_the_band_is_under_the_inputs_lsb(band, noted, tmp_path, capsys):
    """A band under one LSB of the q15 input is one LSB in the C: emit says so, with the LSB."""
    model = replace(greybox("exponential"), velocity_band=band, name="gb")
    model.save(tmp_path / "m.json")
    assert main(["emit", str(tmp_path / "m.json"), "--dtype", "q15", "-o", str(tmp_path / "c")]) == 0
    lsb = fx.input_range(model, "q15") / 2 ** 15
    said = capsys.readouterr().err
    assert (f"is under the q15 input's LSB ({lsb:.4g} m/s)" in said) == noted
    assert band > lsb or noted
