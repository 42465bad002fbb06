"""The joints with load- and temperature-dependent friction (fricgen/sim/loaded_joint.py): their
logs against force = J a + L + F + o by inverse dynamics, the warming duty's temperatures, the
laws' driving and back-driving quadrants and their oils, the sensors, the seeds, and the
held-out and constant-conditions logs against the training's."""
import math

import numpy as np
import pytest

from fricgen.sim import loaded_joint as lj
from fricgen.sim.loaded_joint import (HarmonicJoint, PlanetaryJoint, logs, random_harmonic_joint,
                                      random_planetary_joint)

RANDOM = {"harmonic": random_harmonic_joint, "planetary": random_planetary_joint}
SEED = 1


@pytest.fixture(scope="module", params=sorted(RANDOM))
def joint(request):
    return RANDOM[request.param](SEED)


@pytest.fixture(scope="module")
def runs(joint):
    return logs(joint, SEED)


@pytest.fixture(scope="module")
def exact_duty(joint):
    return joint.duty_log(SEED, noise=False)[0]


def central(x, dt):
    """(v, a) of x by central differences, NaN at the ends."""
    v, a = np.full(x.size, np.nan), np.full(x.size, np.nan)
    v[1:-1] = (x[2:] - x[:-2]) / (2 * dt)
    a[1:-1] = (x[2:] - 2 * x[1:-1] + x[:-2]) / dt ** 2
    return v, a


def test_random_joints_stay_in_their_ranges():
    for seed in range(5):
        h = random_harmonic_joint(seed)
        assert 19 <= h.peak_gravity <= 150 and 1 <= h.inertia <= 10 and 2 <= h.coulomb <= 10
        assert 1.2 <= h.static / h.coulomb <= 2 and 0.06 <= h.slope_driving <= 0.15
        assert 0.35 <= h.slope_back / h.slope_driving <= 0.7 and 5 <= h.viscous <= 40
        assert 2 <= h.viscosity_ratio <= 4 and 300 <= h.time_constant <= 600
        p = random_planetary_joint(seed)
        assert 28 <= p.peak_gravity <= 144 and 2 <= p.coulomb <= 10 and 5 <= p.viscous <= 40
        assert 0.8 <= p.forward <= 0.95 and p.forward_low < p.forward and p.back_low < p.back
        assert 2 <= p.oil_ratio <= 4 and p.back <= p.forward


def test_seeds_are_reproducible():
    for make in RANDOM.values():
        assert make(3) == make(3) != make(4)
        first, again, other = (make(s).constant_log(s) for s in (3, 3, 4))
        assert all(np.array_equal(first[k], again[k]) for k in first)
        assert not np.array_equal(first["force"][:1000], other["force"][:1000])


def test_the_exact_log_is_the_inverse_dynamics_of_its_position(joint, exact_duty):
    """J a + L(q) + F(v, L, T) + o from the position's central differences is the logged force
    wherever the joint moves (the differences' error: jerk steps, the friction's bends)."""
    log = exact_duty
    v, a = central(log["x"], 1.0 / joint.rate)
    moving = np.abs(log["true_v"]) > 0.01
    moving[[0, -1]] = False
    predicted = (joint.inertia * a + log["load"] + joint.offset
                 + joint.true_friction(v, log["load"], log["temperature"]))
    residual = np.abs(log["force"] - predicted)[moving]
    assert np.median(residual) < 1e-4
    assert np.percentile(residual, 99) < 0.02 * joint.coulomb
    assert np.max(np.abs(v[moving] - log["true_v"][moving])) < 0.01


def shares(joint, log):
    """The payload shares the log's load holds: L / L(q, no payload) - 1 over the full one's."""
    x = log["true_x"]
    loaded = np.abs(joint.load(x, 0.0)) > 0.2 * joint.load(-getattr(joint, "phase", 0.0), 0.0)
    extra = log["load"][loaded] / joint.load(x[loaded], 0.0) - 1.0
    return set(np.round(extra / (joint.load(0.3, 1.0) / joint.load(0.3, 0.0) - 1.0), 6))


def test_the_load_is_the_gravity_of_the_link_and_payload(joint, exact_duty):
    assert shares(joint, exact_duty) == {0.0, 1.0}
    assert np.max(np.abs(exact_duty["load"])) == pytest.approx(joint.peak_gravity, rel=0.01)


def test_the_warming_duty_warms_the_joint_from_25_to_about_60(joint, exact_duty):
    temperature = exact_duty["true_temperature"]
    assert temperature[0] == lj.AMBIENT
    assert 55 <= temperature[-1] <= 65
    assert temperature.max() <= 65
    halfway = temperature[int(temperature.size / 2)]
    assert halfway - lj.AMBIENT > 0.6 * (temperature[-1] - lj.AMBIENT)    # first order: concave
    assert exact_duty["t"][-1] >= lj.DUTY_RUNS * lj.RUN_SECONDS


@pytest.mark.parametrize("seed", [11, 12])
def test_other_seeds_warm_to_55_65_too(seed):
    for make in RANDOM.values():
        log, end = make(seed).duty_log(seed, noise=False)
        assert 55 <= log["true_temperature"][-1] <= 65 and end[0] == pytest.approx(
            log["true_temperature"][-1], abs=0.5)


def test_the_harmonic_joint_loses_more_driving_than_back_driving():
    h = random_harmonic_joint(5)
    v, load, temperature = np.array([0.05, 0.5, 1.2]), 60.0, 40.0
    driving = h.true_friction(v, load, temperature)
    back = h.true_friction(v, -load, temperature)
    unloaded = h.true_friction(v, 0.0, temperature)
    assert np.all(driving > back) and np.all(back > unloaded)
    theta = h.viscosity(temperature) ** h.level_exponent
    assert np.allclose(driving - back, theta * (h.slope_driving - h.slope_back) * load)
    assert np.allclose(h.true_friction(-v, -load, temperature), -driving)


@pytest.mark.parametrize("forward, back, driving_more", [(0.9, 0.9, True), (0.9, 0.88, False)])
def test_the_planetary_joints_quadrants_follow_its_efficiencies(forward, back, driving_more):
    """Lifting costs (1 / eta_f - 1) |L|, lowering (1 - eta_b) |L|: more driving where
    eta_b > 2 - 1 / eta_f (0.889 for eta_f = 0.9)."""
    p = PlanetaryJoint(forward=forward, forward_low=forward, back=back, back_low=back)
    v, load = np.array([0.1, 1.0]), 80.0
    driving = p.true_friction(v, load, 25.0)
    lowering = p.true_friction(v, -load, 25.0)
    assert np.allclose(driving - lowering, ((1 / forward - 1) - (1 - back)) * load)
    assert np.all((driving > lowering) == driving_more)


def test_the_planetary_efficiencies_fall_at_low_speed():
    p = random_planetary_joint(5)
    slow, fast = p.true_friction(np.array([0.002, 1.5]), 50.0, 25.0) - p.true_friction(
        np.array([0.002, 1.5]), 0.0, 25.0)
    assert slow > fast > 0
    assert slow == pytest.approx((1 / p.efficiencies(0.002)[0] - 1) * 50.0)


@pytest.mark.parametrize("make", sorted(RANDOM))
def test_the_viscous_term_falls_with_the_temperature_by_the_oils_ratio(make):
    joint = RANDOM[make](6)
    temperatures = np.array([25.0, 35.0, 45.0, 60.0])
    slope = np.array([(joint.true_friction(1.4, 0.0, t) - joint.true_friction(1.0, 0.0, t)) / 0.4
                      for t in temperatures])
    assert np.all(np.diff(slope) < 0)
    ratio = joint.viscosity_ratio if make == "harmonic" else joint.oil_ratio
    assert slope[0] / slope[-1] == pytest.approx(ratio, rel=1e-3)
    assert slope[0] == pytest.approx(joint.viscous, rel=1e-3)


def test_the_harmonic_levels_fall_more_weakly_than_the_viscous_term():
    h = random_harmonic_joint(7)
    level = [h.true_friction(1.0, 0.0, t) - h.viscous * h.viscosity(t) for t in (25.0, 60.0)]
    assert 1.0 < level[0] / level[1] < h.viscosity_ratio
    assert level[0] / level[1] == pytest.approx(h.viscosity_ratio ** h.level_exponent, rel=1e-3)


def test_the_oils_follow_vogel_and_walther():
    h = HarmonicJoint(viscosity_ratio=3.0, vogel_temperature=170.0)
    t = np.array([20.0, 40.0, 70.0])
    inverse = 1.0 / (t + lj.KELVIN - 170.0)
    log_mu = np.log(h.viscosity(t))
    assert (log_mu[2] - log_mu[1]) / (inverse[2] - inverse[1]) == pytest.approx(
        (log_mu[1] - log_mu[0]) / (inverse[1] - inverse[0]))
    p = PlanetaryJoint(oil_viscosity=220.0, oil_ratio=3.0)
    nu = 220.0 * p.viscosity(t)
    walther = np.log10(np.log10(nu + 0.7))
    log_t = np.log10(t + lj.KELVIN)
    slopes = np.diff(walther) / np.diff(log_t)
    assert slopes[1] == pytest.approx(slopes[0])
    assert p.viscosity(lj.HOT) == pytest.approx(1 / 3.0)
    assert h.viscosity(lj.HOT) == pytest.approx(1 / 3.0)


def test_resting_cools_the_joint_toward_the_ambient():
    h = HarmonicJoint(time_constant=400.0)
    assert h.rested((60.0,), 400.0)[0] - lj.AMBIENT == pytest.approx(35.0 / math.e, rel=1e-6)
    p = random_planetary_joint(2)
    oil, housing = p.rested((60.0, 50.0), 60.0)
    assert lj.AMBIENT < housing < oil < 60.0


def test_the_sensors(joint):
    exact, noisy = joint.constant_log(SEED, noise=False), joint.constant_log(SEED)
    q = joint.resolution
    assert q == pytest.approx(2 * math.pi / 2 ** 17)
    counts = noisy["x"] / q - 0.5
    assert np.allclose(counts, np.round(counts), atol=1e-6)
    assert np.max(np.abs(noisy["x"] - exact["x"])) <= q / 2 + 1e-12
    assert np.std(noisy["force"] - exact["force"]) == pytest.approx(joint.force_noise, rel=0.05)
    temperature = noisy["temperature"]
    assert np.allclose(temperature * 10, np.round(temperature * 10), atol=1e-6)
    assert 0.07 < np.std(temperature - exact["temperature"]) < 0.14


def test_the_constant_conditions_log_has_no_load_and_one_temperature(runs):
    log = runs["constant"]
    assert np.all(log["load"] == 0.0)
    true = log["true_temperature"]
    assert np.all(true == true[0])
    assert lj.CONSTANT_TEMPERATURE[0] <= true[0] <= lj.CONSTANT_TEMPERATURE[1]
    assert np.max(np.abs(log["temperature"] - true[0])) < 0.6
    assert np.mean(np.abs(log["true_v"]) > 0.02) > 0.5


def test_the_heldout_log_differs_in_payload_and_temperature_range(joint, runs):
    train, held = runs["train"], runs["heldout"]
    assert shares(joint, train) == {0.0, 1.0}
    assert shares(joint, held) == ({0.5} if isinstance(joint, HarmonicJoint) else {0.0, 0.5})
    assert np.max(np.abs(held["load"])) <= np.max(np.abs(train["load"]))
    t_train, t_held = train["true_temperature"], held["true_temperature"]
    assert t_held.min() > t_train.min() + 10 and t_held.max() <= t_train.max()
    assert t_held[0] < t_train[-1] - 3                  # cooled at rest before the held-out run
    assert held["t"][-1] >= lj.HELDOUT_SECONDS
