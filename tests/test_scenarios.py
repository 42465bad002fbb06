"""The randomized test-log generator (fricgen.sim.scenarios): deterministic per seed, within
its stated ranges, hidden effects that really show, shapes outside the named families, null
logs that agree with the user's model."""
import json
import math

import numpy as np
import pytest

import fricgen.sim.closed_loop as closed_loop
from fricgen.data import MotionLog
from fricgen.effects import EFFECTS
from fricgen.friction import SHAPES
from fricgen.model import FrictionModel
from fricgen.sim.closed_loop import CONTROLLERS
from fricgen.sim.hidden_effects import HIDDEN_AS_OOV, NAMED, NOT_HIDDEN, OUT_OF_VOCABULARY, local_drag_profile
from fricgen.sim.plant_friction import StretchedStribeck
from fricgen.sim.scenarios import DURATION_RANGE, RATE_RANGE, Scenario, draw_settings, make_scenario
from fricgen.sim.trajectory import TRAJECTORIES

ALL_HIDDEN = NAMED + tuple("oov:" + s for s in OUT_OF_VOCABULARY)
#: One fixed, moderate setting for the effect-by-effect checks (5 s at 1 kHz).
FIXED = dict(rate_hz=1000.0, duration_s=5.0, controller="pd_i", trajectory="multisine")


def _smooth(a, w):
    return np.convolve(a, np.ones(w) / w, mode="same")


@pytest.fixture(scope="module")
def null_fixed():
    return make_scenario(0, (), **FIXED)


def test_named_effects_are_the_vocabulary():
    assert set(NAMED) | set(HIDDEN_AS_OOV) | set(NOT_HIDDEN) == set(EFFECTS)
    assert NOT_HIDDEN == ("presliding",)          # the plants' friction is a static curve
    assert set(OUT_OF_VOCABULARY) & set(EFFECTS) == set(HIDDEN_AS_OOV) == {"sensor_delay", "actuator_saturation"}


def test_scenario_is_deterministic_per_seed():
    a = make_scenario(3, ("constant_load",), duration_s=5.0, rate_hz=500.0)
    b = make_scenario(3, ("constant_load",), duration_s=5.0, rate_hz=500.0)
    c = make_scenario(4, ("constant_load",), duration_s=5.0, rate_hz=500.0)
    assert isinstance(a, Scenario) and isinstance(a.log, MotionLog)
    assert isinstance(a.model, FrictionModel)
    assert a.hidden == ("constant_load",)
    for column in ("t", "x", "v", "i"):
        assert np.array_equal(getattr(a.log, column), getattr(b.log, column))
    assert np.array_equal(a.log.extra["x_d"], b.log.extra["x_d"])
    assert a.conditions == b.conditions and a.model.to_dict() == b.model.to_dict()
    assert (a.mass, a.force_constant) == (b.mass, b.force_constant)
    assert a.mass != c.mass and not np.array_equal(a.log.i, c.log.i[:a.log.i.size])


def test_drawn_settings_cover_the_stated_ranges():
    drawn = [draw_settings(seed) for seed in range(300)]
    rates = np.array([d["rate_hz"] for d in drawn])
    durations = np.array([d["duration_s"] for d in drawn])
    assert RATE_RANGE[0] <= rates.min() and rates.max() <= RATE_RANGE[1]
    assert DURATION_RANGE[0] <= durations.min() and durations.max() <= DURATION_RANGE[1]
    # log-uniform draws reach both ends of the ranges
    assert rates.min() < 350 and rates.max() > 3000
    assert durations.min() < 7 and durations.max() > 90
    assert {d["controller"] for d in drawn} == set(CONTROLLERS)
    assert {d["trajectory"] for d in drawn} == set(TRAJECTORIES)
    assert {d["feedforward"] for d in drawn} == {True, False}


@pytest.mark.parametrize("seed", [0, 1, 2, 3, 4, 5])
def test_conditions_are_within_ranges_and_json(seed):
    sc = make_scenario(seed, duration_s=5.0)
    c = sc.conditions
    assert json.loads(json.dumps(c)) == c
    assert RATE_RANGE[0] <= c["rate_hz"] <= RATE_RANGE[1]
    assert len(sc.log) == c["samples"] == int(round(5.0 * c["rate_hz"])) + 1
    assert math.isclose(sc.log.sample_time, 1.0 / c["rate_hz"], rel_tol=1e-9)
    plant = c["plant"]
    assert 0.5 <= plant["mass"] <= 20 and 5 <= plant["force_constant"] <= 60
    assert (sc.mass, sc.force_constant) == (plant["mass"], plant["force_constant"])
    friction = plant["friction"]
    assert 2 <= len(friction["fc"]) <= 3 and friction["B"] > 0
    assert all(fs > fc > 0 for fc, fs in zip(friction["fc"], friction["fs"]))
    assert c["controller"]["kind"] in CONTROLLERS
    assert c["trajectory"]["kind"] in TRAJECTORIES
    assert c["controller"]["bandwidth_hz"] <= c["rate_hz"] / 40 + 1e-9
    # logged signals lie on their quantization grids
    q = c["quantization"]
    for column, step in (("x", q["x"]), ("v", q["v"]), ("i", q["i"])):
        values = getattr(sc.log, column) / step
        assert np.max(np.abs(values - np.round(values))) < 1e-6
    # the loop tracks its reference and stays off the current limit
    assert c["current_limit_fraction"] < 0.01
    assert c["tracking_rms"] < 0.05 * np.ptp(sc.log.extra["x_d"])
    assert c["seam_jump"] <= closed_loop.SEAM_TOLERANCE


def test_long_logs_are_feasible():
    sc = make_scenario(1, ("thermal_drift",), rate_hz=250.0, duration_s=1200.0,
                       trajectory="sine")
    assert len(sc.log) == 1200 * 250 + 1
    assert sc.conditions["current_limit_fraction"] < 0.01
    assert sc.conditions["seam_jump"] <= closed_loop.SEAM_TOLERANCE


@pytest.mark.parametrize("hidden", [h for h in ALL_HIDDEN if h != "oov:sensor_delay"])
def test_each_hidden_effect_changes_the_current(hidden, null_fixed):
    """Against the null log of the same seed (same plant, loop, trajectory and noise), the
    smoothed force phi i changes by far more than the sensor noise."""
    sc = make_scenario(0, (hidden,), **FIXED)
    assert sc.hidden == (hidden,)
    assert sc.conditions["plant"] == null_fixed.conditions["plant"]
    w = 10
    noise = null_fixed.conditions["force_noise"] / math.sqrt(w)
    change = _smooth(sc.force_constant * (sc.log.i - null_fixed.log.i), w)
    assert np.sqrt(np.mean(change ** 2)) > 3 * noise
    assert sc.conditions["signature_rms"][hidden] > 3 * noise


@pytest.mark.parametrize("hidden", [h for h in ALL_HIDDEN if h != "oov:sensor_delay"])
def test_the_hidden_force_is_what_the_residual_sees(hidden, null_fixed):
    """``Scenario.hidden_force`` has the sign and about the size of the residual
    phi i - m dv/dt - F(v) it causes (least-squares gain near 1, smoothed over 10 samples);
    the sensor delay's is checked through the held-out gap (test_diagnose_scenarios)."""
    sc = make_scenario(0, (hidden,), **FIXED)
    assert np.all(null_fixed.hidden_force == 0.0)
    log, w = sc.log, 10
    residual = _smooth(sc.force_constant * log.i - sc.mass * np.gradient(_smooth(log.v, w), log.sample_time)
                       - sc.model.force(log.v), w)[50:-50]
    hidden_force = _smooth(sc.hidden_force, w)[50:-50]
    gain = np.dot(residual, hidden_force) / np.dot(hidden_force, hidden_force)
    # within a factor 1.6 of 1: the smoothing and the differentiated velocity bias the residual
    # (0.70 for a force-constant error and 1.36 for the dead zone reached); a lost factor 2 fails
    assert 1 / 1.6 < gain < 1.6


def test_the_truth_carries_a_mass_error_in_the_mass_not_the_current():
    """A current corrected by (m_true - m) dv/dt of the measured velocity would drive the
    gap's simulation with the velocity sensor's noise; the truth takes the true mass."""
    sc = make_scenario(0, ("inertia_mismatch", "constant_load"), **FIXED)
    assert sc.true_mass == pytest.approx(sc.conditions["magnitudes"]["inertia_mismatch"]["mass"])
    assert sc.true_mass != sc.mass
    load = sc.conditions["magnitudes"]["constant_load"]["load"]
    assert np.allclose(sc.force_constant * (sc.log.i - sc.truth_log().i), load)
    assert not np.allclose(sc.hidden_force, load)
    null = make_scenario(0, (), **FIXED)
    assert null.true_mass == null.mass and np.array_equal(null.truth_log().i, null.log.i)


def _force_lag(sc, most=15):
    """The shift k (samples) at which phi i(t) best matches m dv/dt + F(v) at t + k, all
    smoothed over 10 samples: how far the logged motion trails the logged current."""
    log, ts = sc.log, sc.log.sample_time
    v = _smooth(log.v, 10)
    motion = sc.mass * np.gradient(v, ts) + _smooth(sc.model.force(log.v), 10)
    force = _smooth(sc.force_constant * log.i, 10)
    misfit = [np.sqrt(np.mean((force[:force.size - k] - motion[k:])[50:-50] ** 2))
              for k in range(most)]
    return int(np.argmin(misfit))


def test_sensor_delay_makes_the_motion_trail_the_current(null_fixed):
    sc = make_scenario(0, ("oov:sensor_delay",), **FIXED)
    d = sc.conditions["magnitudes"]["oov:sensor_delay"]["samples"]
    assert d >= 1
    shift = _force_lag(sc) - _force_lag(null_fixed)
    assert shift >= 1 and abs(shift - d) <= 1


def test_two_and_three_effects_at_once(null_fixed):
    pair = make_scenario(0, ("constant_load", "oov:local_drag"), **FIXED)
    triple = make_scenario(0, ("position_ripple", "thermal_drift", "inertia_mismatch"), **FIXED)
    assert set(pair.conditions["signature_rms"]) == {"constant_load", "oov:local_drag"}
    assert len(triple.conditions["magnitudes"]) == 3
    # each effect is the one it would be alone (parameters drawn per effect)
    alone = make_scenario(0, ("thermal_drift",), **FIXED)
    assert triple.conditions["magnitudes"]["thermal_drift"] == \
        alone.conditions["magnitudes"]["thermal_drift"]
    assert not np.array_equal(triple.log.i, null_fixed.log.i)


def test_magnitude_scales_the_effect():
    small = make_scenario(1, ("constant_load",), magnitude=0.2, **FIXED)
    full = make_scenario(1, ("constant_load",), **FIXED)
    assert math.isclose(small.conditions["magnitudes"]["constant_load"]["load"],
                        0.2 * full.conditions["magnitudes"]["constant_load"]["load"])


# ----------------------------------------------------------------------------- out of vocabulary


def test_local_drag_is_zero_outside_its_stretch():
    sc = make_scenario(0, ("oov:local_drag",), **FIXED)
    p = sc.conditions["magnitudes"]["oov:local_drag"]
    x = np.linspace(-0.5, 0.5, 200001)
    profile = local_drag_profile(x, p["centre"], p["width"], p["drag"])
    outside = np.abs(x - p["centre"]) >= 0.5 * p["width"]
    assert np.all(profile[outside] == 0.0)
    assert np.max(profile) == pytest.approx(p["drag"], rel=1e-6)
    # no sinusoid in x (position_ripple) nor a constant (constant_load) explains it over
    # the travel: the best of them leaves most of its energy
    travel = np.linspace(*[float(f(sc.log.extra["x_d"])) for f in (np.min, np.max)], 20001)
    drag = local_drag_profile(travel, p["centre"], p["width"], p["drag"])
    span = travel[-1] - travel[0]
    best = 0.0
    for period in np.geomspace(span / 200, 4 * span, 400):
        k = 2 * np.pi / period
        basis = np.column_stack([np.sin(k * travel), np.cos(k * travel), np.ones_like(travel)])
        coef, *_ = np.linalg.lstsq(basis, drag, rcond=None)
        best = max(best, 1 - np.sum((drag - basis @ coef) ** 2) / np.sum(drag ** 2))
    assert best < 0.6


def test_ripple_harmonics_is_no_single_sinusoid():
    sc = make_scenario(0, ("oov:ripple_harmonics",), **FIXED)
    p = sc.conditions["magnitudes"]["oov:ripple_harmonics"]
    x = np.linspace(0.0, 10 * p["period"], 4001)
    k0 = 2 * np.pi / p["period"]
    ripple = sum(a * np.sin((j + 1) * k0 * x + ph)
                 for j, (a, ph) in enumerate(zip(p["amplitudes"], p["phases"])))
    explained = []
    for k in np.linspace(0.2 * k0, 4 * k0, 761):
        basis = np.column_stack([np.sin(k * x), np.cos(k * x)])
        coef, *_ = np.linalg.lstsq(basis, ripple, rcond=None)
        explained.append(1 - np.sum((ripple - basis @ coef) ** 2) / np.sum(ripple ** 2))
    assert max(explained) < 0.6


def test_nonlinear_viscous_is_outside_the_extra_source_family():
    """c sgn(v) |v|^p is fitted by the best extra friction source of any shape and speed
    (sgn(v) [fc + (fs - fc) g(v, vs)] + B v); it leaves a residual well above rounding."""
    sc = make_scenario(0, ("oov:nonlinear_viscous",), **FIXED)
    p = sc.conditions["magnitudes"]["oov:nonlinear_viscous"]
    v = np.linspace(1e-4, np.max(np.abs(sc.log.v)), 4000)
    force = p["coefficient"] * v ** p["power"]
    best = np.inf
    for shape in SHAPES.values():
        for vs in np.geomspace(v[1], 100 * v[-1], 120):
            basis = np.column_stack([np.ones_like(v), shape(v, vs), v])
            coef, *_ = np.linalg.lstsq(basis, force, rcond=None)
            best = min(best, np.sqrt(np.mean((force - basis @ coef) ** 2)))
    assert best > 0.01 * np.max(force)


@pytest.mark.parametrize("shape", ["oov:actuator_deadzone", "oov:actuator_saturation"])
def test_actuator_shapes_are_not_a_force_constant(shape):
    """The force the actuator loses, phi (i - h(i)), is not proportional to i (the
    force-constant family): a line through 0 leaves much of it over the logged currents."""
    sc = make_scenario(0, (shape,), **FIXED)
    p = sc.conditions["magnitudes"][shape]
    i = sc.log.i
    if "deadzone_a" in p:
        lost = i - np.sign(i) * np.maximum(np.abs(i) - p["deadzone_a"], 0.0)
    else:
        lost = i - p["saturation_a"] * np.tanh(i / p["saturation_a"])
    gain = np.dot(i, lost) / np.dot(i, i)
    assert np.sum((lost - gain * i) ** 2) > 0.1 * np.sum(lost ** 2)


# ----------------------------------------------------------------------------- null logs


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_null_log_agrees_with_the_users_model(seed):
    """phi i - m dv/dt - F(v) with the user's model, smoothed over 20 ms where the axis moves
    briskly, is a few per cent of the plant's Coulomb friction; a hidden load of 0.3 F_c
    in the same log is not."""
    null = make_scenario(seed, duration_s=6.0)
    load = make_scenario(seed, ("constant_load",), duration_s=6.0)
    coulomb = null.conditions["plant"]["coulomb"]

    def residual(sc):
        log, ts = sc.log, sc.log.sample_time
        w = max(3, int(round(0.02 / ts)))
        v = _smooth(log.v, w)
        r = _smooth(sc.force_constant * log.i, w) - sc.mass * np.gradient(v, ts) \
            - _smooth(sc.model.force(log.v), w)
        keep = np.abs(v) > 0.2 * np.max(np.abs(v))
        keep[:3 * w] = keep[-3 * w:] = False
        return np.sqrt(np.mean(r[keep] ** 2))

    assert residual(null) < 0.1 * coulomb
    assert residual(load) > 0.2 * coulomb


def test_users_model_is_close_to_the_plant_but_not_equal():
    sc = make_scenario(5, duration_s=5.0)
    f = sc.conditions["plant"]["friction"]
    plant = StretchedStribeck(tuple(f["fc"]), tuple(f["fs"]), tuple(f["vs"]),
                                        tuple(f["exponent"]), tuple(f["kind"]), f["B"])
    v = np.linspace(-np.max(np.abs(sc.log.v)), np.max(np.abs(sc.log.v)), 2001)
    error = np.abs(sc.model.force(v) - plant(v))
    assert np.max(error) < 0.1 * plant.coulomb
    assert np.max(error) > 1e-4 * plant.coulomb


def test_stitched_simulation_equals_a_serial_one(monkeypatch):
    """The log simulated in stretches agrees with one simulated from start to end within the
    sensor resolution."""
    stitched = make_scenario(3, ("constant_load",), duration_s=6.0)
    monkeypatch.setattr(closed_loop, "STRETCH_S", 1e9)
    serial = make_scenario(3, ("constant_load",), duration_s=6.0)
    assert serial.conditions["passes"] == 1
    c = stitched.conditions
    resolution = max(c["quantization"]["x"], c["noise"]["sigma_x"])
    assert np.max(np.abs(stitched.log.x - serial.log.x)) <= 2 * resolution
    di = stitched.force_constant * (stitched.log.i - serial.log.i)
    assert np.sqrt(np.mean(di ** 2)) < 0.1 * c["force_noise"]


@pytest.mark.parametrize("kwargs", [
    dict(hidden=("nope",)), dict(hidden=("constant_load", "constant_load")),
    dict(hidden=("oov:actuator_deadzone", "oov:actuator_saturation")),
    dict(controller="lqr"), dict(trajectory="spiral"), dict(rate_hz=10.0),
    dict(duration_s=2000.0), dict(noise=-1.0), dict(magnitude=0.0)])
def test_bad_arguments(kwargs):
    with pytest.raises(ValueError):
        make_scenario(0, **kwargs)
