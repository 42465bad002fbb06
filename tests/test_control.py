"""Closed-loop control of section 6: trajectory, axis, controller, Lyapunov properties, CLI."""
import json

import numpy as np
import pytest

from fricgen.cli import main
from fricgen.control.backstepping import AdaptiveBackstepping
from fricgen.control.gamma import gamma_matrix
from fricgen.friction import multisource
from fricgen.control.loop import compare, default_axis, simulate
from fricgen.sim.axis import AxisState
from fricgen.sim.trajectory import SineSumTrajectory, reversing


# ----------------------------------------------------------------------------- trajectory


def test_trajectory_derivatives_match_finite_differences_and_start_at_rest():
    traj = reversing()
    t = np.linspace(0.0, 4.0, 40001)
    x, xd, xdd = traj(t)
    h = t[1] - t[0]
    # central differences are exact to O(h^2 x'''): |x'''| <= sum a w^2 ~ 10 m/s^3, h^2 = 1e-8
    assert np.max(np.abs(np.gradient(x, h)[1:-1] - xd[1:-1])) < 1e-6
    assert np.max(np.abs(np.gradient(xd, h)[1:-1] - xdd[1:-1])) < 1e-4
    assert x[0] == 0.0 and abs(xd[0]) < 1e-15


def test_reversing_trajectory_reverses_inside_and_far_outside_the_stribeck_region():
    t = np.linspace(0.0, 4.0, 40001)
    _, v, _ = reversing(v_low=0.02, v_high=0.2)(t)
    sign = np.sign(v[1:-1])
    cuts = np.concatenate([[0], np.flatnonzero(np.diff(sign) != 0) + 1])
    peaks = [np.max(np.abs(v[a:b])) for a, b in zip(cuts[:-1], cuts[1:])]
    assert len(peaks) >= 14                                    # reverses every 0.25 s
    assert sum(p < 0.06 for p in peaks) >= 3                   # within 3 vs_max of Table 1
    assert max(peaks) > 0.19


@pytest.mark.parametrize("kwargs, word", [
    (dict(amplitudes=(1.0,), omegas=(0.0,)), "omegas"),
    (dict(amplitudes=(1.0, 2.0), omegas=(1.0,)), "amplitudes"),
])
def test_trajectory_rejects_bad_parameters(kwargs, word):
    with pytest.raises(ValueError, match=word):
        SineSumTrajectory(**kwargs)


# ----------------------------------------------------------------------------- axis


def test_axis_with_viscous_friction_matches_the_analytic_step_response():
    B, m, phi, i = 57.5, 2.0, 18.0, 3.0
    axis = default_axis(friction=multisource(fc=[0.0], fs=[0.0], vs=[0.01], B=[B]), mass=m,
                        force_constant=phi)
    state = AxisState.of(np.zeros(1))
    for _ in range(50):
        state = axis.rk4(state, i, 1e-3, substeps=4)
    t, vinf, tau = 0.05, phi * i / B, m / B
    # RK4 with h = 2.5e-4 s on a 35 ms time constant: error ~ (h / tau)^4 / 120 ~ 1e-11 relative
    assert state.v[0] == pytest.approx(vinf * (1 - np.exp(-t / tau)), rel=1e-8)
    assert state.x[0] == pytest.approx(vinf * (t - tau * (1 - np.exp(-t / tau))), rel=1e-8)
    assert state.t[0] == pytest.approx(t)


def test_axis_sticks_below_the_breakaway_force_and_starts_above_it(paper_friction):
    axis = default_axis()
    assert axis.breakaway() == pytest.approx(44.0)             # sum of fs in Table 1
    assert axis.breakaway(-1.0) == pytest.approx(44.0)
    i_stick = 0.99 * axis.breakaway() / axis.law.force_constant
    state = axis.rk4(AxisState.of(np.zeros(2)), np.array([i_stick, 1.01 * i_stick / 0.99]), 1e-3)
    assert state.x[0] == 0.0 and state.v[0] == 0.0
    assert state.v[1] > 0.0


def test_axis_stops_instead_of_chattering_when_velocity_crosses_zero():
    axis = default_axis()
    state = axis.rk4(AxisState.of(np.zeros(1), np.array([1e-3])), 0.0, 1e-3)   # friction brakes to rest
    assert state.v[0] == 0.0
    later = axis.rk4(state, 0.0, 1e-3)
    assert later.v[0] == 0.0 and later.x[0] == state.x[0]


@pytest.mark.parametrize("kwargs, word", [(dict(mass=0.0), "mass"),
                                          (dict(force_constant=-1.0), "force_constant"),
                                          (dict(i_max=0.0), "i_max"), (dict(load=np.inf), "load"),
                                          (dict(friction=3.0), "friction")])
def test_axis_rejects_bad_parameters(kwargs, word):
    with pytest.raises(ValueError, match=word):
        default_axis(**kwargs)


# ----------------------------------------------------------------------------- controller


@pytest.mark.parametrize("kwargs, message", [
    (dict(k1=0.0), "k1 must be > 0"),
    (dict(k1=-5.0), "k1 must be > 0"),
    (dict(k2=0.5), "k2 must be > 0.5"),
    (dict(ts=0.0), "ts must be > 0"),
    (dict(ts=float("nan")), "ts must be > 0"),
    (dict(gamma=((1.0, 2.0), (2.0, 1.0))), "gamma must be positive definite"),
    (dict(gamma=((1.0, 0.1), (0.0, 1.0))), "gamma must be symmetric"),
    (dict(gamma=(1.0, -1.0)), "gamma must be positive definite"),
    (dict(gamma=np.eye(3)), "gamma must be a scalar"),
    (dict(delta=-0.1), "delta must be >= 0"),
    (dict(law="d"), "law must be one of"),
    (dict(phi_n=0.0), "phi_n must be > 0"),
    (dict(i_max=-1.0), "i_max must be > 0"),
    (dict(a0=(1.0,)), "a0 must be 2 finite numbers"),
    (dict(compensation=42), "compensation must be None or a callable"),
    (dict(friction_input="x"), "friction_input must be"),
    (dict(dtype="float16"), "dtype must be"),
])
def test_controller_rejects_bad_parameters_with_a_message_naming_them(kwargs, message):
    with pytest.raises(ValueError, match=message):
        AdaptiveBackstepping(**kwargs).reset()


def test_controller_keeps_its_parameters_and_clone_changes_only_what_is_asked():
    c = AdaptiveBackstepping(law="b", k1=50.0)
    d = c.clone(law="a")
    assert (c.law, c.k1, d.law, d.k1) == ("b", 50.0, "a", 50.0)
    assert gamma_matrix(2.0).tolist() == [[2.0, 0.0], [0.0, 2.0]]


def one_step_expected(law):
    """(current, A_hat after) of one step of ``ONE_STEP`` computed from [C3]-[C14] directly."""
    e1 = 0.1
    e2 = 0.5 + 2.0 * e1 - 0.3                                     # [C3], [C5]
    vd_dot = 1.0 + 2.0 * (-2.0 * e1 + e2)                          # [C7]
    xi = np.array([vd_dot, 10.0 / 5.0])                            # [C10]
    A = np.array([0.2, 0.9])
    G = np.array([[1.0, 0.5], [0.5, 2.0]])
    sigma = {"a": 0.0, "b": 0.1, "c": 0.1 * np.hypot(e1, e2)}[law]  # [C14] (a), (b), (c)
    return A @ xi + 3.0 * e2 + e1, A + 0.01 * (e2 * G @ xi - sigma * G @ A)   # [C11], [C14]


#: The settings and the inputs of one step with every term of [C3]-[C14] nonzero.
ONE_STEP = (dict(k1=2.0, k2=3.0, gamma=((1.0, 0.5), (0.5, 2.0)), delta=0.1, ts=0.01, phi_n=5.0,
                 a0=(0.2, 0.9)), dict(x=0.1, v=0.3, xd=0.2, xd_dot=0.5, xd_ddot=1.0))


@pytest.mark.parametrize("law", ["a", "b", "c"])
def test_one_step_implements_eqs_3_to_14(law):
    settings, inputs = ONE_STEP
    c = AdaptiveBackstepping(compensation=lambda v: 10.0 + 0.0 * v, law=law, **settings).reset()
    i = c.step(**inputs)
    current, A = one_step_expected(law)
    assert i == pytest.approx(current, rel=1e-12)
    assert c.a_ == pytest.approx(A, rel=1e-12)


def test_current_is_limited_to_i_max():
    c = AdaptiveBackstepping(i_max=2.0).reset()
    assert c.step(0.0, 0.0, 1.0, 0.0, 0.0) == 2.0
    assert c.step(0.0, 0.0, -1.0, 0.0, 0.0) == -2.0


# ----------------------------------------------------------------------------- Lyapunov


def lyapunov(run, ctrl, axis, traj):
    """V of [C13] along a run, with A* = [m / phi, phi_N / phi] (the exact parameters)."""
    xd, xd1, _ = traj(run.t)
    e1 = xd - run.x
    e2 = xd1 + ctrl.k1 * e1 - run.v
    m_o = axis.law.mass / axis.law.force_constant
    a_err = np.stack([m_o - run.m_o_hat, ctrl.phi_n / axis.law.force_constant - run.k_hat], axis=-1)
    g_inv = np.linalg.inv(gamma_matrix(ctrl.gamma))
    return 0.5 * (e1 ** 2 + m_o * e2 ** 2 + np.einsum("ki,ij,kj->k", a_err, g_inv, a_err))


def test_lyapunov_function_does_not_grow_under_law_a_when_the_model_is_exact():
    """With a model that can be exact (viscous friction, eps = 0), [C15] gives
    V' = -k1 e1^2 - k2 e2^2 <= 0; sampling at 1 kHz may add O(Ts^2) per step only."""
    visc = multisource(fc=[0.0], fs=[0.0], vs=[0.01], B=[57.5])
    axis = default_axis(friction=visc)
    ctrl = AdaptiveBackstepping(compensation=visc, law="a")
    traj = reversing()
    run, = simulate(axis, [ctrl], traj, duration=2.0, substeps=4)
    V = lyapunov(run, ctrl, axis, traj)
    assert run.finite
    assert np.max(np.diff(V)) < 1e-4 * V[0]
    assert V[-1] < 0.95 * V[0]


def test_errors_and_parameters_stay_bounded_under_law_c_with_a_constant_disturbance():
    """A 20 N load no model knows, over two periods of the reference (2 x 4 s): law (c) with
    leakage delta keeps A_hat bounded (it changes less and less), while law (a) lets m_o_hat
    drift on; e1 stays ultimately bounded (no larger in the second period than in the first)."""
    axis = default_axis(load=20.0)
    law_c = AdaptiveBackstepping(compensation=axis.law.friction, law="c", delta=5.0)
    law_a = AdaptiveBackstepping(compensation=axis.law.friction, law="a")
    run_c, run_a = simulate(axis, [law_c, law_a], duration=8.0, substeps=4)
    h = run_c.t.size // 2
    for run in (run_c, run_a):
        e1 = np.abs(run.e1)
        assert run.finite
        assert e1[h:].max() < 1.5e-3                               # metres
        assert e1[h:].max() <= 1.05 * e1[:h].max()
    for a in (run_c.m_o_hat, run_c.k_hat):
        assert abs(a[-1] - a[h]) < 0.5 * abs(a[h] - a[0])
        assert np.max(np.abs(a)) < 2.0
    drift_first = run_a.m_o_hat[h] - run_a.m_o_hat[0]
    drift_second = run_a.m_o_hat[-1] - run_a.m_o_hat[h]
    assert drift_second > 0.5 * drift_first > 0


# ----------------------------------------------------------------------------- variants


def test_elm_compensation_tracks_like_exact_and_far_better_than_none(default_model):
    axis = default_axis()
    runs = compare({"none": None, "exact": axis.law.friction, "elm": default_model}, axis,
                   duration=2.0, substeps=5)
    rms = {k: r.metrics()["rms_e1"] for k, r in runs.items()}
    assert rms["elm"] <= 1.1 * rms["exact"]
    assert rms["elm"] <= 0.3 * rms["none"]


class BlowsUp(AdaptiveBackstepping):
    """A controller that stops being finite at sample 50 (the real one cannot: its output stays
    within +-i_max whatever it is fed, see test_control_faults.py)."""

    def reset(self):
        self.k_ = 0
        return super().reset()

    def step(self, *args):
        self.k_ += 1
        return super().step(*args) if self.k_ < 50 else float("nan")


def test_a_diverging_run_is_cut_short_and_reported_not_finite():
    run, = simulate(default_axis(), [BlowsUp(ts=0.02)], duration=2.0, substeps=2)
    m = run.metrics()
    assert run.n_finite == 49
    assert not m["finite"] and np.isfinite(m["rms_e1"])


def test_simulate_rejects_controllers_with_different_sampling_times():
    with pytest.raises(ValueError, match="ts"):
        simulate(default_axis(), [AdaptiveBackstepping(ts=1e-3), AdaptiveBackstepping(ts=2e-3)])


# ----------------------------------------------------------------------------- CLI


def test_cli_simulate_json_has_every_variant_with_the_figures(capsys, tmp_path):
    assert main(["simulate", "--json", "--duration", "0.3", "--law", "b"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert set(report["variants"]) == {"none", "exact", "elm", "fuzzy"}
    for m in report["variants"].values():
        assert {"rms_e1", "max_e1", "rms_i", "m_o_hat", "k_hat"} <= set(m)
        assert m["finite"] and 0 < m["rms_e1"] < m["max_e1"]


def test_cli_simulate_with_a_model_compares_it_and_draws_plots(capsys, tmp_path, default_model):
    pytest.importorskip("matplotlib")
    model_path = default_model.save(tmp_path / "m.json")
    assert main(["simulate", "--model", str(model_path), "--duration", "0.2",
                 "--plot", str(tmp_path / "fig")]) == 0
    out = capsys.readouterr().out
    assert "model" in out and "exact" in out
    assert sorted(p.name for p in (tmp_path / "fig").iterdir()) == [
        "simulate_exact.png", "simulate_model.png", "simulate_none.png"]


def _reference(path, t, x):
    np.savetxt(path, np.column_stack([t, x]), delimiter=",", header="t,x", comments="")
    return str(path)


def test_cli_simulate_follows_the_users_reference_with_the_users_gains(capsys, tmp_path):
    t = np.arange(0.0, 1.2001, 0.01)                       # a 50 mm move and back, from x = 0.3 m
    ref = _reference(tmp_path / "ref.csv", t, 0.3 + 0.025 * (1.0 - np.cos(2 * np.pi * t / 1.2)))
    figures = {}
    for k1 in ("80", "20"):
        assert main(["simulate", "--json", "--reference", ref, "--k1", k1]) == 0
        report = json.loads(capsys.readouterr().out)
        assert report["duration"] == pytest.approx(1.2) and report["k1"] == float(k1)
        assert f"reference {ref} (1.2 s)" in report["plant"]
        figures[k1] = report["variants"]["exact"]
    # the reference is followed (positions relative to its first), a softer k1 follows it worse
    assert figures["80"]["finite"] and figures["80"]["rms_e1"] < 5e-4 < 0.05
    assert figures["20"]["rms_e1"] > 1.5 * figures["80"]["rms_e1"]


def test_cli_simulate_names_a_current_that_sits_at_its_limit(capsys, tmp_path):
    t = np.arange(0.0, 0.3001, 0.01)
    ref = _reference(tmp_path / "ref.csv", t, 0.01 * np.sin(2 * np.pi * t / 0.3))
    assert main(["simulate", "--reference", ref, "--k1", "1e5", "--k2", "1e5"]) == 0
    err = capsys.readouterr().err
    assert "with exact the current sits at its limit of +-10 A in 100% of the samples" in err
    assert main(["simulate", "--reference", ref]) == 0
    assert "sits at its limit" not in capsys.readouterr().err
    # a sample too long for the gains: the warning names it beside them
    assert main(["simulate", "--reference", ref, "--ts", "0.02"]) == 0
    assert "or the sample time --ts 0.02 s is too long for the gains" in capsys.readouterr().err


def test_cli_simulate_tells_its_progress(capsys, monkeypatch):
    from fricgen import _progress
    monkeypatch.setattr(_progress, "PROGRESS_SECONDS", 0.0)
    assert main(["simulate", "--duration", "0.05"]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if line.startswith("simulate: ")]
    assert lines and lines[-1].startswith("simulate: 0.049 of 0.05 s of 4 variants")


def test_a_tabulated_reference_starts_and_ends_at_rest():
    from fricgen.sim.trajectory import TabulatedTrajectory
    t = np.linspace(2.0, 3.0, 11)
    ref = TabulatedTrajectory(t, 1.0 + (t - 2.0) ** 2)
    x, v, a = ref(np.array([-1.0, 0.0, 0.5, 1.0, 5.0]))
    assert x[0] == x[1] == 0.0 and x[-1] == x[-2] == pytest.approx(1.0)
    assert v[0] == v[1] == v[-1] == v[-2] == 0.0 and a[-1] == 0.0 and x[2] == pytest.approx(0.25, abs=0.02)


@pytest.mark.parametrize("rows, message", [
    ("t,x\n0,0\n1,1\n0.5,2\n2,3\n", "the reference's t must increase, it steps from 1 to 0.5 s"),
    ("t,x\n0,0\n1,1\n", "a reference needs 4 or more rows of t and x, got 2"),
    ("t,x\n0,0\n1,1\n2,nan\n3,3\n", "data row 3 holds t = 2, x = nan"),
    ("t,y\n0,0\n1,1\n2,2\n3,3\n", "x"),
    ("t,x\n0,0\n1,0\n1.01,0.05\n2,0.05\n", "overshoots them by"),      # a step in four points
    ("t,x\n0,0\n1000,0.01\n2000,0.02\n3000,0.02\n",                     # t in ms
     "lasts 3000 s (is its t in ms?), which at --ts 0.001 s is 3e+06 samples"),
])
def test_cli_simulate_refuses_a_bad_reference_in_one_line(capsys, tmp_path, rows, message):
    path = tmp_path / "ref.csv"
    path.write_text(rows)
    assert main(["simulate", "--reference", str(path)]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert captured.out == "" and len(lines) == 1 and message in lines[0]


@pytest.mark.parametrize("argv, message", [
    (["--k1", "0"], "--k1: must be a finite number > 0"),
    (["--k2", "0.5"], "--k2: must be a finite number > 0.5"),
    (["--ts", "0"], "--ts: must be a finite number >= 1e-06"),
    (["--ts=-1e-3"], "--ts: must be a finite number >= 1e-06"),
    (["--ts", "5e-324"], "--ts: must be a finite number >= 1e-06"),
    (["--duration", "nan"], "--duration: must be a finite number > 0"),
    (["--duration", "1e9"], "--duration: must be a finite number > 0 and <= 3600"),
    (["--ts", "0.1", "--duration", "0.5"], "--duration must cover"),
    (["--model", "/nonexistent/model.json"], "cannot read"),
])
def test_cli_simulate_bad_input_is_one_error_line_and_exit_2(capsys, argv, message):
    assert main(["simulate"] + argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("fricgen: error: ") and message in lines[0]
