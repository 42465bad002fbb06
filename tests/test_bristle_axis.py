"""The controlled axis with a model's bristles (``sim.bristle_axis``): its integration against a
fine implicit reference, at rest and sliding, stable at any stiffness, and in ``simulate``."""
import dataclasses
import json

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import fricgen
from fricgen.cli import main
from fricgen.control import compensations, simulate
from fricgen.control.loop import model_plant
from fricgen.effects.presliding import Bristles
from fricgen.sim.axis import AxisState
from fricgen.sim.bristle_axis import BristleAxis
from fricgen.sim.effect_law import EffectLaw

MASS, STIFFNESS, DAMPING, FADING, VISCOUS, PHI = 2.0, 1e6, 3000.0, 0.02, 5.0, 18.0


def level(v):
    return 8.0 + 4.0 * np.exp(-(np.abs(v) / 0.01) ** 2)


def axis(stiffness=STIFFNESS, damping=DAMPING):
    law = EffectLaw(fricgen.preset("paper3"), mass=MASS, force_constant=PHI)
    return BristleAxis(law, Bristles(stiffness, damping, FADING), level, lambda v: VISCOUS * v)


def thrust(k, ts):
    """A force that sweeps through the breakaway both ways (N)."""
    return 11.0 * np.sin(2 * np.pi * 3 * k * ts) + 2.0 * np.sin(2 * np.pi * 17 * k * ts)


def reference_positions(n, ts):
    """The same LuGre axis under the same held force, by Radau at tight tolerances."""
    y, xs = [0.0, 0.0, 0.0], [0.0]
    for k in range(n):
        u = thrust(k, ts)

        def rates(_t, s, u=u):
            x, v, z = s
            dz = v - STIFFNESS * abs(v) * z / level(v)
            f = STIFFNESS * z + DAMPING * np.exp(-(v / FADING) ** 2) * dz + VISCOUS * v
            return [v, (u - f) / MASS, dz]

        y = solve_ivp(rates, (0.0, ts), y, method="Radau", rtol=1e-10, atol=1e-14).y[:, -1]
        xs.append(y[0])
    return np.array(xs)


def positions(ax, n, ts, substeps):
    state, xs = AxisState.of([0.0]), [0.0]
    for k in range(n):
        state = ax.advance(state, [thrust(k, ts) / PHI], ts, substeps)
        xs.append(float(state.x[0]))
    return np.array(xs)


def test_the_integration_converges_to_a_fine_reference_at_second_order():
    ts, n = 1e-3, 400
    truth = reference_positions(n, ts)
    errors = [np.abs(positions(axis(), n, ts, sub) - truth).max() / np.abs(truth).max()
              for sub in (10, 40)]
    assert errors[0] < 5e-3
    assert errors[1] < errors[0] / 8            # four times finer: ~16x for second order


def test_below_the_breakaway_the_bristles_hold_and_beyond_it_the_axis_slides_on_the_curve():
    ax = axis()
    end = ax.advance(AxisState.of([0.0, 0.0]), i=[6.0 / PHI, 14.0 / PHI], dt=8.0)   # 20 m/B
    assert abs(end.v[0]) < 1e-9 and end.s[0] == pytest.approx(6.0 / STIFFNESS, rel=1e-6)
    v = end.v[1]                                 # sliding: 14 N = g(v) + B v
    assert v > 0.1 and level(v) + VISCOUS * v == pytest.approx(14.0, rel=1e-6)


@pytest.mark.slow
def test_a_stiff_contact_beyond_the_steps_it_is_cut_into_stays_bounded():
    ax = axis(stiffness=1e12, damping=0.0)
    assert ax.substeps(1e-3) == 1000              # MAX_SUBSTEPS: sqrt(1e12 / 2) ms is 7e5 rad
    state = AxisState.of([0.0])
    for k in range(200):
        state = ax.advance(state, [thrust(k, 1e-3) / PHI], 1e-3)
        assert np.all(np.isfinite([state.x, state.v, state.s]))
        assert abs(state.s[0]) <= 12.0 / 1e12 * (1 + 1e-3)   # |z| <= max g / sigma0, nearly


@pytest.fixture(scope="module")
def lugre(tmp_path_factory):
    sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
    model = fricgen.train(sweep, vs_max=0.02, estimator=fricgen.StribeckRegressor(),
                          warn=lambda line: None).model
    model = dataclasses.replace(model, presliding=Bristles(1e6, 2000.0, 0.01))
    path = tmp_path_factory.mktemp("lugre") / "lugre.json"
    model.save(path)
    return model, path


def test_a_model_with_bristles_compensates_through_its_stepper(lugre):
    model, _ = lugre
    plant = model_plant(model, mass=2.0)
    assert isinstance(plant.axis, BristleAxis)
    with pytest.raises(ValueError, match="give ts"):
        compensations(plant.axis, model)
    variants = compensations(plant.axis, model, ts=1e-3)
    assert list(variants) == ["none", "steady", "model"] and variants["steady"] is model
    ctrls = [fricgen.AdaptiveBackstepping(compensation=c, ts=1e-3, phi_n=plant.phi_n)
             for c in variants.values()]
    first = simulate(plant.axis, ctrls, plant.trajectory, duration=1.0)
    again = simulate(plant.axis, ctrls, plant.trajectory, duration=1.0)    # the stepper is reset
    assert np.array_equal(first[2].e1, again[2].e1)
    rms = [float(np.sqrt(np.mean(run.e1 ** 2))) for run in first]
    assert rms[2] < rms[1] < rms[0]


def test_simulate_runs_the_bristles_in_the_plant_and_the_compensation(lugre, capsys):
    _, path = lugre
    assert main(["simulate", "--model", str(path), "--mass", "2", "--duration", "1", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert "with its bristles" in report["plant"]
    figures = report["variants"]
    assert set(figures) == {"none", "steady", "model"}
    assert figures["model"]["rms_e1"] < figures["steady"]["rms_e1"] < figures["none"]["rms_e1"]


def test_a_stepper_needs_the_controller_reset_and_its_sample_time(lugre):
    model, _ = lugre
    ctrl = fricgen.AdaptiveBackstepping(compensation=model.stepper(1e-3), ts=1e-3)
    with pytest.raises(RuntimeError, match="call reset"):
        ctrl.step(0.0, 0.0, 1e-3, 0.0, 0.0)
    assert ctrl.reset().step(0.0, 0.0, 1e-3, 0.0, 0.0) > 0
    with pytest.raises(ValueError, match="dt = 0.0001 s"):
        fricgen.AdaptiveBackstepping(compensation=model.stepper(1e-4), ts=1e-3).reset()


def test_simulate_says_when_the_bristles_are_too_stiff_to_resolve(lugre, tmp_path, capsys):
    model, _ = lugre
    stiff = tmp_path / "stiff.json"
    dataclasses.replace(model, presliding=Bristles(1e12, 2000.0, 0.01)).save(stiff)
    assert main(["simulate", "--model", str(stiff), "--mass", "2", "--duration", "0.02"]) == 0
    assert "not resolved" in capsys.readouterr().err
