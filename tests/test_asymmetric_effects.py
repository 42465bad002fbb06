"""Named effects on an asymmetric model (format version 2): every effect that reads the friction
curve reads the curve of the direction it is evaluated in, in Python (force, fit) and in the
emitted NAME_force_xv."""
import shutil

import numpy as np
import pytest

from fricgen import codegen
from fricgen.codegen.cbuild import build
from fricgen.codegen.twin import force_xv_f32
from fricgen.diagnose.residual import ResidualProblem
from fricgen.effects import (DirectionAsymmetry, ExtraFrictionSource, FrictionalLag, Signals,
                             ThermalDrift, force_xv, with_effects)
from fricgen.model import Direction, FrictionModel, Scaling
from fricgen.networks import StribeckCurve
from fricgen.sim.effect_law import EffectLaw
from fricgen.sim.logsynth import LogSpec, synthesize_log

CC = shutil.which("gcc") or shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler")


def _curve(shape, level, drop, x_s, v_sat, k_out, viscous):
    """A Direction of eq. (3) whose AIM is eq. (1): S(0) = level + drop, S(v_sat) ~ level (N)."""
    aim = StribeckCurve(shape, k_out * level, np.array([k_out * drop]), np.array([x_s]))
    return Direction(aim, Scaling(1.0 / v_sat, k_out), viscous, v_sat)


@pytest.fixture(scope="module")
def asym():
    """v >= 0: 10 N + a 10 N Gaussian drop; v < 0: 25 N + a 30 N exponential drop, its own
    v_sat, K_out and B: the two directions differ at every speed."""
    positive = _curve("gauss", 10.0, 10.0, 0.2, 0.06, 0.05, 8.0)
    negative = _curve("exponential", 25.0, 30.0, 0.1, 0.09, 0.02, 20.0)
    return FrictionModel.from_directions(positive, negative, name="fa")


def _by_direction(v, positive, negative):
    """``positive`` where v >= 0, ``negative`` where v < 0 (each an array of v's shape)."""
    return np.where(np.asarray(v) < 0, negative, positive)


def _lag_by_hand(model, v, lagged):
    """sgn(v) [S(s) - S(|v|)] with S of the curve of v's direction (model.positive/negative)."""
    speed = np.abs(v)
    return np.sign(v) * _by_direction(
        v, model.positive.stribeck(lagged) - model.positive.stribeck(speed),
        model.negative.stribeck(lagged) - model.negative.stribeck(speed))


def _moving_both_ways(n=400, ts=1e-3):
    t = np.arange(n) * ts
    v = 0.08 * np.sin(2 * np.pi * 3.0 * t) + 0.02 * np.sin(2 * np.pi * 17.0 * t)
    return t, v, ts


def test_the_curve_an_effect_reads_is_that_of_the_direction(asym):
    _, v, ts = _moving_both_ways()
    for tabulate in (False, True):
        sig = Signals(asym, v=v, sample_time=ts, tabulate=tabulate)
        speed = np.abs(v)
        hand = _by_direction(v, asym.positive.stribeck(speed), asym.negative.stribeck(speed))
        np.testing.assert_allclose(sig.stribeck_speed, hand, rtol=0, atol=1e-4)
        np.testing.assert_allclose(sig.friction, asym.force(v), rtol=1e-15)


def test_frictional_lag_reads_the_negative_curve_below_zero(asym):
    t, v, ts = _moving_both_ways()
    lag = FrictionalLag(tau=0.02)
    for tabulate, atol in ((False, 1e-12), (True, 1e-4)):
        sig = Signals(asym, t=t, v=v, sample_time=ts, tabulate=tabulate)
        hand = _lag_by_hand(asym, v, sig.lagged_speed(lag.tau))
        assert np.max(np.abs(hand[v < 0])) > 1.0                    # a lag worth the test
        np.testing.assert_allclose(lag.force(sig), hand, rtol=0, atol=atol)


def test_the_simulated_friction_memory_reads_each_directions_curve(asym):
    """EffectLaw.sliding_friction with the lag state s of a simulation (eq. 18)."""
    v = np.array([-0.05, -0.01, 0.01, 0.05])
    s = np.array([0.002, 0.03, 0.002, 0.03])
    law = EffectLaw(asym, [FrictionalLag(tau=0.02)], mass=4.0, force_constant=20.0)
    got = law.sliding_friction(v, np.zeros(4), s)
    np.testing.assert_allclose(got, asym.force(v) + _lag_by_hand(asym, v, s), rtol=1e-12)


def test_friction_scaling_effects_read_the_negative_curve_below_zero(asym):
    v = np.array([-0.2, -0.05, -0.004, 0.0, 0.004, 0.05, 0.2])
    t = np.full(v.size, 3.0)
    sig = Signals(asym, t=t, x=np.zeros(v.size), v=v)
    hand = _by_direction(v, np.sign(v) * asym.positive.magnitude(v), -asym.negative.magnitude(v))
    np.testing.assert_allclose(DirectionAsymmetry(0.1, -0.3).force(sig),
                               np.where(v > 0, 0.1, np.where(v < 0, -0.3, 0.0)) * hand, rtol=1e-14)
    drift = ThermalDrift(rate=0.01, offset=0.02, t0=0.0)
    np.testing.assert_allclose(drift.force(sig), (0.02 + 0.01 * 3.0) * hand, rtol=1e-14)


@pytest.fixture(scope="module")
def lag_problem(asym):
    log = synthesize_log(LogSpec("none", seed=5, duration=8.0), asym)
    return ResidualProblem(log, asym, 4.0, 20.0, 21, 0.3)


@pytest.mark.parametrize("tau", [0.005, 0.3])
def test_frictional_lag_is_fitted_with_each_directions_curve(asym, lag_problem, tau):
    """A residual made, by hand, of a lag of each direction's curve gives back its tau, and
    the fitted lag explains it."""
    sig = lag_problem.signals
    assert np.mean(sig.v[lag_problem.rows] < 0) > 0.3                  # both directions fitted
    hand = _lag_by_hand(asym, sig.v, sig.lagged_speed(tau))
    target = lag_problem.at_rows(hand, np.arange(lag_problem.rows.size))
    q = lag_problem.with_target(target)
    fit = FrictionalLag.fit(q, q.fit_rows)
    assert fit.tau == pytest.approx(tau, rel=0.05)
    left = target[q.fit_rows] - q.predict(fit, q.fit_rows)
    assert np.sum(left ** 2) < 1e-3 * np.sum(target[q.fit_rows] ** 2)


XV_EFFECTS = [DirectionAsymmetry(gain_positive=-0.05, gain_negative=0.2),
              ExtraFrictionSource(fc=2.0, fs=6.0, vs=0.03, B=15.0, shape="gauss")]


@needs_cc
def test_force_xv_in_c_reads_the_negative_curve_below_zero(asym, tmp_path):
    """C NAME_force_xv of the asymmetric model vs its float32 twin and vs the hand computation
    from each direction's curve (float32 rounding: 1e-5 of the force range)."""
    augmented = with_effects(asym, XV_EFFECTS + [FrictionalLag(tau=0.02)])
    codegen.emit(augmented, tmp_path, "fa")
    lib = build(tmp_path, "fa.h", "float fa_force(float v);\nfloat fa_force_xv(float v, float x);\n",
                build_dir=tmp_path / "build")
    v = np.concatenate([np.linspace(-0.3, 0.3, 601), [0.0, 1e-7, -1e-7]]).astype(np.float32)
    x = np.zeros_like(v)
    base = np.array([lib.fa_force(float(a)) for a in v], dtype=np.float32)
    c = np.array([lib.fa_force_xv(float(a), float(b)) for a, b in zip(v, x)], dtype=np.float32)
    twin = force_xv_f32(augmented, v, x, base=base)
    scale = float(np.max(np.abs(c)))
    assert np.max(np.abs(c.astype(float) - twin)) <= 8 * np.finfo(np.float32).eps * scale
    vd = v.astype(float)
    F = _by_direction(vd, np.sign(vd) * asym.positive.magnitude(vd), -asym.negative.magnitude(vd))
    asymmetry = np.where(vd > 0, -0.05, np.where(vd < 0, 0.2, 0.0)) * F
    hand = F + asymmetry + XV_EFFECTS[1].force(Signals(asym, v=vd))
    np.testing.assert_allclose(force_xv(augmented, vd, x.astype(float)), hand, rtol=1e-14, atol=1e-12)
    assert np.max(np.abs(c - hand)) / scale < 1e-5
