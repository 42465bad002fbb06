"""Cogging as a Fourier series in position (fricgen/effects/position_series.py): the period and
the number of harmonics found on signals made here (not by the class), a known pitch, a ripple
that acts against motion kept apart from a force, the one-sinusoid model.json of earlier
versions, and the C helper's parity with Python."""
import json
import shutil
from dataclasses import replace

import numpy as np
import pytest

from conftest import assert_builds_strictly
from fricgen import codegen
from fricgen.cli import main
from fricgen.codegen.cbuild import build
from fricgen.codegen.twin import force_xv_f32
from fricgen.data.motionlog import log_csv_text
from fricgen.diagnose.diagnoser import Diagnoser
from fricgen.diagnose.residual import ResidualProblem
from fricgen.diagnose.select import mean_square
from fricgen.effects import PositionFriction, PositionRipple, effect_from_dict, force_xv, with_effects
from fricgen.model import FrictionModel
from fricgen.sim.logsynth import RIPPLE_PERIOD, LogSpec, nominal_model, synthesize_log

CC = shutil.which("gcc") or shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler")

PERIOD = 0.0137                                   # m: about 6 periods over the log's travel
THREE = ((1.2, 1.0, 0.8), (0.3, 2.0, 4.5))        # amplitudes (N), phases: the sim's 0.12/0.10/0.08


@pytest.fixture(scope="module")
def model():
    return nominal_model()


@pytest.fixture(scope="module")
def problem(model):
    spec = LogSpec(effect="none", seed=5, duration=8.0)
    log = synthesize_log(spec, model)
    return ResidualProblem(log, model, spec.mass, spec.force_constant, 21, 0.3)


def cogging(x, v, amplitudes, phases, against_motion=False, period=PERIOD):
    """A Fourier series in x written out here, times sgn(v) when it acts against motion."""
    f = sum(a * np.sin((h + 1) * 2 * np.pi * x / period + ph)
            for h, (a, ph) in enumerate(zip(amplitudes, phases)))
    return np.sign(v) * f if against_motion else f


def _residual(problem, amplitudes, phases, against_motion=False, noise=0.3, seed=0):
    """The problem with a residual of that series, smoothed as the residual is, plus white noise
    of ``noise`` times its standard deviation."""
    sig = problem.signals
    raw = cogging(sig.x, sig.v, amplitudes, phases, against_motion)
    target = problem.at_rows(raw, np.arange(problem.rows.size))
    target = target + noise * np.std(target) * np.random.default_rng(seed).standard_normal(target.size)
    return problem.with_target(target)


def replace_pitch(problem, pitch):
    other = problem.with_target(problem.target)
    other.pitch = pitch
    return other


@pytest.mark.parametrize("cls, against_motion", [(PositionRipple, False), (PositionFriction, True)])
def test_three_harmonics_give_the_period_within_one_percent_and_three_harmonics(problem, cls, against_motion):
    q = _residual(problem, *THREE, against_motion=against_motion)
    fit = cls.fit(q, q.fit_rows)
    assert fit.harmonics == 3
    assert abs(fit.period / PERIOD - 1) < 0.01
    np.testing.assert_allclose(fit.amplitude, THREE[0], rtol=0.1)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_one_harmonic_gives_one_harmonic(problem, seed):
    q = _residual(problem, (2.0,), (1.1,), seed=seed)
    fit = PositionRipple.fit(q, q.fit_rows)
    assert fit.harmonics == 1 and abs(fit.period / PERIOD - 1) < 0.01
    assert fit.to_dict()["parameters"]["amplitude"] == pytest.approx(2.0, rel=0.05)


@pytest.mark.parametrize("amplitudes", [(0.5, 1.5, 0.4), (0.4, 0.3, 1.5)])
def test_a_harmonic_larger_than_the_fundamental_is_not_taken_for_it(problem, amplitudes):
    """The periodogram peaks at the 2nd (3rd) harmonic; the fit still finds the fundamental and
    every harmonic (a fundamental at the peak would lose the others)."""
    q = _residual(problem, amplitudes, THREE[1])
    fit = PositionRipple.fit(q, q.fit_rows)
    assert fit.harmonics == 3 and abs(fit.period / PERIOD - 1) < 0.01
    np.testing.assert_allclose(fit.amplitude, amplitudes, rtol=0.2)


def test_a_pitch_fixes_the_period(problem):
    q = _residual(problem, *THREE)
    pitch = PERIOD * 1.003                 # what the user knows, not what the data say
    fit = PositionRipple.fit(replace_pitch(q, pitch), q.fit_rows)
    assert fit.period == pitch and fit.harmonics == 3


def test_a_ripple_against_motion_is_position_friction_and_a_force_is_position_ripple(problem):
    """Each form fits its own kind of residual far better than the other form does."""
    for against_motion, own, other in ((True, PositionFriction, PositionRipple),
                                       (False, PositionRipple, PositionFriction)):
        q = _residual(problem, *THREE, against_motion=against_motion)
        mine, theirs = own.fit(q, q.fit_rows), other.fit(q, q.fit_rows)
        assert mean_square(q, [mine]) < 0.2 * mean_square(q, [theirs])


def test_the_one_sinusoid_model_json_of_earlier_versions_loads_as_one_harmonic(model, tmp_path):
    old = {"effect": "position_ripple", "parameters": {"amplitude": 2.5, "period": 0.0123, "phase": 1.1}}
    earlier = replace(model, effects=(old,))
    d = earlier.to_dict()
    d["effects"] = [old]                     # as an earlier version wrote it, hash and all
    path = tmp_path / "model.json"
    path.write_text(json.dumps(d))
    loaded = FrictionModel.load(path)
    assert not loaded.edited_after_training
    ripple = effect_from_dict(loaded.effects[0])
    assert ripple == PositionRipple(amplitude=(2.5,), period=0.0123, phase=(1.1,)) and ripple.harmonics == 1
    x = np.linspace(-0.05, 0.05, 101)
    np.testing.assert_allclose(force_xv(loaded, 0.1, x) - model.force(0.1),
                               2.5 * np.sin(2 * np.pi * x / 0.0123 + 1.1), atol=1e-12)


@pytest.mark.parametrize("effect", ["position_ripple", "position_friction"])
def test_diagnosis_names_the_form_the_log_hides(model, effect):
    spec = LogSpec(effect=effect, duration=4.0, seed=3)
    log = synthesize_log(spec, model)
    d = Diagnoser(max_effects=2).fit(log, model, spec.mass, spec.force_constant)
    assert [s.effect for s in d.effects_] == [effect], [(s.effect, s.reason) for s in d.steps_]
    assert abs(d.fitted_.period / RIPPLE_PERIOD - 1) < 0.01


def test_diagnose_pitch_fixes_the_period_on_the_command_line(model, tmp_path):
    model.save(tmp_path / "model.json")
    log = synthesize_log(LogSpec(effect="position_ripple", duration=4.0, seed=4), model)
    (tmp_path / "log.csv").write_text(log_csv_text(log))
    pitch = 0.0121
    assert main(["diagnose", str(tmp_path / "log.csv"), "--model", str(tmp_path / "model.json"),
                 "--mass", "4", "--force-constant", "20", "--pitch", str(pitch),
                 "-o", str(tmp_path / "out")]) == 0
    effects = json.loads((tmp_path / "out" / "model.json").read_text())["effects"]
    assert [e["effect"] for e in effects] == ["position_ripple"]
    assert effects[0]["parameters"]["period"] == pitch


SERIES = [PositionRipple(amplitude=(2.5, 1.0, 0.6), period=0.0123, phase=(1.1, 0.2, 5.0)),
          PositionFriction(amplitude=(0.9, 0.4), period=0.047, phase=(3.0, 0.5))]


@needs_cc
def test_the_emitted_series_matches_python_and_builds_strictly(model, tmp_path):
    """C NAME_force_xv with both series (sinf and cosf once each, harmonics by angle addition)
    vs the float64 model within 1e-5 of max |F| over a grid of x and v, and vs its float32
    twin within a few float32 roundings."""
    augmented = with_effects(model, SERIES)
    codegen.emit(augmented, tmp_path, "cg")
    source = (tmp_path / "cg.c").read_text()
    assert source.count("sinf(") == 2 and source.count("cosf(") == 2
    assert_builds_strictly(tmp_path, "cg.c", CC)
    lib = build(tmp_path, "cg.h", "float cg_force(float v);\nfloat cg_force_xv(float v, float x);\n",
                build_dir=tmp_path / "build")
    vv, xx = np.meshgrid(np.linspace(-0.3, 0.3, 61), np.linspace(-0.1, 0.1, 201))
    v, x = vv.ravel().astype(np.float32), xx.ravel().astype(np.float32)
    c = np.array([lib.cg_force_xv(float(a), float(b)) for a, b in zip(v, x)], dtype=np.float32)
    base = np.array([lib.cg_force(float(a)) for a in v], dtype=np.float32)
    scale = float(np.max(np.abs(c)))
    twin = force_xv_f32(augmented, v, x, base=base)
    assert np.max(np.abs(c.astype(float) - twin)) <= 16 * np.finfo(np.float32).eps * scale
    exact = force_xv(augmented, v.astype(float), x.astype(float))
    assert np.max(np.abs(c - exact)) / scale < 1e-5
