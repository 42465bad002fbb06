"""The named effects' own fits on a residual made of their own force: a one-sided asymmetry, a
thermal drift with and without its time constant, the plausibility of mass and force
constant errors (fricgen/effects/), and joint fits of effects alike enough that
backfitting alone does not separate them (fricgen/diagnose/select.py)."""
import numpy as np
import pytest

from fricgen.diagnose.select import joint_fit, joint_linear
from fricgen.effects import (ConstantLoad, DirectionAsymmetry, ExtraFrictionSource,
                             ForceConstantMismatch, FrictionalLag, InertiaMismatch,
                             PositionFriction, PositionRipple, SensorDelay, ThermalDrift, effect_from_dict)
from fricgen.errors import ModelError


@pytest.fixture(scope="module")
def problem(null_problem):
    return null_problem


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
    truth = ThermalDrift(rate=0.05, offset=0.0, t0=float(t[0]), time_constant=2.0)
    fit = _fit(problem, truth, ThermalDrift, noise=0.05)
    assert fit.offset == 0.0                  # a drift starts from the model's level
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


EXAMPLES = [PositionRipple(amplitude=0.3, period=0.05, phase=1.0), DirectionAsymmetry(0.0, 0.2),
            ConstantLoad(load=-0.4), InertiaMismatch(mass=1.3, nominal_mass=1.0),
            ForceConstantMismatch(force_constant=9.0, nominal_force_constant=10.0),
            ExtraFrictionSource(fc=0.2, fs=0.5, vs=0.01, B=0.3), FrictionalLag(tau=0.05),
            ThermalDrift(rate=0.02, offset=0.01, t0=0.0, time_constant=3.0),
            PositionFriction(amplitude=(0.3, 0.1), period=0.02, phase=(1.0, 2.5)),
            SensorDelay(tau=0.003, nominal_force_constant=20.0)]


@pytest.mark.parametrize("effect", EXAMPLES, ids=lambda e: e.name)
def test_the_linear_parameters_rebuild_the_force(problem, effect):
    """force = the part held + regressors @ values, and new values change only that part."""
    sig = problem.signals
    R, c = effect.linear(sig)
    assert R.shape == (sig.t.size, c.size)
    held = effect.force(sig) - R @ c
    np.testing.assert_allclose(effect.with_coefficients(c).force(sig), effect.force(sig), atol=1e-12)
    other = effect.with_coefficients(0.5 * c)
    np.testing.assert_allclose(other.force(sig), held + R @ (0.5 * c), atol=1e-9)


def test_a_force_constant_error_and_a_drift_are_separated_by_the_joint_fit(problem):
    """-dphi i and a drift of the friction level are alike (the current carries the friction):
    the joint fit recovers both from their sum."""
    t0 = float(problem.signals.t[0])
    truth = [ForceConstantMismatch(force_constant=8.5, nominal_force_constant=problem.force_constant),
             ThermalDrift(rate=0.03, offset=0.0, t0=t0)]
    every = np.arange(problem.rows.size)
    q = problem.with_target(sum(problem.predict(e, every) for e in truth))
    joint = joint_fit(q, [], ForceConstantMismatch)
    joint = joint_fit(q, joint, ThermalDrift)
    fcm, drift = joint
    assert fcm.force_constant - problem.force_constant == pytest.approx(8.5 - problem.force_constant, rel=0.02)
    assert drift.rate == pytest.approx(0.03, rel=0.05)


def test_the_joint_fit_decides_the_asymmetry_side_with_a_force_constant_error(problem):
    """A force-constant error changes the friction level in both directions, so fitted first
    alone the asymmetry may take the wrong side; the joint solve tries both sides."""
    phi = problem.force_constant
    truth = [DirectionAsymmetry(gain_positive=0.0, gain_negative=0.25),
             ForceConstantMismatch(force_constant=1.15 * phi, nominal_force_constant=phi)]
    every = np.arange(problem.rows.size)
    q = problem.with_target(sum(problem.predict(e, every) for e in truth))
    wrong_side = [DirectionAsymmetry(gain_positive=-0.2, gain_negative=0.0),
                  ForceConstantMismatch(force_constant=phi, nominal_force_constant=phi)]
    asym, fcm = joint_linear(q, wrong_side)
    assert asym.gain_positive == 0.0
    assert asym.gain_negative == pytest.approx(0.25, rel=0.02)
    assert fcm.force_constant == pytest.approx(1.15 * phi, rel=0.01)
