"""The named sensor delay (fricgen/effects/timing.py): its fit on signals shifted by
interpolation (not by its own formula), model.json round trip and refusal, the held-out
simulation it drives, and the diagnosis of scenario logs that hide a delay or a mass error."""
import numpy as np
import pytest

from conftest import assert_cli_names_only_with
from fricgen.diagnose.diagnoser import Diagnoser, candidates_with, diagnose
from fricgen.effects import EFFECTS, InertiaMismatch, SensorDelay, effect_from_dict
from fricgen.errors import ModelError
from fricgen.sim.effect_law import EffectLaw
from fricgen.sim.logsynth import nominal_model
from fricgen.sim.scenarios import make_scenario

FIXED = {"rate_hz": 500.0, "duration_s": 15.0}


@pytest.fixture(scope="module")
def problem(null_problem):
    return null_problem


def _delayed_target(problem, samples):
    """The residual of a log whose motion is logged ``samples`` late, its current held over each
    sample: m a + F(v) = phi i(t - 1/2 - d), so phi (i(t) - i(t - 1/2 - d)), with i read by cubic
    interpolation, independent of the effect's own linear interpolation."""
    from scipy.interpolate import CubicSpline
    i = problem.signals.i
    k = np.arange(i.size, dtype=float)
    late = i - CubicSpline(k, i)(np.clip(k - 0.5 - samples, 0, k[-1]))
    return problem.at_rows(problem.force_constant * late, np.arange(problem.rows.size))


@pytest.mark.parametrize("samples", [1.0, 2.0, 3.0, -2.0])
def test_the_fit_recovers_a_delay_of_whole_samples(problem, samples):
    q = problem.with_target(_delayed_target(problem, samples))
    fit = SensorDelay.fit(q, q.fit_rows)
    assert fit.tau == pytest.approx(samples * problem.sample_time, rel=0.2)
    assert fit.nominal_force_constant == problem.force_constant


def test_a_residual_of_noise_alone_fits_the_delay_whose_force_vanishes(problem):
    """phi (i(t) - i(t - h - tau)) vanishes at tau = -h: a residual without the held current's
    half sample (a log of the measured current) and without delay."""
    from fricgen.effects.timing import HOLD
    rng = np.random.default_rng(0)
    noise = 0.05 * rng.standard_normal(problem.rows.size)
    q = problem.with_target(noise)
    fit = SensorDelay.fit(q, q.fit_rows)
    assert abs(fit.tau / problem.sample_time + HOLD) < 0.2


def test_the_delay_is_not_a_mass_error(problem):
    """A mass error acts on m a only: the delay's fit explains little of it, and the mass
    error's fit explains little of a delay."""
    every = np.arange(problem.rows.size)
    inertia = problem.predict(InertiaMismatch(mass=1.3 * problem.mass, nominal_mass=problem.mass), every)
    delayed = _delayed_target(problem, 2.0)
    for target, cls in ((inertia, SensorDelay), (delayed, InertiaMismatch)):
        q = problem.with_target(target)
        fit = cls.fit(q, q.fit_rows)
        rest = target[q.fit_rows] - problem.predict(fit, q.fit_rows)
        assert np.sum(rest ** 2) > 0.3 * np.sum(target[q.fit_rows] ** 2), cls.name


def test_the_effect_is_registered_and_not_emitted_to_c():
    assert EFFECTS["sensor_delay"] is SensorDelay
    assert not SensorDelay.in_xv and SensorDelay(tau=0.001, nominal_force_constant=20.0).n_params == 1


def test_the_delay_round_trips_and_bad_values_are_refused():
    e = SensorDelay(tau=-0.0015, nominal_force_constant=20.0)          # the current logged 1.5 ms late
    assert effect_from_dict(e.to_dict()) == e
    for tau, message in ((1.0, r"within \+-0.1 s"), (float("nan"), "finite number"),
                         ("late", "finite number")):
        d = {"effect": "sensor_delay", "parameters": {"tau": tau, "nominal_force_constant": 20.0}}
        with pytest.raises(ModelError, match=message) as info:
            effect_from_dict(d)
        assert "\n" not in str(info.value)
    with pytest.raises(ModelError, match="nominal_force_constant must be > 0"):
        effect_from_dict({"effect": "sensor_delay", "parameters": {"tau": 0.0, "nominal_force_constant": -1.0}})


@pytest.mark.parametrize("samples, refused", [(0.0, True), (0.49, True), (-0.49, True),
                                                (0.51, False), (-0.51, False), (3.0, False)])
def test_a_delay_within_half_a_sample_is_unresolved(samples, refused):
    """Where in each sample a drive reads its signals is not logged: no delay below half a
    sample is named, whatever the sample time."""
    for ts in (1e-3, 2.5e-4):
        delay = SensorDelay(tau=samples * ts, nominal_force_constant=20.0)
        why = delay.unresolved(ts)
        assert bool(why) == refused, why
        assert delay.refused(ts) == why        # what the selection and the refinement ask
    assert InertiaMismatch(mass=3.0, nominal_mass=2.0).unresolved(1e-3) == ""


def test_the_law_leaves_the_delay_out_of_the_forces():
    model = nominal_model()
    law = EffectLaw(model, [SensorDelay(tau=0.002, nominal_force_constant=20.0)], mass=4.0, force_constant=20.0)
    v = np.array([-0.1, 0.05, 0.2])
    assert np.array_equal(law.sliding_friction(v, np.zeros(3), np.abs(v)), model(v))
    assert law.input_delay == 0.002 and law.mass == 4.0


@pytest.fixture(scope="module")
def delayed_run():
    sc = make_scenario(14, ("oov:sensor_delay",), controller="pid", **FIXED)
    return sc, diagnose(sc.log, sc.model, sc.mass, sc.force_constant, candidates=candidates_with("sensor_delay"))


def test_a_hidden_sensor_delay_is_named(delayed_run):
    sc, d = delayed_run
    assert [e.name for e in d.added_] == ["sensor_delay"], [(s.effect, s.reason) for s in d.steps_]
    truth = sc.conditions["magnitudes"]["oov:sensor_delay"]["delay_s"]
    assert d.added_[0].tau == pytest.approx(truth, rel=0.3)
    assert d.gap_after_ < d.gap_before_


def test_a_hidden_frictional_lag_is_named_as_itself():
    """Friction memory lags the velocity-weakening part alone: not read as a delay."""
    sc = make_scenario(14, ("frictional_lag",), controller="pid", **FIXED)
    d = Diagnoser(candidates=candidates_with("sensor_delay")).fit(sc.log, sc.model, sc.mass, sc.force_constant)
    assert [e.name for e in d.added_] == ["frictional_lag"], [(s.effect, s.reason) for s in d.steps_]


def test_the_delay_is_considered_only_when_asked_for(delayed_run):
    """By default diagnose leaves the delay out (on short closed-loop logs a delay of a sample
    stands in for friction dynamics); the same log then gets no sensor_delay."""
    sc, asked = delayed_run
    d = diagnose(sc.log, sc.model, sc.mass, sc.force_constant)
    assert "sensor_delay" in {s.effect for s in asked.steps_}
    assert "sensor_delay" not in {s.effect for s in d.steps_}
    assert "sensor_delay" not in {c["effect"] for c in d.summary()["candidates"]}


def test_the_cli_considers_the_delay_with_its_flag(tmp_path):
    sc = make_scenario(14, ("oov:sensor_delay",), controller="pid", **FIXED)
    assert_cli_names_only_with("--sensor-delay", "sensor_delay", sc, tmp_path)
