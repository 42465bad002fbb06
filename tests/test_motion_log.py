"""Training from motion logs: inverse dynamics, the vendor-export options, sweep or log."""
import json

import numpy as np
import pytest

import fricgen

from fricgen.cli import main
from fricgen.data.export import ExportLayout, merge_on_time, read_export
from fricgen.data.inverse_dynamics import identify_friction, is_log
from fricgen.data.table import table_csv_text
from fricgen.errors import DataError
from fricgen.friction import multisource, preset
from fricgen.model import FrictionModel
from fricgen.sim.identification import DirectionalFriction, SweepRun, simulate_sweep_run

FRICTION = DirectionalFriction(preset("paper3"), multisource(
    fc=(5.0, 7.5, 6.0), fs=(9.0, 19.0, 24.0), vs=(0.012, 0.006, 0.025), B=(2.5, 45.0, 5.0)))
RUN = SweepRun(duration=8.0, rate=1500.0)
#: A quick explicit ELM and the true bound on the Stribeck velocities, for short tests.
FAST = ["--method", "elm", "--neurons", "20", "--vs-max", "0.025"]


@pytest.fixture(scope="module")
def signals():
    """One identification run (one cycle of the velocity sweep, 1.5 kHz), noise-free."""
    return simulate_sweep_run(FRICTION, RUN)


@pytest.fixture(scope="module")
def noisy(signals):
    rng = np.random.default_rng(3)
    n = signals["t"].size
    return {"t": signals["t"], "v": signals["v"] + 3e-4 * rng.standard_normal(n),
            "force": signals["force"] + 0.5 * rng.standard_normal(n)}


def _error(ident):
    return ident.sweep.f - FRICTION(ident.sweep.v)


def test_noise_free_inverse_dynamics_recovers_the_friction(signals):
    ident = identify_friction(signals["t"], signals["force"], RUN.mass, v=signals["v"])
    assert ident.window == 7                       # nothing to smooth: the smallest window
    assert np.median(np.abs(_error(ident))) < 1e-3
    assert ident.sweep.v.min() < -0.19 and ident.sweep.v.max() > 0.19
    assert np.abs(ident.sweep.v).min() < 0.005     # the Stribeck region is in the log


def test_noise_widens_the_window_and_the_samples_stay_unbiased(signals, noisy):
    ident = identify_friction(noisy["t"], noisy["force"], RUN.mass, v=noisy["v"])
    error = _error(ident)
    assert ident.window > 15
    assert abs(np.mean(error)) < 0.05 and np.sqrt(np.mean(error ** 2)) < 0.3
    worse = identify_friction(noisy["t"], noisy["force"], RUN.mass, v=noisy["v"], window=7)
    assert np.sqrt(np.mean(_error(worse) ** 2)) > 2 * np.sqrt(np.mean(error ** 2))


def test_position_instead_of_velocity(signals, noisy):
    from_x = identify_friction(noisy["t"], noisy["force"], RUN.mass, x=signals["x"])
    assert np.sqrt(np.mean(_error(from_x) ** 2)) < 0.3
    assert from_x.sweep.v.max() > 0.19


def test_the_columns_tell_a_log_from_a_sweep():
    a = np.zeros(3)
    assert is_log({"t": a, "v": a, "force": a}) and is_log({"t": a, "x": a, "i": a})
    assert not is_log({"v": a, "f": a}) and not is_log({"t": a, "v": a, "f": a})


@pytest.fixture(scope="module")
def log_model(noisy, tmp_path_factory):
    d = tmp_path_factory.mktemp("log")
    (d / "log.csv").write_text(table_csv_text(noisy))
    return d


def test_train_on_a_log_reports_it_and_fits_each_direction(log_model, capsys):
    # asked for: the symmetric curve with the offset beside it cross-validates as well here (the
    # offset takes up the difference of the Coulomb levels)
    assert main(["train", str(log_model / "log.csv"), "--mass", str(RUN.mass), *FAST,
                 "--asymmetric", "-o", str(log_model / "m.json")]) == 0
    report = capsys.readouterr().out
    for words in ("log       12001 rows at 1500 Hz", "independent samples", "Savitzky-Golay",
                  "velocity  -0.19", "symmetry asymmetric", "v > 0:", "v < 0:"):
        assert words in report, report
    model = FrictionModel.load(log_model / "m.json")
    assert not model.symmetric and model.training["axis"]["mass"] == RUN.mass
    speed = np.linspace(0.01, 0.19, 100)
    for sign in (1, -1):
        error = sign * model.force(sign * speed) - FRICTION.magnitude(speed, sign)
        assert np.sqrt(np.mean(error ** 2)) < 0.4      # 20 neurons on ~130 effective samples: 0.32, 0.36


def test_symmetric_friction_in_a_log_keeps_the_symmetric_model(tmp_path, capsys):
    symmetric = DirectionalFriction(preset("paper3"), preset("paper3"))
    sig = simulate_sweep_run(symmetric, RUN)
    rng = np.random.default_rng(4)
    cols = {"t": sig["t"], "v": sig["v"] + 3e-4 * rng.standard_normal(sig["t"].size),
            "i": sig["i"] + 0.02 * rng.standard_normal(sig["t"].size)}
    (tmp_path / "log.csv").write_text(table_csv_text(cols))
    assert main(["train", str(tmp_path / "log.csv"), "--mass", "4", "--force-constant", "20",
                 *FAST, "-o", str(tmp_path / "m.json")]) == 0
    assert "symmetry symmetric by 5-fold" in capsys.readouterr().out
    assert FrictionModel.load(tmp_path / "m.json").symmetric


def test_a_vendor_export_equals_the_plain_log(noisy, log_model, tmp_path):
    # drive: preamble, vendor names, speed in units of 2^-10 m/s; load cell on the same clock
    rows = zip(noisy["t"], noisy["v"] * 1024.0)
    (tmp_path / "drive.csv").write_text("Drive trace\n(c) vendor\nTime [s],Speed [u]\n" + "".join(
        f"{float(t)!r},{float(v)!r}\n" for t, v in rows))
    (tmp_path / "cell.csv").write_text("Stamp,Load\n" + "".join(
        f"{float(t)!r},{float(f)!r}\n" for t, f in zip(noisy["t"], noisy["force"])))
    common = ["--mass", str(RUN.mass), "--symmetric", "--method", "elm", "--neurons", "10"]
    assert main(["train", str(tmp_path / "drive.csv"), "--skip", "2", "--columns",
                 "t=Time [s],v=Speed [u]", "--scale", "v=0.0009765625", "--merge",
                 str(tmp_path / "cell.csv"), "--merge-columns", "t=Stamp", "--merge-columns",
                 "force=Load", *common, "-o", str(tmp_path / "vendor.json")]) == 0
    assert main(["train", str(log_model / "log.csv"), *common, "-o", str(tmp_path / "plain.json")]) == 0
    vendor, plain = (json.loads((tmp_path / n).read_text()) for n in ("vendor.json", "plain.json"))
    assert vendor["aim"] == plain["aim"] and vendor["viscous"] == plain["viscous"]


def test_merge_uses_the_slower_clock_and_the_shift(tmp_path):
    t_fast = np.arange(2001) / 2000.0          # 2 kHz, its clock 4 ms behind
    t_slow = np.arange(1501) / 1500.0          # 1.5 kHz
    slow = {"t": t_slow, "v": np.sin(t_slow)}
    fast = {"t": t_fast - 0.004, "force": 3.0 + 2.0 * t_fast}
    merged = merge_on_time(slow, fast, shift=0.004)
    assert np.array_equal(merged["t"], t_slow[(t_slow >= 0) & (t_slow <= 1.0)])
    np.testing.assert_allclose(merged["force"], 3.0 + 2.0 * merged["t"], atol=1e-12)
    swapped = merge_on_time(fast, slow, shift=-0.004)
    assert np.median(np.diff(swapped["t"])) == pytest.approx(1 / 1500.0)


@pytest.mark.parametrize("shift, said", [(0.0, ""), (0.5, " (after the shift of 0.5 s)")],
                         ids=["no shift", "a shift"])
def test_merge_messages_mention_the_shift_only_when_one_is_given(shift, said):
    first = {"t": np.arange(100) / 100.0, "v": np.ones(100)}
    second = {"t": np.arange(100) / 100.0 + 0.5 - shift, "force": np.ones(100)}
    with pytest.raises(DataError) as short:
        merge_on_time(first, second, shift, ("a.csv", "b.csv"), min_rows=80)
    assert str(short.value).endswith("need 80 rows" + said)
    second["t"] += 10.0
    with pytest.raises(DataError) as apart:
        merge_on_time(first, second, shift, ("a.csv", "b.csv"))
    assert str(apart.value) == "a.csv and b.csv share no time span" + said


def test_read_export_skips_maps_and_scales(tmp_path):
    (tmp_path / "e.csv").write_text("a preamble, with a comma\nline 2\nZeit,Geschw,other\n0,2,7\n1,4,8\n")
    cols = read_export(tmp_path / "e.csv", ExportLayout(2, {"t": "Zeit", "v": "GESCHW"}), {"v": 0.5, "t": 2.0})
    assert set(cols) == {"t", "v", "other"}
    np.testing.assert_array_equal(cols["v"], [1.0, 2.0])
    np.testing.assert_array_equal(cols["t"], [0.0, 2.0])


def test_too_narrow_a_velocity_range_warns_in_one_line(tmp_path, capsys):
    t = np.arange(20001) / 1000.0
    v = 0.115 + 0.085 * np.sin(2 * np.pi * t / 5.0)           # 0.03 to 0.2 m/s only
    a = 0.085 * 2 * np.pi / 5.0 * np.cos(2 * np.pi * t / 5.0)
    force = preset("paper3")(v) + 4.0 * a
    (tmp_path / "fast.csv").write_text(table_csv_text({"t": t, "v": v, "force": force}))
    assert main(["train", str(tmp_path / "fast.csv"), "--mass", "4", "--vs-max", "0.02",
                 "--method", "elm", "--neurons", "10", "-o", str(tmp_path / "m.json")]) == 0
    err = capsys.readouterr().err
    warnings = [line for line in err.splitlines() if line.startswith("fricgen: warning:")]
    assert len(warnings) == 1 and "Stribeck region" in warnings[0], err


def _sine_log(v_column: bool):
    """6 s of v = 0.2 sin(pi t) at 1 kHz on a 2 kg axis whose friction differs by direction."""
    def friction(v, fc, fs):
        return np.sign(v) * (fc + (fs - fc) * np.exp(-(np.abs(v) / 0.01) ** 2)) + 0.4 * v
    t = np.arange(0.0, 6.0, 1e-3)
    v = 0.2 * np.sin(np.pi * t)
    force = 2.0 * np.gradient(v, 1e-3) + np.where(v > 0, friction(v, 1.0, 1.5), friction(v, 0.5, 0.8))
    x = np.cumsum(v) * 1e-3
    return {"t": t, "x": x, **({"v": v} if v_column else {}), "force": force}


def test_a_log_of_position_still_gets_one_curve_per_direction(tmp_path, capsys):
    """Each direction falls back to the folded vs_max estimate when its own leaves no
    high-speed rows for B, instead of a silent symmetric model."""
    columns = _sine_log(v_column=False)
    path = tmp_path / "logx.csv"
    path.write_text(table_csv_text(columns))
    assert main(["train", str(path), "--mass", "2", "--method", "elm_auto",   # quicker than the default
                 "-o", str(tmp_path / "m.json")]) == 0
    assert "symmetry asymmetric" in capsys.readouterr().out
    model = FrictionModel.load(tmp_path / "m.json")
    f = model.force(np.array([0.1, -0.1]))
    assert abs(f[0] - 1.04) < 0.05 and abs(f[1] + 0.54) < 0.05


def test_csv_text_writes_no_negative_zero():
    assert table_csv_text({"v": np.array([-0.0, -1.0, 0.0])}) == "v\n0.0\n-1.0\n0.0\n"


def test_x_and_v_swapped_are_named_as_swapped():
    from fricgen.data.motionlog import check_units
    ts = 1e-3
    t = np.arange(4000) * ts
    x = 0.05 * np.sin(2 * np.pi * 0.7 * t) + 0.01 * np.sin(2 * np.pi * 2.3 * t)
    v = np.gradient(x, ts)
    check_units(x, v, ts)                                   # as logged: no complaint
    with pytest.raises(DataError, match="are the x and v columns swapped"):
        check_units(v, x, ts)
    with pytest.raises(DataError, match=r"is t in ms, x in mm"):
        check_units(1000 * x, v, ts)                        # x in mm: not a swap


def test_a_merged_files_header_units_are_read(noisy, tmp_path, capsys):
    (tmp_path / "drive.csv").write_text("t,v\n" + "".join(
        f"{float(t)!r},{float(v)!r}\n" for t, v in zip(noisy["t"], noisy["v"])))
    common = ["--mass", str(RUN.mass), "--symmetric", "--method", "elm", "--neurons", "10"]
    trained = []
    for name, header, time_factor, force_factor in (("si.csv", "Stamp,Load", 1.0, 1.0),
                                                    ("units.csv", "Stamp [ms],Load [kN]", 1e3, 1e-3)):
        (tmp_path / name).write_text(header + "\n" + "".join(
            f"{float(t) * time_factor!r},{float(f) * force_factor!r}\n"
            for t, f in zip(noisy["t"], noisy["force"])))
        stamp, load = header.split(",")
        assert main(["train", str(tmp_path / "drive.csv"), "--merge", str(tmp_path / name),
                     "--merge-columns", f"t={stamp},force={load}", *common,
                     "-o", str(tmp_path / f"{name}.json")]) == 0
        trained.append(FrictionModel.load(tmp_path / f"{name}.json"))
    assert "force read in kN ('Load [kN]'): scaled by 1000 to SI" in capsys.readouterr().err
    v = np.linspace(-0.3, 0.3, 13)
    np.testing.assert_allclose(trained[1].force(v), trained[0].force(v), rtol=1e-6, atol=1e-9)


def test_a_log_out_of_time_order_counts_its_backward_steps():
    """One swapped pair of rows names its step alone; a shuffled log says how many more there
    are and asks for sorting (it named one of 1042 and nothing else)."""
    from fricgen.data.motionlog import uniform_sample_time
    t = np.arange(2000) * 1e-3
    swapped = t.copy()
    swapped[[100, 101]] = swapped[[101, 100]]
    with pytest.raises(DataError, match=r"between data rows 101 and 102: time must increase"):
        uniform_sample_time(swapped)
    shuffled = np.random.default_rng(0).permutation(t)
    with pytest.raises(DataError, match=r"and at \d+ other rows: sort the log by t\?"):
        uniform_sample_time(shuffled)


def joint_log_with_filtered_velocity(cutoff, seed=0):
    """A joint's log at 1 kHz: J = 0.05 kg m^2, Coulomb + viscous friction (0.8 Nm, 0.5 Nm s/rad),
    q to 2^20 counts a turn, dq a drive's first-order filtered estimate at ``cutoff`` Hz (None:
    the exact velocity), tau with 0.01 Nm of noise."""
    from scipy.integrate import cumulative_trapezoid
    from scipy.signal import lfilter
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 6.0, 1e-3)
    dq = 1.5 * np.sin(2 * np.pi * 0.4 * t) + 0.6 * np.sin(2 * np.pi * 1.1 * t)
    q = cumulative_trapezoid(dq, t, initial=0.0)
    tau = 0.05 * np.gradient(dq, t) + 0.8 * np.tanh(dq / 1e-3) + 0.5 * dq + 0.01 * rng.standard_normal(t.size)
    count = 2 * np.pi / 2 ** 20
    if cutoff is not None:
        alpha = 1.0 - np.exp(-2 * np.pi * cutoff * 1e-3)
        dq = lfilter([alpha], [1.0, alpha - 1.0], dq)
    return {"t": t, "q": np.round(q / count) * count, "dq": dq, "tau": tau}


def test_a_lagging_velocity_column_is_set_aside_for_the_positions_derivative():
    """dq filtered at 20 Hz (8 ms behind q's derivative) took the inertia 13 % high (0.0566
    +- 0.0023 kg m^2): the lag is found, said in one line, and the velocity taken from q. The
    exact dq is kept without a word."""
    said = []
    report = fricgen.train(joint_log_with_filtered_velocity(20.0), warn=said.append)
    inertia = report.identification.body
    assert [line for line in said if "lags dx/dt by" in line and "taken from x" in line]
    assert abs(inertia.inertia - 0.05) < 0.02 * 0.05
    said = []
    fricgen.train(joint_log_with_filtered_velocity(None), warn=said.append)
    assert not [line for line in said if "dx/dt" in line]


def test_a_joint_log_whose_dq_and_tau_are_swapped_is_refused_with_q_beside_them():
    """dq and tau swapped in a joint log with q: the torque read as a velocity leading dx/dt by
    50 ms was set aside for q's derivative, and the force, the velocity itself, trained to a
    viscous slope of 1 +- 1e-5. A lagging dx/dt must explain the velocity column to be one; the
    swap is then named."""
    log = joint_log_with_filtered_velocity(None, seed=3)
    swapped = {"t": log["t"], "q": log["q"], "dq": log["tau"], "tau": log["dq"]}
    with pytest.raises(DataError, match="swapped"):
        fricgen.train(swapped, warn=lambda line: None)


def viscous_joint_log(seed=0):
    """A joint's log at 100 Hz whose torque is mostly viscous (J = 3.3 kg m^2, F_c = 5.4 Nm, F_v =
    8.5 Nm s/rad, a 10 s sine of 0.98 rad/s, 0.7 Nm of noise): its torque is nearly a line of its
    speed, so the force's law reads alike with v and the force swapped."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 30.0, 0.01)
    w = 2 * np.pi / 10.0
    q, dq = 0.98 / w * (1 - np.cos(w * t)), 0.98 * np.sin(w * t)
    tau = 3.3 * 0.98 * w * np.cos(w * t) + 5.4 * np.sign(dq) + 8.5 * dq + 0.7 * rng.standard_normal(t.size)
    return {"t": t, "q": q, "dq": dq + 0.001 * rng.standard_normal(t.size), "tau": tau}


@pytest.mark.parametrize("swap, named", [(("dq", "tau"), "v and the force look swapped"),
                                         (("q", "tau"), "x and the force look swapped")])
def test_a_mostly_viscous_joint_logs_swapped_columns_are_named_not_called_units(swap, named):
    """A joint log whose torque is mostly viscous, with dq and tau (or q and tau) swapped, was
    refused as a matter of units ("dx/dt is 0.0593 times v: t in ms, x in mm?") or named the
    wrong pair (v and the force, for q and tau). The column that x's derivative follows, or
    whose derivative follows v, names the swap. The log as written trains."""
    log = viscous_joint_log()
    a, b = swap
    with pytest.raises(DataError, match=named):
        fricgen.train({**log, a: log[b], b: log[a]}, warn=lambda line: None)
    assert fricgen.train(log, warn=lambda line: None).model is not None


def test_a_load_larger_than_the_friction_trains_in_either_direction():
    """A vertical axis whose weight (35 N) exceeds its Coulomb friction (20 N): where it moved
    down more often than up, the force had the sign of the motion in fewer than half the rows
    before the offset was taken out, and the log was refused ("the force has the opposite sign
    of v in most rows"); its mirror image trained. The sign is judged beside the offset."""
    t = np.arange(0.0, 8.0, 2e-3)
    w = 2 * np.pi * 0.5
    v = 0.2 * np.sin(w * t) - 0.06                    # down more often than up
    x = -0.2 / w * np.cos(w * t) - 0.06 * t
    a = 0.2 * w * np.cos(w * t)
    noise = 0.3 * np.random.default_rng(1000).standard_normal(t.size)
    for load in (35.0, -35.0):
        force = 10.0 * a + np.sign(v) * (20.0 + 10.0 * np.exp(-(v / 0.01) ** 2)) + 50.0 * v + load + noise
        report = fricgen.train({"t": t, "x": x, "v": v, "force": force}, warn=lambda line: None)
        assert abs(report.training["axis"]["offset"] - load) < 0.5
        assert abs(report.model.force(0.1) - (20.0 + 5.0)) < 0.5


def test_a_log_with_a_force_and_a_current_says_which_it_trains_on(noisy, tmp_path, capsys):
    """A robot's log often holds tau and the motor current: the force is trained on, and one
    line says the current is not used (it had been left out without a word)."""
    cols = {**noisy, "current": 0.05 * noisy["force"]}
    (tmp_path / "log.csv").write_text(table_csv_text(cols))
    assert main(["train", str(tmp_path / "log.csv"), *FAST, "-o", str(tmp_path / "m.json")]) == 0
    said = [line for line in capsys.readouterr().err.splitlines() if "current i is not used" in line]
    assert len(said) == 1 and "trained on the force column" in said[0]
