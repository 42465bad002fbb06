"""The named-effect library: model.json round trip and validation, and C parity of NAME_force_xv."""
import copy
import json
import shutil

import numpy as np
import pytest

from conftest import assert_builds_strictly
from fricgen import codegen
from fricgen.codegen.cbuild import build
from fricgen.effects import (EFFECTS, ActuatorSaturation, ConstantLoad, DirectionAsymmetry, ExtraFrictionSource, ForceConstantMismatch,
                             FrictionalLag, InertiaMismatch, PositionFriction, PositionRipple, SensorDelay, Signals,
                             ThermalDrift, force_xv, with_effects)
from fricgen.codegen.twin import force_xv_f32
from fricgen.model import FrictionModel, ModelError

CC = shutil.which("gcc") or shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler")

XV_EFFECTS = [PositionRipple(amplitude=2.5, period=0.0123, phase=1.1),
              DirectionAsymmetry(gain_positive=-0.05, gain_negative=0.2),
              ConstantLoad(load=-3.25),
              ExtraFrictionSource(fc=2.0, fs=6.0, vs=0.03, B=15.0, shape="gauss"),
              ExtraFrictionSource(fc=1.0, fs=3.0, vs=0.01, B=0.0, shape="exponential"),
              ExtraFrictionSource(fc=0.5, fs=1.5, vs=0.02, B=-1.0, shape="rational"),
              PositionFriction(amplitude=(0.8, 0.3, 0.2), period=0.031, phase=(0.2, 2.0, 4.0))]
OTHER_EFFECTS = [InertiaMismatch(mass=5.2, nominal_mass=4.0), FrictionalLag(tau=0.02),
                 ThermalDrift(rate=0.02, offset=0.01, t0=0.0), SensorDelay(tau=0.0015, nominal_force_constant=20.0),
                 ActuatorSaturation(droop=0.1, peak_current=3.0, nominal_force_constant=20.0)]


@pytest.fixture(scope="module")
def augmented(default_model):
    return with_effects(default_model, XV_EFFECTS + OTHER_EFFECTS)


def test_every_effect_round_trips_through_model_json(augmented, tmp_path):
    path = augmented.save(tmp_path / "model.json")
    loaded = FrictionModel.load(path)
    assert loaded.effects == augmented.effects
    assert loaded.model_hash == augmented.model_hash
    # every effect but the contact's, which a model carries as its bristles (presliding)
    assert {d["effect"] for d in loaded.effects} == set(EFFECTS) - {"force_constant_mismatch", "presliding"}


def test_effects_change_the_model_hash(default_model, augmented):
    assert augmented.model_hash != default_model.model_hash


def _bad_effects():
    ripple = {"effect": "position_ripple", "parameters": {"amplitude": 1.0, "period": 0.01, "phase": 0.0}}
    yield "unknown effect", [{"effect": "gremlins", "parameters": {}}], "unknown effect"
    yield "pre-sliding as an effect", [{"effect": "presliding", "parameters": {"stiffness": 1e5, "damping": 0.0}}], \
        "carried as the model's 'presliding'"
    yield "not an object", ["position_ripple"], "must be an object"
    yield "missing parameter", [{"effect": "constant_load", "parameters": {}}], "missing field 'load'"
    bad = copy.deepcopy(ripple); bad["parameters"]["period"] = -0.01
    yield "negative period", [bad], "period must be > 0"
    bad = copy.deepcopy(ripple); bad["parameters"]["amplitude"] = "big"
    yield "string amplitude", [bad], "finite number"
    bad = copy.deepcopy(ripple); bad["parameters"]["extra"] = 1.0
    yield "unknown parameter", [bad], "unknown field 'extra'"
    bad = copy.deepcopy(ripple); bad["comment"] = "x"
    yield "unknown field", [bad], "unknown field 'comment'"
    bad = {"effect": "extra_friction_source",
           "parameters": {"fc": 1.0, "fs": 2.0, "vs": 0.01, "B": 0.0, "shape": "square"}}
    yield "unknown shape", [bad], "shape must be one of"


@pytest.mark.parametrize("label, effects, message", list(_bad_effects()), ids=[b[0] for b in _bad_effects()])
def test_invalid_effects_are_refused_with_one_line(default_model, label, effects, message):
    d = json.loads(json.dumps(default_model.to_dict()))
    d["effects"] = effects
    with pytest.raises(ModelError, match=message) as info:
        FrictionModel.from_dict(d)
    assert "\n" not in str(info.value)


def test_nan_parameter_is_refused(default_model):
    d = default_model.to_dict()
    d["effects"] = [{"effect": "constant_load", "parameters": {"load": float("nan")}}]
    with pytest.raises(ModelError, match="finite"):
        FrictionModel.from_dict(d)


def test_effect_forces_follow_their_definitions(default_model):
    v = np.array([-0.1, -0.01, 0.0, 0.01, 0.1])
    x = np.array([0.0, 0.003, 0.01, -0.02, 0.05])
    sig = Signals(default_model, x=x, v=v, t=np.full(5, 10.0), a=np.full(5, 2.0), i=np.ones(5))
    F = default_model.force(v)
    np.testing.assert_allclose(XV_EFFECTS[0].force(sig), 2.5 * np.sin(2 * np.pi * x / 0.0123 + 1.1))
    np.testing.assert_allclose(XV_EFFECTS[1].force(sig), np.where(v > 0, -0.05, 0.2) * F)
    np.testing.assert_allclose(OTHER_EFFECTS[0].force(sig), 1.2 * 2.0)
    np.testing.assert_allclose(OTHER_EFFECTS[2].force(sig), (0.01 + 0.02 * 10.0) * F)
    total = force_xv(with_effects(default_model, XV_EFFECTS[:3]), v, x)
    np.testing.assert_allclose(total, F + sum(e.force(sig) for e in XV_EFFECTS[:3]))


@needs_cc
def test_force_xv_in_c_equals_the_python_effects(augmented, tmp_path):
    """C NAME_force_xv vs its float32 twin (bit-equal but for libm's sinf/expf, <= 1 ULP
    each) and vs the float64 model with effects (float32 rounding: 1e-5 of the force range)."""
    codegen.emit(augmented, tmp_path, "fx")
    header = (tmp_path / "fx.h").read_text()
    assert "float fx_force_xv(float v, float x);" in header
    assert "frictional_lag, thermal_drift, sensor_delay, actuator_saturation" in header and "FX_N_EFFECTS_XV 7" in header
    lib = build(tmp_path, "fx.h", "float fx_force(float v);\nfloat fx_force_xv(float v, float x);\n",
                build_dir=tmp_path / "build")
    rng = np.random.default_rng(0)
    v = np.concatenate([np.linspace(-0.3, 0.3, 1201), [0.0, 1e-7, -1e-7]]).astype(np.float32)
    x = rng.uniform(-0.1, 0.1, v.size).astype(np.float32)
    base = np.array([lib.fx_force(float(a)) for a in v], dtype=np.float32)
    c = np.array([lib.fx_force_xv(float(a), float(b)) for a, b in zip(v, x)], dtype=np.float32)
    twin = force_xv_f32(augmented, v, x, base=base)
    scale = float(np.max(np.abs(c)))
    assert np.max(np.abs(c.astype(float) - twin)) <= 8 * np.finfo(np.float32).eps * scale
    exact = force_xv(augmented, v.astype(float), x.astype(float))
    assert np.max(np.abs(c - exact)) / scale < 1e-5


@needs_cc
def test_force_xv_builds_without_a_single_warning(augmented, tmp_path):
    codegen.emit(augmented, tmp_path, "fx")
    assert_builds_strictly(tmp_path, "fx.c", CC)


def test_models_without_effects_emit_no_force_xv(default_model):
    files = codegen.render(default_model, "fm")
    assert "force_xv" not in files["fm.h"] and "force_xv" not in files["fm.c"]


@pytest.mark.parametrize("effect, expected", [
    (InertiaMismatch(mass=1.5, nominal_mass=1.0), 0.5),
    (InertiaMismatch(mass=0.5, nominal_mass=1.0), 0.5),
    (ForceConstantMismatch(force_constant=9.0, nominal_force_constant=10.0), 0.1),
    (ConstantLoad(load=3.0), 0.0),
    (SensorDelay(tau=0.002, nominal_force_constant=20.0), 0.0),
])
def test_mismatch_is_how_far_a_value_is_from_its_nominal_one(effect, expected):
    assert effect.mismatch() == pytest.approx(expected)


def test_an_extra_source_that_dwarfs_the_models_friction_is_no_friction_source(default_model):
    """A Stribeck term of a huge level below the speeds a log resolves (fitted to a few rows)
    would make NAME_force_xv push with meganewtons near rest: refused beside the model."""
    speeds = np.geomspace(1e-6, 0.3, 256)
    level = float(np.max(np.abs(default_model.force(np.concatenate([speeds, -speeds])))))
    plausible = ExtraFrictionSource(fc=0.5, fs=2.0, vs=0.01, B=1.0)
    spike = ExtraFrictionSource(fc=-1.1, fs=-2.2e8, vs=7e-4, B=-1.1)
    assert plausible.implausible_beside(default_model, speeds) == ""
    why = spike.implausible_beside(default_model, speeds)
    assert why.startswith("its force reaches 2.2e+08 at") and f"({level:.3g}; both in the log" in why
