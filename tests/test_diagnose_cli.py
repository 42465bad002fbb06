"""fricgen diagnose / synth-log on the command line: outputs, --json, and unusable input
refused with one line, exit code 2 and nothing written."""
import json

import numpy as np
import pytest

from fricgen.cli import main
from fricgen.sim.logsynth import LogSpec, nominal_model, synthesize_log
from fricgen.data.motionlog import MotionLog, log_csv_text, read_log_csv
from fricgen.diagnose.diagnoser import Diagnoser
from fricgen.errors import DataError
from fricgen.model import FrictionModel

ARGS = ["--mass", "4", "--force-constant", "20"]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("diag")
    model = nominal_model()
    model.save(folder / "model.json")
    log = synthesize_log(LogSpec(effect="constant_load", duration=6.0), model)
    (folder / "log.csv").write_text(log_csv_text(log))
    return folder, log


def test_diagnose_writes_model_report_plots_and_prints_json(files, capsys):
    folder, _ = files
    out = folder / "out"
    assert main(["diagnose", str(folder / "log.csv"), "--model", str(folder / "model.json"), *ARGS,
                 "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["effect"] == "constant_load"
    assert summary["parameters"]["load"] == pytest.approx(5.0, rel=0.05)
    assert summary["gap_after"] <= 0.5 * summary["gap_before"]
    model = json.loads((out / "model.json").read_text())
    assert model["effects"][0]["effect"] == "constant_load"
    report = (out / "report.md").read_text()
    assert "constant_load" in report and "Gap on the held-out part" in report
    pytest.importorskip("matplotlib")
    for png in ("residuals.png", "velocity.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_augmented_model_emits_force_xv(files, tmp_path):
    folder, _ = files
    out = tmp_path / "d"
    assert main(["diagnose", str(folder / "log.csv"), "--model", str(folder / "model.json"), *ARGS,
                 "--out", str(out)]) == 0
    assert main(["emit", str(out / "model.json"), "-o", str(tmp_path / "c"), "--name", "ax"]) == 0
    assert "float ax_force_xv(float v, float x);" in (tmp_path / "c" / "ax.h").read_text()
    # fixed point does not carry effects: refused with one line, nothing written
    assert main(["emit", str(out / "model.json"), "-o", str(tmp_path / "q"), "--dtype", "q31"]) == 2
    assert not (tmp_path / "q").exists()


def test_a_force_log_without_v_is_diagnosed_as_its_current_log(files, tmp_path, capsys):
    """A log of t, x and the drive force in N (what train reads) is the log of current at a
    force constant of 1 N/A, v from x: the same effect, and each reading said in one line."""
    folder, log = files
    (tmp_path / "force.csv").write_text("t,x,force\n" + "".join(
        f"{t!r},{x!r},{20.0 * i!r}\n" for t, x, i in zip(log.t.tolist(), log.x.tolist(), log.i.tolist())))
    assert main(["diagnose", str(tmp_path / "force.csv"), "--model", str(folder / "model.json"),
                 "--mass", "4", "--out", str(tmp_path / "out"), "--json"]) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert summary["effect"] == "constant_load"
    assert summary["parameters"]["load"] == pytest.approx(5.0, rel=0.05)
    assert "read as the drive force: phi = 1 N/A" in captured.err and "v = dx/dt" in captured.err
    assert "a constant_load is the same force as a friction whose level is higher one way" in captured.err
    assert main(["diagnose", str(tmp_path / "force.csv"), "--model", str(folder / "model.json"),
                 *ARGS, "--out", str(tmp_path / "refused")]) == 2
    assert "--force-constant applies to a current column i" in capsys.readouterr().err
    assert not (tmp_path / "refused").exists()


def test_the_offset_of_the_model_s_axis_is_not_named_again(files, tmp_path, capsys):
    """The log hides a 5 N load; a model whose axis record holds that offset (a symmetric
    curve leaves it out) carries it into the diagnosis as a constant_load, and the load is not
    named again; a model that holds less names the change."""
    folder, _ = files
    model = json.loads((folder / "model.json").read_text())
    speeds = {"speed_min": 0.001, "speed_max": 0.2}
    model["training"]["axis"] = {"mass": 4.0, "mass_se": None, "mass_from": "option",
                                 "force_constant": 20.0, "offset": 5.0, "offset_se": 0.01, **speeds}
    (tmp_path / "m.json").write_text(json.dumps(model))
    assert main(["diagnose", str(folder / "log.csv"), "--model", str(tmp_path / "m.json"),
                 "--out", str(tmp_path / "out"), "--json"]) == 0
    captured = capsys.readouterr()
    assert "o = 5 N, held as a constant_load" in captured.err
    assert all(e["effect"] != "constant_load" for e in json.loads(captured.out)["effects"])
    written = json.loads((tmp_path / "out" / "model.json").read_text())
    assert written["effects"][0] == {"effect": "constant_load", "parameters": {"load": 5.0}}
    # the emitted header says where the offset is, so that the firmware adds it once
    for source, said in ((folder / "model.json", False), (tmp_path / "out" / "model.json", True)):
        assert main(["emit", str(source), "--name", "axis", "-o", str(tmp_path / "c"), "--force"]) == 0
        header = (tmp_path / "c" / "axis.h").read_text()
        assert ("force_xv holds it already" in header) is said
    # the load changed since training (3 N held of the log's 5 N): the change is named, and
    # model.json holds one load, their sum
    model["training"]["axis"]["offset"] = 3.0
    (tmp_path / "m3.json").write_text(json.dumps(model))
    assert main(["diagnose", str(folder / "log.csv"), "--model", str(tmp_path / "m3.json"),
                 "--out", str(tmp_path / "out3"), "--json"]) == 0
    captured = capsys.readouterr()
    named = json.loads(captured.out)["effects"]
    assert [e["effect"] for e in named] == ["constant_load"]
    assert named[0]["parameters"]["load"] == pytest.approx(2.0, rel=0.05)
    loads = [e for e in json.loads((tmp_path / "out3" / "model.json").read_text())["effects"]
             if e["effect"] == "constant_load"]
    assert len(loads) == 1 and loads[0]["parameters"]["load"] == pytest.approx(5.0, rel=0.02)
    assert "the change of the load the model held (3 N): model.json holds their sum" in captured.err


def test_synth_log_writes_a_readable_log(tmp_path):
    path = tmp_path / "log.csv"
    assert main(["synth-log", "--effect", "position_ripple", "--duration", "1.5", "-o", str(path)]) == 0
    log = read_log_csv(path)
    assert len(log) == 1501 and "x_d" in log.extra


def _log_text(log, mutate):
    cols = {"t": log.t.copy(), "x": log.x.copy(), "v": log.v.copy(), "i": log.i.copy()}
    mutate(cols)
    names = list(cols)
    rows = zip(*(cols[k].tolist() for k in names))
    return ",".join(names) + "\n" + "".join(",".join(repr(c) for c in r) + "\n" for r in rows)


def _bad_inputs():
    def drop_i(c): del c["i"]
    def nan_v(c): c["v"][100] = float("nan")
    def jitter_t(c): c["t"][500:] += 0.0004
    def short(c):
        for k in c: c[k] = c[k][:400]
    def still(c):
        c["v"][:] = 0.0
        c["x"][:] = c["x"][0]

    def t_in_ms(c):
        c["t"][:] = 1000.0 * c["t"]

    def noise_only(c):
        rng = np.random.default_rng(3)
        c["x"][:] = c["x"][0] + 1e-6 * rng.standard_normal(c["x"].size)
        c["v"][:] = 1e-4 * rng.standard_normal(c["v"].size)

    def i_almost_constant(c):
        c["i"][:] = 1.0
        c["i"][7] = 1.0001

    def i_negated(c):
        c["i"][:] = -c["i"]

    def in_mm(c):
        c["x"][:] = 1000.0 * c["x"]
        c["v"][:] = 1000.0 * c["v"]
    yield "missing column", drop_i, ARGS, "a log needs the columns t, x, v, i: missing i (header is t,x,v)"
    yield "NaN", nan_v, ARGS, "NaN"
    yield "non-uniform", jitter_t, ARGS, "not uniformly sampled"
    yield "too short", short, ARGS, "need at least"
    yield "no motion", still, ARGS, "the axis never moves"
    yield "time in ms", t_in_ms, ARGS, "dx/dt is 0.001 times v"
    yield "standing still in the noise", noise_only, ARGS, "x does not follow v"
    yield "current constant but one sample", i_almost_constant, ARGS, "current i is constant"
    yield "current of the wrong sign", i_negated, ARGS, "sign of the current or of the force constant"
    yield "x and v in mm", in_mm, ARGS, "is v in mm/s? --scale v=0.001 converts it"
    yield "force constant 1000 x off", None, ["--mass", "4", "--force-constant", "20000"], "beyond the factor 5"
    yield "mass in tonnes", None, ["--mass", "0.004", "--force-constant", "20"], "check the mass, its unit"
    yield "mass and phi both 1000 x", None, ["--mass", "4000", "--force-constant", "20000"], "x the model's friction"
    yield "mass in grams", None, ["--mass", "4000", "--force-constant", "20"], "check the force constant, the mass"
    yield "zero mass", None, ["--mass", "0", "--force-constant", "20"], "--mass: must be"
    yield "negative phi", None, ["--mass", "4", "--force-constant", "-2"], "--force-constant: must be"
    yield "text mass", None, ["--mass", "heavy", "--force-constant", "20"], "--mass: must be"
    yield "nan phi", None, ["--mass", "4", "--force-constant", "nan"], "--force-constant: must be"


@pytest.mark.parametrize("label, mutate, args, message", list(_bad_inputs()), ids=[b[0] for b in _bad_inputs()])
def test_unusable_input_exits_2_with_one_line_and_writes_nothing(files, tmp_path, capsys, label, mutate,
                                                                  args, message):
    folder, log = files
    path = tmp_path / "bad.csv"
    path.write_text(_log_text(log, mutate or (lambda c: None)))
    out = tmp_path / "out"
    code = main(["diagnose", str(path), "--model", str(folder / "model.json"), *args, "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith("fricgen: error: ") and err.count("\n") == 1 and message in err, err
    assert not out.exists()


def test_a_broken_model_is_refused_before_anything_is_written(files, tmp_path, capsys):
    folder, _ = files
    bad = tmp_path / "model.json"
    d = json.loads((folder / "model.json").read_text())
    d["effects"] = [{"effect": "gremlins", "parameters": {}}]
    bad.write_text(json.dumps(d))
    code = main(["diagnose", str(folder / "log.csv"), "--model", str(bad), *ARGS, "--out", str(tmp_path / "o")])
    assert code == 2 and "unknown effect" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_extra_columns_are_kept_when_numeric_and_left_out_when_text(files, tmp_path):
    """Columns beside t, x, v, i are read when they hold numbers; a column of text is left out
    instead of refusing the log."""
    _, log = files
    lines = _log_text(log, lambda c: None).splitlines()
    body = [lines[0] + ",x_d,note"] + [f"{row},{k * 1e-3!r},ok" for k, row in enumerate(lines[1:])]
    path = tmp_path / "extra.csv"
    path.write_text("\n".join(body) + "\n")
    read = read_log_csv(path)
    np.testing.assert_array_equal(read.i, log.i)
    assert read.extra["x_d"][2] == 2e-3 and "note" not in read.extra


def test_a_log_beyond_a_tables_range_gets_a_note(files, tmp_path, capsys):
    """A table fitted on one stretch of travel holds its end values beyond it; a log that goes
    further is diagnosed, with a note on stderr that says how much of it lies outside."""
    folder, log = files
    lo, hi = np.quantile(log.x, [0.25, 0.75])
    d = json.loads((folder / "model.json").read_text())
    d["effects"] = [{"effect": "table_position",
                     "parameters": {"lo": float(lo), "hi": float(hi), "values": [0.0] * 8}}]
    model = tmp_path / "with_table.json"
    model.write_text(json.dumps(d))
    code = main(["diagnose", str(folder / "log.csv"), "--model", str(model), *ARGS,
                 "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 0
    notes = [line for line in err.splitlines() if line.startswith("fricgen: note: ") and "range" in line]
    assert len(notes) == 1 and "outside table_position's range" in notes[0], err
    assert 45 <= int(notes[0].split("fricgen: note: ")[1].split("%")[0]) <= 55


@pytest.mark.parametrize("rate, decimals, gap, accepted", [
    (300.0, 3, 0, True), (700.0, 4, 0, True), (300.0, 2, 0, True), (4000.0, 3, 0, True),
    (300.0, 2, 30, False), (4000.0, 3, 40, False)])
def test_time_written_with_few_decimals_is_read_as_the_grid_it_was_rounded_from(
        tmp_path, rate, decimals, gap, accepted):
    """A uniform log whose time column was written to milliseconds (steps of 3 and 4 ms at
    300 Hz) is the uniform grid; so is one rounded coarser than its step (300 Hz to 10 ms, 4 kHz
    to whole ms: several rows to a stamp, which had been refused). ``gap`` rows left out of
    it are a gap the rounding cannot hide, refused."""
    n = 1500
    k = np.arange(n)
    k = np.where(k < n // 2, k, k + gap)
    t = 1000.0 + k / rate
    lines = ["t,x,v,i"] + [f"{tk:.{decimals}f},{0.3 * j / rate:.9g},0.3,1.0" for j, tk in zip(k, t)]
    path = tmp_path / "rounded.csv"
    path.write_text("\n".join(lines) + "\n")
    if accepted:
        assert read_log_csv(path).sample_time == pytest.approx(1.0 / rate, rel=1e-5)
    else:
        with pytest.raises(DataError, match="not uniformly sampled|must increase|gap|repeats"):
            read_log_csv(path)


def _with_effect(model_path, effect, parameters):
    d = json.loads(model_path.read_text())
    d["effects"] = [{"effect": effect, "parameters": parameters}]
    return FrictionModel.from_dict(d)


def test_a_carried_mass_or_force_constant_is_the_axis_whatever_is_given_now(files):
    """model.json from a run with the wrong --mass carries the true mass; diagnosing with the
    corrected --mass (or the old one) sees the same axis, not the correction applied twice."""
    folder, log = files
    plain = FrictionModel.load(folder / "model.json")
    gap = Diagnoser().held_out_gap(log, plain, 4.0, 20.0)
    carried = _with_effect(folder / "model.json", "inertia_mismatch", {"mass": 4.0, "nominal_mass": 12.0})
    for mass in (4.0, 12.0):
        assert Diagnoser().held_out_gap(log, carried, mass, 20.0) == pytest.approx(gap, rel=1e-9)
    phi = _with_effect(folder / "model.json", "force_constant_mismatch",
                       {"force_constant": 20.0, "nominal_force_constant": 60.0})
    assert Diagnoser().held_out_gap(log, phi, 4.0, 20.0) == pytest.approx(gap, rel=1e-9)


def test_a_carried_drift_starts_with_the_log(files):
    """A drift is measured from the model's level at the start of each log, so a log whose
    clock starts at 1000 s gets the gap of the same log starting at 0."""
    folder, log = files
    drift = _with_effect(folder / "model.json", "thermal_drift",
                         {"rate": 0.02, "offset": 0.0, "t0": 0.0, "time_constant": 0.0})
    late = MotionLog(t=log.t + 1000.0, x=log.x, v=log.v, i=log.i)
    gap = Diagnoser().held_out_gap(log, drift, 4.0, 20.0)
    assert Diagnoser().held_out_gap(late, drift, 4.0, 20.0) == pytest.approx(gap, rel=1e-6)


def test_a_rotary_model_s_gaps_are_in_rad_per_second(files, tmp_path, capsys):
    """A model trained on a rotary axis (training.units) gets its diagnosis's gaps in rad/s,
    on the command line and in report.md."""
    folder, _ = files
    model = json.loads((folder / "model.json").read_text())
    model["training"]["units"] = "rotary"
    (tmp_path / "m.json").write_text(json.dumps(model))
    assert main(["diagnose", str(folder / "log.csv"), "--model", str(tmp_path / "m.json"), *ARGS,
                 "--out", str(tmp_path / "out")]) == 0
    gap = [line for line in capsys.readouterr().out.splitlines() if line.startswith("gap ")]
    assert len(gap) == 1 and " rad/s (rms velocity error (rad/s)" in gap[0] and "m/s" not in gap[0]
    report = (tmp_path / "out" / "report.md").read_text()
    assert "| velocity gap (rad/s) |" in report and "gap before (rad/s)" in report
