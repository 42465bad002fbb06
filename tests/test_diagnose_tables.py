"""Tables without a physical name (fricgen.effects.tables): interpolation, model.json round trip
and validation, bit-equal C (NAME_force_xv through NAME_interp) under the strict flags, and the
cross-validated smoothing recovering a shape no named effect has."""
import json
from dataclasses import replace
import shutil

import numpy as np
import pytest

from conftest import assert_builds_strictly
from fricgen import codegen
from fricgen.codegen.cbuild import build
from fricgen.codegen.twin import force_xv_f32
from fricgen.effects import TABLES, PositionRipple, Signals, force_xv, with_effects
from fricgen.effects.tables import (TablePosition, TablePositionFriction, TableTime, TableVelocity,
                                    _positions, smooth_table)
from fricgen.data import prepare
from fricgen.fit import StribeckRegressor
from fricgen.model import FrictionModel, ModelError

CC = shutil.which("gcc") or shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler")

TABLE_EFFECTS = [TablePosition(lo=-0.05, hi=0.08, values=(0.0, 1.5, -0.25, 3.0, 2.0)),
                 TablePositionFriction(lo=0.0, hi=0.1, values=(0.5, 0.0, 2.5)),
                 TableVelocity(lo=-0.2, hi=0.25, values=tuple(np.sin(np.arange(12.0))))]


@pytest.fixture(scope="module")
def tabled(default_model):
    return with_effects(default_model, TABLE_EFFECTS + [PositionRipple(amplitude=1.0, period=0.02, phase=0.3),
                                                        TableTime(lo=0.0, hi=10.0, values=(0.0, 1.0))])


def test_interpolation_is_linear_between_knots_and_constant_beyond(default_model):
    table = TABLE_EFFECTS[0]
    x = np.array([-1.0, -0.05, -0.05 + 0.13 / 4 * 1.5, 0.08, 1.0])
    sig = Signals(default_model, x=x, v=np.ones(5))
    np.testing.assert_allclose(table.force(sig), [0.0, 0.0, 0.5 * (1.5 - 0.25), 2.0, 2.0], atol=1e-12)
    signed = TABLE_EFFECTS[1].force(Signals(default_model, x=np.full(3, 0.05), v=np.array([-1.0, 0.0, 2.0])))
    np.testing.assert_allclose(signed, [0.0, 0.0, 0.0])
    signed = TABLE_EFFECTS[1].force(Signals(default_model, x=np.full(3, 0.1), v=np.array([-1.0, 0.0, 2.0])))
    np.testing.assert_allclose(signed, [-2.5, 0.0, 2.5])


def test_tables_round_trip_through_model_json(tabled, tmp_path):
    loaded = FrictionModel.load(tabled.save(tmp_path / "model.json"))
    assert loaded.effects == tabled.effects
    names = [e["effect"] for e in loaded.effects]
    assert set(TABLES) <= set(names)


@pytest.mark.parametrize("params, message", [
    ({"lo": 0.0, "hi": 0.0, "values": [1.0, 2.0]}, "hi must be > lo"),
    ({"lo": 0.0, "hi": 1.0, "values": [1.0]}, "list of 2 to 256"),
    ({"lo": 0.0, "hi": 1.0, "values": [1.0, None]}, "list of 2 to 256"),
    ({"lo": 0.0, "hi": 1.0, "values": [1.0] * 257}, "list of 2 to 256"),
    ({"lo": "0", "hi": 1.0, "values": [1.0, 2.0]}, "lo must be a finite number"),
    ({"lo": 0.0, "hi": 1.0, "values": [1.0, 2.0], "shape": "gauss"}, "unknown field 'shape'"),
])
def test_a_broken_table_is_refused(default_model, tmp_path, params, message):
    d = json.loads(default_model.to_json())
    d["effects"] = [{"effect": "table_velocity", "parameters": params}]
    path = tmp_path / "model.json"
    path.write_text(json.dumps(d))
    with pytest.raises(ModelError, match=message):
        FrictionModel.load(path)


def _hat_basis(u, knots):
    """Linear interpolation on ``knots`` equally spaced knots over [0, 1] at ``u``."""
    k, frac = _positions(u, 0.0, 1.0, knots)
    H = np.zeros((u.size, knots))
    H[np.arange(u.size), k] = 1 - frac
    H[np.arange(u.size), k + 1] = frac
    return H


def test_smoothing_by_cross_validation_follows_a_bump_and_ignores_noise():
    rng = np.random.default_rng(3)
    u = rng.uniform(0.0, 1.0, 3000)
    knots = 24
    H = _hat_basis(u, knots)
    truth = lambda s: 2.0 * np.exp(-((s - 0.4) / 0.08) ** 2)
    values, penalty = smooth_table(H, truth(u) + rng.normal(0, 0.5, u.size))
    grid = np.linspace(0, 1, knots)
    assert np.sqrt(np.mean((values - truth(grid)) ** 2)) < 0.15
    flat, flat_penalty = smooth_table(H, rng.normal(0, 0.5, u.size))
    assert np.max(np.abs(flat)) < 0.25 and flat_penalty >= penalty


def test_absolute_second_differences_follow_a_tight_spot_and_stay_straight_elsewhere():
    """A raised-cosine drag over 2 % of the range on a fine grid: the absolute penalty (kinks)
    bends only around it, where the squared penalty, tied to one smoothness for the whole
    range, either rounds the spot off or follows the noise everywhere."""
    rng = np.random.default_rng(5)
    u = rng.uniform(0.0, 1.0, 6000)
    knots = 192
    H = _hat_basis(u, knots)

    def truth(s):
        z = (s - 0.43) / 0.01
        return np.where(np.abs(z) < 1, 0.5 * (1 + np.cos(np.pi * np.clip(z, -1, 1))), 0.0)
    r = truth(u) + rng.normal(0, 0.3, u.size)
    grid = np.linspace(0, 1, knots)
    away = np.abs(grid - 0.43) > 0.05
    errors, noise = {}, {}
    for kinks in (False, True):
        values, _ = smooth_table(H, r, kinks=kinks)
        errors[kinks] = np.sqrt(np.mean((values - truth(grid)) ** 2))
        noise[kinks] = np.max(np.abs(values[away]))
    assert errors[True] < 0.8 * errors[False]
    assert noise[True] < noise[False] and np.max(values) > 0.7


@needs_cc
def test_tables_in_c_equal_their_float32_twin_bit_for_bit(tabled, tmp_path):
    codegen.emit(tabled, tmp_path, "tx")
    header = (tmp_path / "tx.h").read_text()
    assert "TX_N_EFFECTS_XV 4" in header and "table_time" in header
    lib = build(tmp_path, "tx.h", "float tx_force(float v);\nfloat tx_force_xv(float v, float x);\n",
                build_dir=tmp_path / "build")
    rng = np.random.default_rng(1)
    v = np.concatenate([np.linspace(-0.3, 0.3, 801), [0.0, -0.2, 0.25, 1e30, -1e30]]).astype(np.float32)
    x = np.concatenate([rng.uniform(-0.1, 0.12, v.size - 5), [-0.05, 0.08, 0.1, 1e30, -1e30]]).astype(np.float32)
    base = np.array([lib.tx_force(float(a)) for a in v], dtype=np.float32)
    c = np.array([lib.tx_force_xv(float(a), float(b)) for a, b in zip(v, x)], dtype=np.float32)
    twin = force_xv_f32(tabled, v, x, base=base)
    # the ripple's sinf may differ by 1 ULP; every table term is bit-equal
    scale = float(np.max(np.abs(c[:-2])))
    assert np.max(np.abs(c[:-2].astype(float) - twin[:-2])) <= 4 * np.finfo(np.float32).eps * scale
    tables_only = with_effects(replace(tabled, effects=()), TABLE_EFFECTS)
    codegen.emit(tables_only, tmp_path / "t2", "ty")
    lib2 = build(tmp_path / "t2", "ty.h", "float ty_force(float v);\nfloat ty_force_xv(float v, float x);\n",
                 build_dir=tmp_path / "build2")
    c2 = np.array([lib2.ty_force_xv(float(a), float(b)) for a, b in zip(v, x)], dtype=np.float32)
    base2 = np.array([lib2.ty_force(float(a)) for a in v], dtype=np.float32)
    np.testing.assert_array_equal(c2, force_xv_f32(tables_only, v, x, base=base2))
    exact = force_xv(tables_only, v[:-2].astype(float), x[:-2].astype(float))
    assert np.max(np.abs(c2[:-2] - exact)) / float(np.max(np.abs(exact))) < 1e-5
    assert np.isnan(lib2.ty_force_xv(0.1, float("nan")))


@needs_cc
def test_tables_build_without_a_single_warning(tabled, tmp_path):
    codegen.emit(tabled, tmp_path, "tx")
    assert_builds_strictly(tmp_path, "tx.c", CC)


@needs_cc
def test_tables_on_a_grey_box_model_build_strictly_and_equal_their_twin(bench, tmp_path):
    """The grey-box C (templates/curve.c.j2) carries the same NAME_force_xv."""
    grey = FrictionModel.fit(prepare(bench.train, vs_max=0.02), StribeckRegressor(), name="gb")
    model = with_effects(grey, TABLE_EFFECTS)
    codegen.emit(model, tmp_path, "gb")
    assert_builds_strictly(tmp_path, "gb.c", CC)
    lib = build(tmp_path, "gb.h", "float gb_force(float v);\nfloat gb_force_xv(float v, float x);\n",
                build_dir=tmp_path / "build")
    v = np.linspace(-0.3, 0.3, 401).astype(np.float32)
    x = np.random.default_rng(2).uniform(-0.1, 0.12, v.size).astype(np.float32)
    base = np.array([lib.gb_force(float(a)) for a in v], dtype=np.float32)
    c = np.array([lib.gb_force_xv(float(a), float(b)) for a, b in zip(v, x)], dtype=np.float32)
    np.testing.assert_array_equal(c, force_xv_f32(model, v, x, base=base))


def test_a_named_drift_points_to_online_adaptation():
    """When the diagnosis names a thermal drift, the report says what addresses it in service
    (emit --adapt, its default rule, readback); other effects get no such line."""
    from types import SimpleNamespace

    from fricgen.diagnose.report import service_hint
    from fricgen.effects import ConstantLoad, ThermalDrift
    drift = SimpleNamespace(effect="thermal_drift", fitted=ThermalDrift(rate=0.002, offset=0.0, t0=0.0,
                                                                          time_constant=120.0))
    load = SimpleNamespace(effect="constant_load", fitted=ConstantLoad(load=3.0))
    hint = service_hint(SimpleNamespace(effects_=[load, drift]))
    assert "rate 0.002/s" in hint and "time constant 120 s" in hint
    assert "`fricgen emit --adapt`" in hint and "Lyapunov" in hint and "readback" in hint
    assert service_hint(SimpleNamespace(effects_=[load])) == ""
    linear = SimpleNamespace(effect="thermal_drift", fitted=ThermalDrift(rate=0.002, offset=0.0,
                                                                         t0=0.0, time_constant=0.0))
    hint = service_hint(SimpleNamespace(effects_=[linear]))
    assert "linear in time" in hint and "time constant" not in hint


def test_where_names_the_simplest_axis_among_those_that_explain_as_much():
    """A constant load explains itself along every axis: "constant" (one group) is named, not
    the axis that ranks first by a rounding; a composite axis yields to a simple one as good;
    a clear winner stays."""
    from fricgen.diagnose.localize import where

    def axis(name, share, groups):
        return {"axis": name, "share": share, "detail": "d", "groups": groups}
    assert where([axis("acceleration", 0.996, 10), axis("direction of motion", 0.996, 2),
                  axis("constant", 0.995, 1)]).startswith("constant")
    assert where([axis("position and direction", 0.974, 20), axis("direction of motion", 0.973, 2),
                  axis("velocity", 0.966, 10)]).startswith("direction of motion")
    assert where([axis("speed, friction level", 0.988, 10), axis("velocity", 0.969, 10),
                  axis("direction of motion", 0.6, 2)]).startswith("speed, friction level")
    assert where([axis("time", 0.03, 10)]).startswith("nowhere")
