"""The axis of [C1] under a pluggable force law: its three integrators, stiction, and the
force law of a friction curve with named effects (truth logs, diagnosis re-simulation)."""
import numpy as np
import pytest

from fricgen.effects import (DirectionAsymmetry, FrictionalLag, PositionRipple, Signals,
                             ThermalDrift, effect_from_dict)
from fricgen.firmware.closed_loop import Float32Plant
from fricgen.friction import multisource, preset
from fricgen.sim.axis import AxisState, MotorAxis
from fricgen.sim.effect_law import EffectLaw
from fricgen.sim.logsynth import (HIDDEN_EFFECTS, LogSpec, magnitude_range, truth_effect, truth_effects,
                                  truth_law)

# ----------------------------------------------------------------------------- integrators


def smooth_axis():
    """A law that is smooth while v > 0 and exercises every input of the force law: position
    (ripple), time (drift) and the friction memory (lag)."""
    friction = multisource(fc=[5.0], fs=[8.0], vs=[0.5], B=[20.0])
    effects = (PositionRipple(amplitude=3.0, period=0.05, phase=0.3),
               ThermalDrift(rate=0.5, offset=0.0, t0=0.0), FrictionalLag(tau=0.01))
    return MotorAxis(EffectLaw(friction, effects, mass=2.0, force_constant=18.0, i_max=10.0))


def end_state(step, substeps, samples=10, dt=5e-3):
    """Where the axis is after ``samples`` samples of 3 A from x = 0, v = 0.2 m/s (v stays > 0)."""
    state = AxisState.of(np.zeros(1), 0.2, 0.0, 0.2)
    for _ in range(samples):
        state = step(state, 3.0, dt, substeps)
    assert state.v.min() > 0.1
    return np.array([float(state.x[0]), float(state.v[0]), float(state.s[0])])


@pytest.fixture(scope="module")
def reference():
    return end_state(smooth_axis().rk4, 400)


def error(step, substeps, reference):
    return np.max(np.abs(end_state(step, substeps) - reference) / np.abs(reference))


def test_rk4_is_fourth_order_on_a_smooth_law(reference):
    axis = smooth_axis()
    coarse, fine = error(axis.rk4, 2, reference), error(axis.rk4, 4, reference)
    assert coarse < 1e-6
    assert 10.0 < coarse / fine < 24.0                       # 2^4 = 16


@pytest.mark.parametrize("integrator", ["karnopp", "euler_f32"])
def test_karnopp_and_float32_euler_are_first_order_and_agree_with_rk4(reference, integrator):
    step = getattr(smooth_axis(), integrator)
    coarse, fine = error(step, 10, reference), error(step, 20, reference)
    assert coarse < 2e-2
    assert 1.7 < coarse / fine < 2.3                          # 2^1 = 2


@pytest.mark.parametrize("integrator", ["rk4", "karnopp"])
def test_a_stuck_axis_stays_stuck_while_the_applied_force_is_below_breakaway(integrator):
    """Table 1 friction, 20 % more in the negative direction, and a 5 N load: the axis at rest
    stays exactly there for every current whose |phi i - load| <= breakaway in its direction,
    and starts the way the applied force pushes just above it."""
    law = EffectLaw(preset("paper3"), (DirectionAsymmetry(gain_positive=0.0, gain_negative=0.2),),
                    mass=2.0, force_constant=18.0, i_max=10.0)
    law_load = EffectLaw(preset("paper3"), law.effects + (PositionRipple(5.0, 1e9, np.pi / 2),),
                         mass=2.0, force_constant=18.0, i_max=10.0)     # ripple of period 1e9 m: a load
    for law in (law, law_load):
        axis = MotorAxis(law)
        load = float(law.external_force(np.zeros(1), np.zeros(1), 0.0)[0])
        up, down = float(axis.breakaway(1.0)), float(axis.breakaway(-1.0))
        assert down == pytest.approx(1.2 * up)
        below = np.array([load + 0.999 * up, load - 0.999 * down, load, load + 0.5 * up]) / 18.0
        above = np.array([load + 1.001 * up, load - 1.001 * down]) / 18.0
        step = getattr(axis, integrator)
        stuck = AxisState.of(np.zeros(4))
        moving = AxisState.of(np.zeros(2))
        for _ in range(50):
            stuck = step(stuck, below, 1e-3, 5)
            moving = step(moving, above, 1e-3, 5)
        assert np.all(stuck.x == 0.0) and np.all(stuck.v == 0.0)
        assert moving.x[0] > 0.0 and moving.x[1] < 0.0


def test_float32_euler_reproduces_fw_plant_advance_operation_for_operation():
    """``Float32Plant.advance`` (the law driven by ``MotorAxis.euler_f32``) against a literal
    transcription of fw_plant_advance of examples/firmware/fw_plant.c."""
    plant = Float32Plant()
    f = np.float32

    def fw_plant_advance(x, v, i, ts):
        h = f(ts) / f(plant.substeps)
        i = min(max(f(i), f(-plant.i_max)), f(plant.i_max))
        thrust = f(plant.phi) * i
        for _ in range(plant.substeps):
            a = (thrust - plant.friction(v)) / f(plant.mass)
            v = v + h * a
            x = x + h * v
        return x, v

    rng = np.random.default_rng(0)
    x = v = y = w = f(0.0)
    with np.errstate(all="ignore"):
        for i in rng.uniform(-14.0, 14.0, 400).astype(np.float32):
            x, v = plant.advance(x, v, i, 1e-3)
            y, w = fw_plant_advance(y, w, i, 1e-3)
            assert x.dtype == v.dtype == np.float32
            assert x.tobytes() == y.tobytes() and v.tobytes() == w.tobytes()


# ----------------------------------------------------------------------------- force laws


@pytest.mark.parametrize("effect", [e for e in HIDDEN_EFFECTS if e != "none"])
def test_the_truth_law_is_the_friction_plus_the_library_effect(effect):
    spec = LogSpec(effect=effect, magnitude=1.3)
    law = truth_law([spec])
    e, = truth_effects(spec)
    rng = np.random.default_rng(1)
    x, v, t, s = rng.uniform(-0.1, 0.1, 50), rng.uniform(-0.3, 0.3, 50), rng.uniform(0, 12, 50), \
        rng.uniform(0, 0.3, 50)
    sig = Signals(preset("paper3"), t=t, x=x, v=v, s=s)
    want_friction, want_external = preset("paper3")(v), np.zeros(50)
    if e.acts_at_rest:
        want_external = want_external + e.force(sig)
    elif not e.via_dynamics:
        want_friction = want_friction + e.force(sig)
    assert np.array_equal(law.sliding_friction(v, t, s), want_friction)
    assert np.array_equal(law.external_force(x, v, t), want_external)
    assert law.mass == spec.mass + e.mass_delta
    assert law.force_constant == spec.force_constant + e.force_constant_delta
    assert law.lag_tau == e.lag_tau


@pytest.mark.parametrize("effect", [e for e in HIDDEN_EFFECTS if e != "none"])
def test_the_magnitude_range_ends_where_the_effect_library_refuses_the_effect(effect):
    # a negative extra friction source, or a force constant 3 % of the nominal one (which left the
    # axis stuck, "x does not follow v"), was accepted as a magnitude
    low, high = magnitude_range(effect, 4.0, 20.0)
    assert low == 0.0 and (high == float("inf") or 1.0 < high < 100.0)

    def accepted(k):
        e = truth_effect(effect, k, 4.0, 20.0)
        try:
            return effect_from_dict(e.to_dict()) == e and e.implausible() == ""
        except ValueError:
            return False

    assert all(accepted(k) for k in (1e-3, 1.0, min(high, 100.0)))
    if high < float("inf"):
        assert not accepted(1.01 * high)
        with pytest.raises(ValueError, match=f"> 0 and <= {high:g} for {effect}, got"):
            LogSpec(effect=effect, magnitude=1.01 * high)


def test_a_batch_law_gives_each_axis_exactly_its_own_law():
    specs = [LogSpec(effect=e, magnitude=m) for e in HIDDEN_EFFECTS for m in (1.0, 0.4)]
    batch = truth_law(specs)
    rng = np.random.default_rng(2)
    n = len(specs)
    x, v, t, s = rng.uniform(-0.1, 0.1, n), rng.uniform(-0.3, 0.3, n), rng.uniform(0, 12, n), \
        rng.uniform(0, 0.3, n)
    for j, spec in enumerate(specs):
        alone = truth_law([spec])
        sl = slice(j, j + 1)
        assert np.array_equal(batch.sliding_friction(v, t, s)[sl], alone.sliding_friction(v[sl], t[sl], s[sl]))
        assert np.array_equal(batch.external_force(x, v, t)[sl], alone.external_force(x[sl], v[sl], t[sl]))
        for name in ("mass", "force_constant", "lag_tau"):
            assert np.broadcast_to(getattr(batch, name), n)[j] == getattr(alone, name)


def test_a_batch_refuses_two_effects_of_one_kind_on_one_axis():
    ripple = PositionRipple(amplitude=1.0, period=0.01, phase=0.0)
    with pytest.raises(ValueError, match="two position_ripple"):
        EffectLaw.batch(preset("paper3"), [(ripple, ripple)], mass=1.0, force_constant=1.0)


def test_a_batch_refuses_a_sensor_delay_it_could_not_simulate():
    """A delay shifts the current that drives the axis, which no batched simulation does: it
    would be left out without a word."""
    from fricgen.effects.timing import SensorDelay
    delay = SensorDelay(tau=0.002, nominal_force_constant=20.0)
    assert EffectLaw(preset("paper3"), [delay], mass=1.0, force_constant=20.0).input_delay == 0.002
    with pytest.raises(ValueError, match="sensor_delay is a log's timing"):
        EffectLaw.batch(preset("paper3"), [(), (delay,)], mass=1.0, force_constant=20.0)
