"""The named actuator saturation (fricgen/effects/actuator.py): its fit on residuals written out
here (the cubic form, and a tanh saturation it does not share), the refusal of a force constant
that grows with the current, the simulation that takes the loss from the motor's force,
model.json, and the diagnosis of a scenario log whose drive saturates as tanh."""
import numpy as np
import pytest

from conftest import assert_cli_names_only_with
from fricgen.diagnose.diagnoser import Diagnoser, candidates_with, diagnose
from fricgen.effects import EFFECTS, ActuatorSaturation, effect_from_dict
from fricgen.errors import ModelError
from fricgen.sim.axis import AxisState, MotorAxis
from fricgen.sim.effect_law import EffectLaw
from fricgen.sim.logsynth import nominal_model
from fricgen.sim.scenarios import make_scenario


@pytest.fixture(scope="module")
def problem(null_problem):
    return null_problem


def _target(problem, loss_of_current, noise=0.2, seed=0):
    """The residual phi i - (the drive's force) for a drive whose force is phi (i - loss(i)),
    smoothed as the residual is, plus white noise of ``noise`` times its standard deviation."""
    raw = problem.force_constant * loss_of_current(np.asarray(problem.signals.i, dtype=float))
    target = problem.at_rows(raw, np.arange(problem.rows.size))
    target = target + noise * np.std(target) * np.random.default_rng(seed).standard_normal(target.size)
    return problem.with_target(target)


def _peak(problem):
    return float(np.percentile(np.abs(problem.signals.i), 99))


@pytest.mark.parametrize("droop", [0.05, 0.3])
def test_the_fit_recovers_the_droop_at_the_peak_current(problem, droop):
    peak = _peak(problem)
    q = _target(problem, lambda i: droop * i * (i / peak) ** 2)
    fit = ActuatorSaturation.fit(q, q.fit_rows)
    assert fit.peak_current == pytest.approx(peak, rel=1e-9)
    assert fit.droop == pytest.approx(droop, rel=0.05)
    assert fit.implausible() == ""


def test_a_tanh_saturation_is_read_as_a_droop_that_explains_most_of_it(problem):
    """The generator's shape is not the effect's: i_s tanh(i / i_s), 30 % down at the peak."""
    i_s = _peak(problem) / 1.2
    q = _target(problem, lambda i: i - i_s * np.tanh(i / i_s), noise=0.0)
    fit = ActuatorSaturation.fit(q, q.fit_rows)
    assert 0.15 < fit.droop < 0.45 and fit.implausible() == ""
    left = q.target[q.fit_rows] - q.predict(fit, q.fit_rows)
    assert np.mean(left ** 2) < 0.1 * np.mean(q.target[q.fit_rows] ** 2)


def test_a_force_constant_that_grows_with_the_current_is_refused(problem):
    peak = _peak(problem)
    q = _target(problem, lambda i: -0.1 * i * (i / peak) ** 2)
    fit = ActuatorSaturation.fit(q, q.fit_rows)
    assert fit.droop < 0 and "grows with the current" in fit.implausible()
    assert "beyond the 50%" in ActuatorSaturation(0.6, peak, 20.0).implausible()


def test_the_simulation_takes_the_loss_from_the_motor_force():
    """The axis driven by i under the effect moves as the ideal axis driven by i (1 - d (i/i_pk)^2)."""
    model = nominal_model()
    sat = ActuatorSaturation(droop=0.2, peak_current=3.0, nominal_force_constant=20.0)
    law = EffectLaw(model, [sat], mass=4.0, force_constant=20.0)
    ideal = EffectLaw(model, [], mass=4.0, force_constant=20.0)
    i = np.array([-4.0, -1.0, 0.5, 3.0])
    np.testing.assert_allclose(law.thrust(i), 20.0 * i * (1 - 0.2 * (i / 3.0) ** 2), rtol=1e-12)
    assert np.array_equal(law.sliding_friction(i, np.zeros(4), np.abs(i)), ideal.sliding_friction(i, np.zeros(4), np.abs(i)))
    start = AxisState.of(np.zeros(4), np.full(4, 0.05), np.zeros(4))
    a = MotorAxis(law).karnopp(start, i, 1e-3, 10)
    b = MotorAxis(ideal).karnopp(start, i * (1 - 0.2 * (i / 3.0) ** 2), 1e-3, 10)
    np.testing.assert_allclose(a.v, b.v, rtol=1e-12, atol=1e-15)
    batch = EffectLaw.batch(model, [[sat], []], mass=4.0, force_constant=20.0)
    np.testing.assert_allclose(batch.thrust(np.array([3.0, 3.0])), [20.0 * 3.0 * 0.8, 60.0], rtol=1e-12)


def test_the_effect_is_registered_round_trips_and_bad_values_are_refused():
    assert EFFECTS["actuator_saturation"] is ActuatorSaturation and not ActuatorSaturation.in_xv
    sat = ActuatorSaturation(droop=0.12, peak_current=8.5, nominal_force_constant=20.0)
    assert effect_from_dict(sat.to_dict()) == sat and sat.n_params == 1
    assert sat.for_log(4.0, 25.0, 3.0) == ActuatorSaturation(0.12, 8.5, 25.0)
    bad = sat.to_dict()
    bad["parameters"]["peak_current"] = 0.0
    with pytest.raises(ModelError, match="peak_current must be > 0"):
        effect_from_dict(bad)


@pytest.fixture(scope="module")
def saturated_run():
    sc = make_scenario(1100, ("oov:actuator_saturation",), rate_hz=1000.0, duration_s=15.0)
    return sc, diagnose(sc.log, sc.model, sc.mass, sc.force_constant,
                        candidates=candidates_with("actuator_saturation"))


@pytest.mark.slow
def test_a_drive_that_saturates_as_tanh_is_named_and_closes_the_gap_as_the_truth(saturated_run):
    sc, d = saturated_run
    assert [e.name for e in d.added_] == ["actuator_saturation"], [(s.effect, s.reason) for s in d.steps_]
    truth = Diagnoser().held_out_gap(sc.truth_log(), sc.model, sc.truth_mass(), sc.force_constant)
    assert d.gap_after_ <= 1.1 * truth
    assert 0.0 < d.added_[0].droop <= 0.5


@pytest.mark.slow
def test_the_saturation_is_considered_only_when_asked_for(saturated_run):
    """By default diagnose leaves it out (it would take the place of a force-constant or mass
    error among the sets a step tries); the same log then names something else."""
    sc, asked = saturated_run
    d = diagnose(sc.log, sc.model, sc.mass, sc.force_constant)
    assert "actuator_saturation" not in {s.effect for s in d.steps_}
    assert "actuator_saturation" not in {c["effect"] for c in d.summary()["candidates"]}
    assert candidates_with("actuator_saturation") == [n for n in EFFECTS if n not in ("sensor_delay", "presliding")]


@pytest.mark.slow
def test_the_cli_considers_the_saturation_with_its_flag(saturated_run, tmp_path):
    assert_cli_names_only_with("--saturation", "actuator_saturation", saturated_run[0], tmp_path)
