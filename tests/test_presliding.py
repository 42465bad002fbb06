"""Pre-sliding (fricgen.effects.presliding, FrictionModel.stepper and .compensation, the emitted
NAME_step and NAME_compensation): the exact update against a fine integration of the LuGre
equation, its bounds at any stiffness, model.json's presliding and velocity_band, and the C
against the Python model for both activation implementations and both symmetries."""
import json
import shutil
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from conftest import assert_builds_strictly
from fricgen import codegen
from fricgen.codegen.cbuild import build_module
from fricgen.data.sweep import Sweep
from fricgen.effects.presliding import Bristles, bristle_states
from fricgen.errors import ModelError
from fricgen.fit import StribeckRegressor
from fricgen.model import FrictionModel
from fricgen.training import train

CC = shutil.which("gcc") or shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler")
DT = 1e-4


def stribeck_model(asymmetric=False, name="ax"):
    """The grey-box fit of a Coulomb 2 N, static 3 N, v_s 2 mm/s, B 10 N s/m curve (10 % more
    friction for v < 0 when ``asymmetric``)."""
    v = np.concatenate([-np.logspace(-4.5, -1, 80)[::-1], np.logspace(-4.5, -1, 80)])
    f = np.sign(v) * (2.0 + np.exp(-(v / 2e-3) ** 2)) + 10.0 * v
    if asymmetric:
        f = f * np.where(v < 0, 1.1, 1.0)
    model = train(Sweep(v, f), estimator=StribeckRegressor(), asymmetric=asymmetric, name=name).model
    return replace(model, presliding=Bristles(stiffness=1e5, damping=300.0, damping_speed=3e-3),
                   velocity_band=2e-3)


@pytest.fixture(scope="module")
def model():
    return stribeck_model()


def velocity_profile(n=6000, seed=0):
    """Random walk of speeds through zero, a dwell at rest and a fast burst."""
    v = np.cumsum(np.random.default_rng(seed).normal(0.0, 2e-4, n))
    v[n // 4:n // 4 + 500] = 0.0
    v[n // 2:n // 2 + 100] = 0.3
    return v


def test_the_exact_update_follows_a_fine_integration_of_the_lugre_equation(model):
    v = velocity_profile(400, seed=1) * 5
    stepper = model.stepper(DT)
    z_exact = []
    for u in v:
        stepper.step(u)
        z_exact.append(stepper.z)
    s0 = model.presliding.stiffness
    z, z_ref = 0.0, []
    for u in v:
        g = float(model.stribeck(u))
        z = solve_ivp(lambda _t, y: [u - s0 * abs(u) * y[0] / g], (0.0, DT), [z], rtol=1e-11,
                      atol=1e-15).y[0, -1]
        z_ref.append(z)
    assert np.max(np.abs(np.array(z_exact) - z_ref)) < 1e-6 * np.max(np.abs(z_ref))


def test_the_scan_gives_the_steppers_states(model):
    v = velocity_profile()
    stepper = model.stepper(DT)
    loop = []
    for u in v:
        stepper.step(u)
        loop.append(stepper.z)
    scan = bristle_states(v, np.maximum(model.stribeck(v), 1e-12), model.presliding.stiffness, DT)
    assert np.allclose(scan, loop, rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize("stiffness", [1e3, 1e8, 1e14])
def test_the_update_is_bounded_and_settles_at_any_stiffness(model, stiffness):
    stiff = replace(model, presliding=Bristles(stiffness=stiffness, damping=0.0))
    stepper = stiff.stepper(DT)
    largest = float(stiff.stribeck(0.0)) / stiffness
    z = []
    for u in velocity_profile(seed=2) * 50:
        stepper.step(u)
        z.append(stepper.z)
    assert np.all(np.abs(z) <= largest * (1 + 1e-12))
    forces = [stepper.step(0.01) for _ in range(20000)]
    assert abs(forces[-1] - float(stiff.force(0.01))) < 1e-6


def test_a_non_finite_velocity_holds_the_deflection(model):
    stepper = model.stepper(DT)
    for _ in range(50):
        stepper.step(1e-4)
    z = stepper.z
    for bad in (np.nan, np.inf, -np.inf):
        assert np.isfinite(stepper.step(bad)) and stepper.z == z
    stepper.reset()
    assert stepper.z == 0.0


def test_a_model_without_bristles_steps_its_static_force(model):
    static = replace(model, presliding=None)
    stepper = static.stepper(DT)
    assert [stepper.step(u) for u in (-0.01, 0.0, 0.02)] == list(static.force([-0.01, 0.0, 0.02]))


def test_compensation_is_zero_within_the_band_and_ramps_to_the_force(model):
    band = model.velocity_band
    v = np.linspace(-3 * band, 3 * band, 1201)
    c = model.compensation(v)
    speed = np.abs(v)
    assert np.all(c[speed <= band] == 0.0)                     # the sensor's jitter at rest
    beyond = speed >= 2 * band
    assert np.allclose(c[beyond], model.force(v[beyond]))
    ramp = (speed > band) & ~beyond
    assert np.allclose(c[ramp], model.force(np.sign(v[ramp]) * 2 * band) * (speed[ramp] - band) / band)
    assert model.compensation(np.nan) == 0.0
    assert np.max(np.abs(np.diff(c))) < 0.03 * float(model.force(2 * band))    # continuous


def test_model_json_keeps_bristles_and_band_and_they_change_the_hash(model, tmp_path):
    path = model.save(tmp_path / "m.json")
    back = FrictionModel.load(path)
    assert back.presliding == model.presliding and back.velocity_band == model.velocity_band
    assert back.model_hash == model.model_hash
    assert replace(model, presliding=None).model_hash != model.model_hash
    assert replace(model, velocity_band=None).model_hash != model.model_hash


@pytest.mark.parametrize("edit, message", [
    ({"presliding": {"kind": "dahl", "stiffness": 1e5, "damping": 0.0}}, "kind 'lugre'"),
    ({"presliding": {"kind": "lugre", "stiffness": -1.0, "damping": 0.0}}, "presliding.stiffness"),
    ({"presliding": {"kind": "lugre", "stiffness": 1e5, "damping": -3.0}}, "presliding.damping"),
    ({"presliding": {"kind": "lugre", "stiffness": 1e40, "damping": 0.0}}, "float32"),
    ({"presliding": {"kind": "lugre", "stiffness": 1e5}}, "kind 'lugre'"),
    ({"velocity_band": 0}, "velocity_band must be > 0"),
    ({"velocity_band": "fast"}, "velocity_band must be a number"),
])
def test_a_hand_edited_presliding_or_band_is_refused(model, edit, message):
    d = {**json.loads(model.to_json()), **edit}
    with pytest.raises(ModelError, match=message):
        FrictionModel.from_dict(d)


CDEF = ("typedef struct { float z; } ax_state_t; void ax_reset(ax_state_t *state);"
        "float ax_step(ax_state_t *state, float v); float ax_compensation(float v);")


@pytest.fixture(scope="module", params=[("libm", False), ("fast", False), ("libm", True), ("fast", True)],
                ids=["libm", "fast", "libm-asymmetric", "fast-asymmetric"])
def emitted(request, tmp_path_factory):
    impl, asymmetric = request.param
    m = stribeck_model(asymmetric)
    folder = tmp_path_factory.mktemp("presliding_c")
    for fname, text in codegen.render(m, activation_impl=impl, sample_time=DT).items():
        (folder / fname).write_text(text)
    return m, folder, build_module(folder, "ax.h", CDEF)


@needs_cc
def test_the_c_step_matches_the_python_stepper(emitted):
    m, _, mod = emitted
    v = velocity_profile(seed=3)
    stepper = m.stepper(DT)
    python = np.array([stepper.step(u) for u in v])
    state = mod.ffi.new("ax_state_t *")
    mod.lib.ax_reset(state)
    c = np.array([mod.lib.ax_step(state, float(u)) for u in v])
    assert np.max(np.abs(c - python)) <= 1e-5 * np.max(np.abs(python))
    for bad in (float("nan"), float("inf"), -float("inf")):
        assert np.isfinite(mod.lib.ax_step(state, bad))


@needs_cc
def test_the_c_compensation_matches_the_python_one(emitted):
    m, _, mod = emitted
    band = m.velocity_band
    v = np.concatenate([np.linspace(-3 * band, 3 * band, 2001), [0.05, -0.08, band, -band, 2 * band]])
    c = np.array([mod.lib.ax_compensation(float(u)) for u in v])
    assert np.max(np.abs(c - m.compensation(v))) <= 1e-5 * np.max(np.abs(m.force(v)))
    for bad in ("nan", "inf", "-inf"):
        assert mod.lib.ax_compensation(float(bad)) == 0.0 == m.compensation(float(bad))


@needs_cc
def test_the_emitted_presliding_builds_strictly(emitted):
    _, folder, _ = emitted
    assert_builds_strictly(folder, "ax.c", CC)


def test_emit_needs_a_sample_time_and_refuses_one_without_bristles(model):
    with pytest.raises(ModelError, match="--sample-time"):
        codegen.render(model)
    with pytest.raises(ModelError, match="has none"):
        codegen.render(replace(model, presliding=None), sample_time=DT)
    with pytest.raises(ModelError, match="pre-sliding"):
        codegen.render(model, dtype="q15")
    banded = codegen.render(replace(model, presliding=None), dtype="q15")     # the band alone
    assert "_compensation_q15(int16_t v_q)" in "".join(banded.values())


def test_emit_names_a_sample_time_far_from_the_logs(model, tmp_path, capsys):
    from fricgen.cli import main
    path = replace(model, training={"log": {"sample_time": DT}}).save(tmp_path / "m.json")
    assert main(["emit", str(path), "--sample-time", "0.1", "-o", str(tmp_path / "slow")]) == 0
    assert "1e+03 times the training log's" in capsys.readouterr().err
    assert main(["emit", str(path), "--sample-time", str(2 * DT), "-o", str(tmp_path / "near")]) == 0
    assert "times the training log's" not in capsys.readouterr().err
    assert "#define AX_SAMPLE_TIME 0.000199999995f" in (tmp_path / "near" / "ax.h").read_text()
