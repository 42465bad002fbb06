"""The precision stage with LuGre-type friction (fricgen/sim/precision_axis.py): its steady
sliding friction and its pre-sliding spring against the law, the integration converged in the
substeps, the scenarios' compensations ordered as the physics says, and the identification
log with and without small reversals."""
from dataclasses import replace

import numpy as np
import pytest

from fricgen.sim import precision_axis as pa
from fricgen.sim.precision_axis import (ExactLuGreCompensation, Plant, SteadyStateCompensation,
                                        hold_after_move, identification_log,
                                        random_precision_axis, reversals, simulate)


def excursions(x, h):
    """The displacements between successive turning points of x, a turn counted once x has
    come back by more than h from its extreme."""
    last = ext = float(x[0])
    direction, out = 0, []
    for xi in np.asarray(x, dtype=float).tolist():
        if direction == 0:
            if abs(xi - last) > h:
                direction, ext = (1 if xi > last else -1), xi
        elif direction * (xi - ext) > 0:
            ext = xi
        elif direction * (ext - xi) > h:
            out.append(abs(ext - last))
            last, direction, ext = ext, -direction, xi
    return np.array(out)


def test_the_excursions_see_a_small_reversal_and_not_the_encoder_noise():
    x = np.r_[np.linspace(0, 10, 50), np.linspace(10, 9, 5), np.linspace(9, 20, 50),
              np.linspace(20, 0, 50)]
    x = x + 0.05 * np.sin(np.arange(x.size))
    assert np.allclose(excursions(x, 0.3), [10, 1, 11], atol=0.1)


@pytest.fixture(scope="module")
def axis():
    return random_precision_axis(1)


def test_random_axes_stay_in_their_ranges():
    for seed in range(20):
        ax = random_precision_axis(seed)
        assert 0.5 <= ax.mass <= 3 and 1 <= ax.coulomb <= 4 and 1.2 <= ax.static_ratio <= 2
        assert 0.5e-3 <= ax.stribeck <= 5e-3 and 1 <= ax.shape <= 2.5 and 2 <= ax.viscous <= 20
        assert 5e-6 <= ax.presliding_distance <= 50e-6 and 5000 <= ax.rate <= 10000
        assert 0.05e-6 <= ax.resolution <= 0.5e-6 and abs(ax.asymmetry) <= 0.15
        zeta = ax.sigma1 / (2 * np.sqrt(ax.sigma0 * ax.mass))
        assert 0.2 <= zeta <= 1.0
    assert random_precision_axis(3) == random_precision_axis(3) != random_precision_axis(4)


def test_the_steady_state_compensation_is_the_steady_curve_with_sgn_0_0(axis):
    comp = SteadyStateCompensation(axis)
    v = np.r_[-np.geomspace(1e-5, 0.1, 9), 0.0, np.geomspace(1e-5, 0.1, 9)]
    assert np.allclose([comp.step(float(s)) for s in v], axis.steady_friction(v), rtol=1e-12)
    assert comp.step(0.0) == 0.0
    fcp, fsp, fcn, fsn = axis.levels
    assert axis.steady_friction(1e-9) == pytest.approx(fsp, rel=1e-6)
    assert axis.steady_friction(-1e-9) == pytest.approx(-fsn, rel=1e-6)
    assert axis.steady_friction(100 * axis.stribeck) == pytest.approx(fcp + axis.viscous * 100 * axis.stribeck)


@pytest.mark.parametrize("factor", [-10.0, -0.5, 0.5, 2.0, 10.0])
def test_long_constant_speed_runs_measure_the_steady_friction(axis, factor):
    """The mean measured drive force over the last 0.3 s of a 0.6 s cruise is sgn(v) g(v) + B v."""
    dt, speed = axis.dt, abs(factor) * axis.stribeck
    move = pa._move(0.0, np.sign(factor) * speed * 0.7, speed, dt)
    log = simulate(axis, *move)
    cruise = (log["t"] > 0.35) & (log["t"] < 0.65)
    assert np.allclose(move[1][cruise], factor * axis.stribeck)
    expected = float(axis.steady_friction(factor * axis.stribeck))
    assert np.mean(log["force"][cruise]) == pytest.approx(expected, rel=0.01)
    assert np.mean(log["friction"][cruise]) == pytest.approx(expected, rel=0.01)


def test_below_the_breakaway_the_bristles_are_a_spring(axis):
    """A force ramped slowly (open loop) to 0.3 Fc and held: x = -(Fs/sigma0) ln(1 - F/Fs),
    the LuGre bristle's first loading at vanishing speed, about F / sigma0; back to 0 the
    bristles keep part of the deflection (hysteresis), and nothing slides away."""
    plant, dt = Plant(axis), axis.dt
    fcp, fsp, _, _ = axis.levels
    top, steps = 0.3 * axis.coulomb, int(1.0 / dt)
    for k in range(steps):
        plant.advance(top * (k + 1) / steps, dt)
    for _ in range(int(0.2 / dt)):
        plant.advance(top, dt)
    exact = -fsp / axis.sigma0 * np.log(1 - top / fsp)
    assert plant.x == pytest.approx(exact, rel=0.01)
    assert plant.x == pytest.approx(top / axis.sigma0, rel=0.15)
    assert abs(plant.v) < 1e-6
    for k in range(steps):
        plant.advance(top * (1 - (k + 1) / steps), dt)
    for _ in range(int(0.2 / dt)):
        plant.advance(0.0, dt)
    assert 0.0 < plant.x < 0.5 * exact


def test_halving_the_substep_barely_changes_the_scenarios():
    ax = random_precision_axis(2)
    fine = replace(ax, substeps=2 * ax.substeps)
    assert reversals(fine)["peak"] == pytest.approx(reversals(ax)["peak"], rel=0.005)
    a = pa.slow_speeds(ax)["rms"]
    b = pa.slow_speeds(fine)["rms"]
    assert b == pytest.approx(a, rel=0.005)


@pytest.mark.parametrize("seed", [1, 5])
def test_the_exact_lugre_observer_cuts_the_quadrant_glitch(seed):
    ax = random_precision_axis(seed)
    none = reversals(ax, None)["peak"]
    steady = reversals(ax, SteadyStateCompensation(ax), use_reference=True)["peak"]
    exact = reversals(ax, ExactLuGreCompensation(ax, ax.dt), use_reference=True)["peak"]
    assert exact < none / 10 and exact < steady / 4
    assert exact < 3 * ax.resolution                    # the encoder's level
    # the steady curve flips by 2 Fs at the reversal, the friction only over the pre-sliding
    # distance: it over-compensates
    assert steady > none


def test_the_exact_lugre_observer_on_the_measured_velocity_also_works(axis):
    none = reversals(axis, None)["peak"]
    exact = reversals(axis, ExactLuGreCompensation(axis, axis.dt), use_reference=False)["peak"]
    assert exact < none / 10


def test_the_hold_settles_within_two_counts_without_hunting(axis):
    for comp in (None, SteadyStateCompensation(axis), ExactLuGreCompensation(axis, axis.dt)):
        hold = hold_after_move(axis, comp, use_reference=True)
        assert hold["amplitude"] <= 2 and hold["max_error"] <= 2


def test_a_coulomb_switch_on_the_measured_velocity_hunts_at_hold(axis):
    """sgn of the encoder's velocity estimate flickers at rest: +-Fs of chatter."""
    assert hold_after_move(axis, SteadyStateCompensation(axis), use_reference=False)["amplitude"] > 10


@pytest.fixture(scope="module")
def logs():
    ax = random_precision_axis(13)         # 5.6 kHz (a short log), pre-sliding distance 37 um
    return ax, identification_log(ax, 7, presliding=True), identification_log(ax, 7, presliding=False)


def test_the_identification_log_is_uniform_and_bounded(logs):
    ax, with_small, without = logs
    for log in (with_small, without):
        assert set(log) == {"t", "x", "force"}
        assert np.allclose(np.diff(log["t"]), ax.dt)
        assert log["t"].size <= 600_000 and log["t"][-1] <= 60.0
        counts = log["x"] / ax.resolution - 0.5              # read at the count's centre
        assert np.allclose(counts, np.round(counts), atol=1e-6)
        assert np.all(np.abs(log["force"]) < ax.force_limit)
    # the sliding part is the same experiment in both, the noise drawn from the same seed
    n = without["t"].size
    assert np.array_equal(with_small["x"][:n], without["x"])


def test_only_the_presliding_log_reverses_within_the_presliding_distance(logs):
    ax, with_small, without = logs
    d = ax.presliding_distance
    small = excursions(with_small["x"], 0.1 * d)
    assert np.sum(small < d) >= 10 and np.sum(small < 0.7 * d) >= 4
    assert excursions(without["x"], 0.1 * d).min() > 5 * d
    # the sliding part reaches 50 vs each way
    v = np.diff(without["x"]) / ax.dt
    assert v.max() > 40 * ax.stribeck and v.min() < -40 * ax.stribeck
