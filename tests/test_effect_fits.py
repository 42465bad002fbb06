"""The named effects' own fits on a residual made of their own force: a one-sided asymmetry, a
thermal drift with and without its time constant, and the plausibility of mass and force
constant errors (fricgen/effects/library.py)."""
import numpy as np
import pytest

from fricgen.diagnose.diagnoser import ResidualProblem
from fricgen.effects import (DirectionAsymmetry, ForceConstantMismatch, InertiaMismatch,
                             ThermalDrift, effect_from_dict)
from fricgen.errors import ModelError
from fricgen.sim.logsynth import LogSpec, nominal_model, synthesize_log


@pytest.fixture(scope="module")
def problem():
    model = nominal_model()
    spec = LogSpec(effect="none", seed=5, duration=8.0)
    log = synthesize_log(spec, model)
    return ResidualProblem(log, model, spec.mass, spec.force_constant, 21, 0.3)


def _fit(problem, truth, cls, noise=0.0, seed=0):
    every = np.arange(problem.rows.size)
    target = problem.predict(truth, every)
    target = target + noise * np.std(target) * np.random.default_rng(seed).standard_normal(target.size)
    q = problem.with_target(target)
    return cls.fit(q, q.fit_rows)


@pytest.mark.parametrize("gains", [(0.0, 0.2), (-0.15, 0.0)])
def test_direction_asymmetry_is_fitted_on_one_side(problem, gains):
    fit = _fit(problem, DirectionAsymmetry(*gains), DirectionAsymmetry, noise=0.05)
    side = 0 if gains[0] else 1
    got = (fit.gain_positive, fit.gain_negative)
    assert got[1 - side] == 0.0
    assert abs(got[side] - gains[side]) < 0.05 * abs(gains[side])


def test_a_saturating_drift_gets_its_time_constant(problem):
    t = problem.signals.t
    truth = ThermalDrift(rate=0.05, offset=0.02, t0=float(t[0]), time_constant=2.0)
    fit = _fit(problem, truth, ThermalDrift, noise=0.05)
    assert fit.time_constant == pytest.approx(2.0, rel=0.15)
    assert fit.rate == pytest.approx(0.05, rel=0.15)


def test_a_linear_drift_stays_linear(problem):
    t = problem.signals.t
    truth = ThermalDrift(rate=0.02, offset=0.0, t0=float(t[0]))
    fit = _fit(problem, truth, ThermalDrift, noise=0.3)
    assert fit.time_constant == 0.0
    assert fit.rate == pytest.approx(0.02, rel=0.1)


def test_a_drift_written_before_the_time_constant_still_loads():
    old = {"effect": "thermal_drift", "parameters": {"rate": 0.01, "offset": 0.0, "t0": 0.0}}
    assert effect_from_dict(old) == ThermalDrift(rate=0.01, offset=0.0, t0=0.0, time_constant=0.0)
    bad = {"effect": "thermal_drift", "parameters": {**old["parameters"], "time_constant": -1.0}}
    with pytest.raises(ModelError, match="time_constant must be >= 0"):
        effect_from_dict(bad)


@pytest.mark.parametrize("effect, plausible", [
    (InertiaMismatch(mass=2.0, nominal_mass=1.0), True),
    (InertiaMismatch(mass=0.25, nominal_mass=1.0), True),
    (InertiaMismatch(mass=0.1, nominal_mass=1.0), False),
    (InertiaMismatch(mass=6.0, nominal_mass=1.0), False),
    (ForceConstantMismatch(force_constant=20.0, nominal_force_constant=10.0), True),
    (ForceConstantMismatch(force_constant=1.0, nominal_force_constant=10.0), False),
])
def test_a_mass_or_force_constant_far_off_is_not_read_as_a_mismatch(effect, plausible):
    why = effect.implausible()
    assert (why == "") == plausible
    if not plausible:
        assert "x the nominal one" in why
