"""diagnose with a model that has bristles (pre-sliding, ``train --dynamic``): its residual and its
held-out simulations run the model's LuGre contact, driven by the log's velocity, so that a log
of that contact leaves nothing to name and a load hidden in it is named alone; the static model
of the same curve leaves the reversals' pre-sliding in the held-out gap."""
import dataclasses

import numpy as np
import pytest

import fricgen
from fricgen.cli import main
from fricgen.diagnose.diagnoser import Diagnoser, candidates_with
from fricgen.data import MotionLog
from fricgen.effects import ConstantLoad, FrictionalLag, with_effects
from fricgen.effects.presliding import Bristles
from fricgen.sim.axis import AxisState
from fricgen.sim.bristle_axis import BristleAxis
from fricgen.sim.effect_law import EffectLaw

MASS, PHI, TS, DURATION, LOAD = 2.0, 18.0, 1e-3, 8.0, 4.0
BRISTLES = Bristles(stiffness=2e5, damping=400.0)


@pytest.fixture(scope="module")
def models():
    sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
    static = fricgen.train(sweep, vs_max=0.02, estimator=fricgen.StribeckRegressor(),
                           warn=lambda line: None).model
    return static, dataclasses.replace(static, presliding=BRISTLES)


def closed_loop_logs(model, loads, seed=1000):
    """Logs of the model's LuGre contact under a PD loop tracking three sinusoids (reversals at
    many speeds), one axis per load (N): position in 1 um counts, velocity by the backward
    difference, the current with noise."""
    rng = np.random.default_rng(seed)
    law = EffectLaw.batch(model, [[ConstantLoad(load)] if load else [] for load in loads],
                          mass=MASS, force_constant=PHI)
    axis = BristleAxis(law, model.presliding, model.stribeck, model.viscous_force)
    n, k = int(DURATION / TS), len(loads)
    t = np.arange(n) * TS
    w = 2 * np.pi * np.array([0.4, 1.3, 3.1])
    amp = np.array([0.02, 0.004, 0.001])
    state = AxisState.of(np.zeros(k))
    x_log, v_log, i_log = (np.empty((n, k)) for _ in range(3))
    x_prev = np.zeros(k)
    omega = 2 * np.pi * 20.0
    for j in range(n):
        x_meas = np.round(state.x * 1e6) / 1e6
        v_meas = (x_meas - x_prev) / TS if j else np.zeros(k)
        x_prev = x_meas
        r, rd = np.sum(amp * np.sin(w * t[j])), np.sum(amp * w * np.cos(w * t[j]))
        current = MASS * (omega ** 2 * (r - x_meas) + 1.6 * omega * (rd - v_meas)) / PHI
        x_log[j], v_log[j] = x_meas, v_meas
        i_log[j] = current + rng.normal(0.0, 0.01, k)
        state = axis.advance(state, current, TS, 2)
    return [MotionLog(t, x_log[:, c], v_log[:, c], i_log[:, c]) for c in range(k)]


@pytest.fixture(scope="module")
def logs(models):
    return closed_loop_logs(models[1], [0.0, LOAD])


def test_a_log_of_the_models_own_contact_leaves_nothing_to_name(models, logs):
    static, lugre = models
    d = Diagnoser().fit(logs[0], lugre, MASS, PHI)
    assert d.effects_ == [], [(s.effect, s.reason) for s in d.steps_]
    assert all(s.effect != FrictionalLag.name for s in d.steps_)       # not considered
    # the static curve leaves the reversals' pre-sliding in the gap
    gap_static = Diagnoser().held_out_gap(logs[0], static, MASS, PHI)
    assert d.gap_before_ < 0.5 * gap_static, (d.gap_before_, gap_static)


def test_a_load_hidden_in_the_contacts_log_is_named_alone(models, logs):
    d = Diagnoser().fit(logs[1], models[1], MASS, PHI)
    assert [s.effect for s in d.effects_] == ["constant_load"], [(s.effect, s.reason) for s in d.steps_]
    assert d.effects_[0].fitted.load == pytest.approx(LOAD, rel=0.1)
    assert d.gap_after_ < 0.5 * d.gap_before_


def test_diagnose_runs_a_model_with_bristles_and_says_so(models, logs, tmp_path, capsys):
    lugre = models[1]
    lugre.save(tmp_path / "lugre.json")
    log = logs[1]
    np.savetxt(tmp_path / "log.csv", np.column_stack([log.t, log.x, log.v, log.i]), delimiter=",",
               header="t,x,v,i", comments="")
    code = main(["diagnose", str(tmp_path / "log.csv"), "--model", str(tmp_path / "lugre.json"),
                 "--mass", str(MASS), "--force-constant", str(PHI), "-o", str(tmp_path / "diag")])
    out = capsys.readouterr()
    assert code == 0, out.err
    assert "bristles (LuGre, sigma0 2e+05" in out.out + out.err
    assert "constant_load" in out.out
    report = (tmp_path / "diag" / "report.md").read_text()
    assert "this effect appended to `effects`" in report and "Nothing explains" not in report
    # a model carrying a frictional lag beside its bristles: two memories, refused in one line
    both = with_effects(lugre, [FrictionalLag(tau=0.01)])
    both.save(tmp_path / "both.json")
    code = main(["diagnose", str(tmp_path / "log.csv"), "--model", str(tmp_path / "both.json"),
                 "--mass", str(MASS), "--force-constant", str(PHI), "-o", str(tmp_path / "d2")])
    err = capsys.readouterr().err
    assert code == 2 and "two friction memories" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "d2").exists()


def test_a_static_model_names_the_contacts_presliding_when_asked(models, logs):
    static = models[0]
    d = Diagnoser(candidates=candidates_with("presliding")).fit(logs[0], static, MASS, PHI)
    assert [s.effect for s in d.effects_] == ["presliding"], [(s.effect, s.reason) for s in d.steps_]
    assert d.model_.presliding.stiffness == pytest.approx(BRISTLES.stiffness, rel=0.1)
    assert d.model_.effects == ()                   # carried as the model's bristles
    assert d.gap_after_ < 0.5 * d.gap_before_
    # not a default candidate: asked for only
    assert all(s.effect != "presliding" for s in Diagnoser().fit(logs[0], static, MASS, PHI).steps_)


def test_diagnose_presliding_writes_bristles_that_emit_turns_into_a_step(models, logs, tmp_path, capsys):
    models[0].save(tmp_path / "static.json")
    log = logs[0]
    np.savetxt(tmp_path / "log.csv", np.column_stack([log.t, log.x, log.v, log.i]), delimiter=",",
               header="t,x,v,i", comments="")
    code = main(["diagnose", str(tmp_path / "log.csv"), "--model", str(tmp_path / "static.json"),
                 "--mass", str(MASS), "--force-constant", str(PHI), "--presliding",
                 "-o", str(tmp_path / "diag")])
    out = capsys.readouterr()
    assert code == 0, out.err
    assert "presliding" in out.out
    report = (tmp_path / "diag" / "report.md").read_text()
    assert "`presliding` as its bristles" in report and "Nothing explains" not in report
    found = fricgen.FrictionModel.load(tmp_path / "diag" / "model.json")
    assert found.presliding.stiffness == pytest.approx(BRISTLES.stiffness, rel=0.1)
    assert main(["emit", str(tmp_path / "diag" / "model.json"), "-o", str(tmp_path / "c"),
                 "--name", "axis", "--sample-time", "0.001"]) == 0, capsys.readouterr().err
    assert "axis_step(" in (tmp_path / "c" / "axis.h").read_text()
