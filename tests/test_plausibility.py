"""Well-formed input that is wrong gets a refusal or the right answer with one warning line; the
commands that read data share one reader; Ctrl-C is one line. (The refusals are rows of
tests/test_bad_input.py; these are the cases that answer.)"""
import json
import re
import signal

import numpy as np
import pytest

from conftest import copy_of
from fricgen.cli import INTERRUPTED, main
from fricgen.data.plausibility import (check_bounds, check_columns, check_merge_shift, check_sweep_shape,
                                      check_timing)
from fricgen.axis import Axis
from fricgen.errors import DataError, ModelError
from fricgen.training import train
from fricgen.model import FrictionModel


@pytest.fixture
def work(cli_inputs, tmp_path):
    return copy_of(cli_inputs, tmp_path / "work")


def _one_line(text: str) -> str:
    assert text.count("\n") == 1, text
    return text


def test_model_json_records_its_hash_and_a_hand_edit_gets_one_warning(work):
    model = json.loads((work / "model.json").read_text())
    loaded = FrictionModel.load(work / "model.json")
    assert model["model_hash"] == loaded.model_hash and not loaded.edited_after_training
    model["viscous"] *= 1.1
    (work / "edited.json").write_text(json.dumps(model))
    edited = FrictionModel.load(work / "edited.json")
    assert edited.edited_after_training
    warning = edited.hash_warning(work / "edited.json")
    assert warning.startswith("fricgen: warning: ") and "edited after training" in warning
    assert "\n" not in warning
    # the edited model is still evaluated as written: a warning, not a refusal
    assert edited.force(0.1) == pytest.approx(loaded.force(0.1) + 0.1 * 0.1 * model["viscous"] / 1.1)
    # the hash removed with the edit: the edit cannot be told, and that is said
    del model["model_hash"]
    (work / "unhashed.json").write_text(json.dumps(model))
    unhashed = FrictionModel.load(work / "unhashed.json")
    assert unhashed.edited_after_training
    assert "holds no model_hash" in _one_line(unhashed.hash_warning(work / "unhashed.json") + "\n")
    # a file that does not name the fricgen which wrote it is not one fricgen wrote: no claim
    del model["fricgen_version"]
    (work / "foreign.json").write_text(json.dumps(model))
    assert FrictionModel.load(work / "foreign.json").hash_warning(work / "foreign.json") == ""


def test_a_hand_edit_of_the_units_is_an_edit(work):
    """training.units says whether the force is in N or Nm: flipping it either way is told."""
    model = json.loads((work / "model.json").read_text())
    model["training"]["units"] = "rotary"
    rotary = FrictionModel.from_dict(model)
    assert rotary.edited_after_training                         # linear -> rotary
    rotary.save(work / "rotary.json")
    saved = json.loads((work / "rotary.json").read_text())
    assert not FrictionModel.load(work / "rotary.json").edited_after_training
    assert saved["model_hash"] != json.loads((work / "model.json").read_text())["model_hash"]
    saved["training"]["units"] = "linear"
    (work / "flipped.json").write_text(json.dumps(saved))
    assert FrictionModel.load(work / "flipped.json").edited_after_training    # rotary -> linear


def test_eval_of_an_edited_model_warns_once_on_stderr(work):
    import subprocess
    import sys
    model = json.loads((work / "model.json").read_text())
    model["viscous"] *= 1.1
    (work / "edited.json").write_text(json.dumps(model))
    runs = [subprocess.run([sys.executable, "-m", "fricgen", "eval", str(work / name)], input="0.05\n",
                           capture_output=True, text=True) for name in ("model.json", "edited.json")]
    assert [r.returncode for r in runs] == [0, 0] and runs[0].stderr == ""
    assert _one_line(runs[1].stderr).startswith("fricgen: warning: ")
    assert float(runs[1].stdout) > float(runs[0].stdout)


def test_ctrl_c_is_one_line_exit_130_and_nothing_written(work, tmp_path, capsys):
    rng = np.random.default_rng(0)
    v = rng.uniform(1e-4, 0.2, 40_000)
    f = 2 + 1.5 * np.exp(-(v / 0.01) ** 2) + 15 * v + rng.normal(0, 0.1, v.size)
    (tmp_path / "big.csv").write_text("v,f\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(v.tolist(), f.tolist())))

    def interrupt(*_):
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGALRM, interrupt)
    signal.setitimer(signal.ITIMER_REAL, 0.3)
    try:
        code = main(["train", str(tmp_path / "big.csv"), "-o", str(tmp_path / "m.json")])
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    captured = capsys.readouterr()
    assert code == INTERRUPTED == 130
    assert _one_line(captured.err) == "fricgen: interrupted; nothing written\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.csv", "work"]


def test_unusual_data_are_kept_with_accept_unusual_and_the_model_loads(work, tmp_path, capsys):
    rows = [line.split(",") for line in (work / "sweep.csv").read_text().splitlines()[1:]]
    (tmp_path / "mm.csv").write_text("v,f\n" + "".join(f"{1000 * float(a)!r},{b}\n" for a, b in rows))
    assert main(["train", str(tmp_path / "mm.csv"), "-o", str(tmp_path / "m.json"), "--accept-unusual"]) == 0
    warnings = [line for line in capsys.readouterr().err.splitlines() if line.startswith("fricgen: warning")]
    assert any("is v in mm/s?" in w for w in warnings)
    model = FrictionModel.load(tmp_path / "m.json")         # accepted at training: loads
    assert model.training["accept_unusual"] is True and model.v_sat > 2.0


def test_the_sweep_converted_with_scale_gives_the_truth(work, tmp_path):
    # the sweep in mm/s, read with --scale v=0.001, trains the model of the sweep in m/s
    rows = [line.split(",") for line in (work / "sweep.csv").read_text().splitlines()[1:]]
    (tmp_path / "mm.csv").write_text("v,f\n" + "".join(f"{1000 * float(a)!r},{b}\n" for a, b in rows))
    for name, extra in (("sweep.csv", []), ("mm.csv", ["--scale", "v=0.001"])):
        src = work / name if name == "sweep.csv" else tmp_path / name
        assert main(["train", str(src), "-o", str(tmp_path / f"{name}.json"), "--vs-max", "0.02",
                     "--method", "stribeck", *extra]) == 0
    a, b = (FrictionModel.load(tmp_path / f"{n}.json") for n in ("sweep.csv", "mm.csv"))
    v = np.linspace(0.001, 0.2, 50)
    np.testing.assert_allclose(b.force(v), a.force(v), rtol=1e-6)


def test_diagnose_reads_an_export_with_train_s_options(work, tmp_path, capsys):
    # a drive export timed in ms (preamble, vendor names) and a current file timed in s, merged:
    # the same diagnosis as the plain log
    log = (work / "log.csv").read_text().splitlines()
    header = log[0].split(",")
    col = {h: [line.split(",")[k] for line in log[1:]] for k, h in enumerate(header)}
    (tmp_path / "drive.csv").write_text("# export\nTime [ms],Pos,Speed\n" + "".join(
        f"{1000 * float(t)!r},{x},{v}\n" for t, x, v in zip(col["t"], col["x"], col["v"])))
    (tmp_path / "current.csv").write_text("Stamp,Current\n" + "".join(f"{t},{i}\n" for t, i in zip(col["t"], col["i"])))
    common = ["--model", str(work / "model.json"), "--mass", "4", "--force-constant", "20", "--json"]
    assert main(["diagnose", str(work / "log.csv"), *common, "-o", str(tmp_path / "a")]) == 0
    plain = json.loads(capsys.readouterr().out)
    assert main(["diagnose", str(tmp_path / "drive.csv"), "--skip", "1", "--columns",
                 "t=Time [ms],x=Pos,v=Speed", "--scale", "t=0.001", "--merge", str(tmp_path / "current.csv"),
                 "--merge-columns", "t=Stamp,i=Current", "--merge-scale", "t=1", *common,
                 "-o", str(tmp_path / "b")]) == 0
    exported = json.loads(capsys.readouterr().out)
    # the ms clock scaled back to s differs from the plain log's by roundings (1e-16 relative),
    # which the diagnosis carries as 1e-11 or less: the same answer
    _assert_close(exported, plain, rel=1e-8)
    # diagnose replaces its own report in a folder it wrote
    assert main(["diagnose", str(work / "log.csv"), *common, "-o", str(tmp_path / "a")]) == 0


def _assert_close(a, b, rel):
    """a equals b, numbers within ``rel`` (nested dicts and lists)."""
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for k in a:
            _assert_close(a[k], b[k], rel)
    elif isinstance(a, list):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            _assert_close(x, y, rel)
    elif isinstance(a, float):
        assert a == pytest.approx(b, rel=rel, abs=1e-12)
    else:
        assert a == b


def test_a_friction_sweep_passes_and_its_swap_is_refused():
    v = np.geomspace(1e-4, 0.2, 300)
    f = 10 + 5 * np.exp(-(v / 0.005) ** 2) + 40 * v + np.random.default_rng(1).uniform(-0.5, 0.5, v.size)
    check_sweep_shape(v, f, "s.csv")                    # friction: nothing said
    with pytest.raises(DataError, match="are the columns v and f swapped"):
        check_sweep_shape(f, v, "s.csv")
    with pytest.raises(DataError, match="no friction curve is in it"):
        check_sweep_shape(v, np.random.default_rng(2).normal(0.1, 1.0, v.size), "s.csv")
    warned = []
    check_sweep_shape(f, v, "s.csv", accept_unusual=True, warn=warned.append)
    assert len(warned) == 1 and warned[0].startswith("fricgen: warning: ")


@pytest.mark.parametrize("speeds", [np.geomspace(0.01, 1.0, 10), np.linspace(0.01, 1.0, 25)])
def test_an_asymmetric_sweep_passes_and_its_swap_is_refused(speeds):
    """Per-direction Coulomb + viscous (2 + 1.5 v and 1.4 + 2.2 |v|): the two directions'
    curves, folded into one, interleave; each is judged alone, so the sweep passes and its
    swap (which trained, F_c = 0 both ways) is refused, also where the speeds are set exactly
    and evenly spaced (no scatter about a running median either way)."""
    rng = np.random.default_rng(7)
    v = np.concatenate([speeds, -speeds])
    f = np.concatenate([2.0 + 1.5 * speeds, -1.4 - 2.2 * speeds]) + 0.03 * rng.standard_normal(v.size)
    check_sweep_shape(v, f, "s.csv")
    with pytest.raises(DataError, match="are the columns v and f swapped"):
        check_sweep_shape(f, v, "s.csv")


def test_the_merge_shift_is_checked_against_the_best_fitting_one(cli_inputs):
    rows = np.array([line.split(",") for line in (cli_inputs / "log.csv").read_text().splitlines()[1:]],
                    dtype=float)
    t, v, i = rows[:, 0], rows[:, 2], rows[:, 3]
    motion = {"t": t, "v": v}
    for true in (0.0, 0.004, -0.7):
        force = {"t": t - true, "force": 20 * i}        # its clock runs `true` s behind
        check_merge_shift(motion, force, true, ("a", "b"))             # right: nothing said
        if abs(true) > 0.1:
            with pytest.raises(DataError, match=r"--merge-shift 0 s looks off: .* about -0\.(69|70)"):
                check_merge_shift(motion, force, 0.0, ("a", "b"))


def test_a_sweep_in_m_per_min_is_refused_naming_the_unit(tmp_path, capsys):
    # 0.25 m/s written as 15 m/min, Stribeck velocity 5 mm/s: speeds beyond most axes, and no
    # linear high-speed region in this geometric sweep, so v_sat is its fastest "speed", 15 m/s:
    # beyond any real axis
    v = np.geomspace(2e-4, 0.25, 300)
    f = 10 + 6 * np.exp(-(v / 0.005) ** 2) + 40 * v + np.random.default_rng(7).normal(0, 0.2, v.size)
    (tmp_path / "m_min.csv").write_text("v,f\n" + "".join(f"{60 * a!r},{b!r}\n" for a, b in zip(v.tolist(), f.tolist())))
    assert main(["train", str(tmp_path / "m_min.csv"), "-o", str(tmp_path / "m.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is v in m/min (--scale v=0.0166667)" in err[0]
    assert not (tmp_path / "m.json").exists()


def test_a_position_in_mm_is_named_as_the_position_s_unit():
    """A log without v whose speed comes from x: the hint names x's unit and x's --scale."""
    t = np.arange(2000) / 1000.0
    x_mm = 1e3 * 0.0016 * np.sin(2 * np.pi * t)             # 1.6 mm at 10 mm/s, written in mm
    warned = []
    check_bounds({"t": t, "x": x_mm, "force": np.ones_like(t)}, "log.csv", warn=warned.append)
    assert len(warned) == 1 and "is x in mm (--scale x=0.001), or the axis a joint or shaft in rad (--rotary)?" in warned[0]
    with pytest.raises(DataError, match=r"above the 20 m/s of any real axis; is x in mm\? "
                                        r"--scale x=0\.001 converts it"):
        check_bounds({"t": t, "x": 1e3 * x_mm, "force": np.ones_like(t)}, "log.csv")


def test_a_current_beyond_any_drive_is_refused_naming_the_scale():
    t = np.arange(2000) / 1000.0
    v = 0.1 * np.sin(2 * np.pi * t)
    with pytest.raises(DataError, match=r"\|i\| \(99th percentile\) is 2e\+04 A, above the "
                                        r"10000 A of any real axis; is i in mA\? --scale i=0\.001"):
        check_bounds({"t": t, "v": v, "i": 2e4 * np.sign(v)}, "log.csv")


def test_forces_in_kn_get_one_warning_and_scaled_the_same_model(work, capsys):
    rows = [line.split(",") for line in (work / "sweep.csv").read_text().splitlines()[1:]]
    (work / "kn.csv").write_text("v,f\n" + "".join(f"{v},{float(f) / 1000!r}\n" for v, f in rows))
    args = ["--vs-max", "0.02", "--method", "stribeck", "--force"]
    assert main(["train", str(work / "sweep.csv"), "-o", str(work / "n.json"), *args]) == 0
    assert "warning" not in capsys.readouterr().err                   # newtons: nothing said
    assert main(["train", str(work / "kn.csv"), "-o", str(work / "kn.json"), *args]) == 0
    warnings = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(warnings) == 1 and "is f in kN (--scale f=1000)?" in warnings[0]
    assert main(["train", str(work / "kn.csv"), "-o", str(work / "scaled.json"), "--scale", "f=1000", *args]) == 0
    assert "warning" not in capsys.readouterr().err
    n, scaled = FrictionModel.load(work / "n.json"), FrictionModel.load(work / "scaled.json")
    assert scaled.force(0.05) == pytest.approx(n.force(0.05), rel=1e-6)


def test_a_log_timed_in_ms_read_as_s_is_named():
    from fricgen.data.plausibility import check_rate
    heard = []
    t = np.arange(2000) * 1e-3
    check_rate(t, "log.csv", heard.append)
    assert heard == []
    check_rate(1000 * t, "log.csv", heard.append)
    assert len(heard) == 1 and "sampled at 1 Hz" in heard[0] and "--scale t=0.001" in heard[0]
    check_rate(1e6 * t, "log.csv", heard.append)        # in us: 1e-3 would leave it at 1 Hz
    assert len(heard) == 2 and "is t in us (--scale t=1e-06)" in heard[1]
    check_rate(1000 * t, "log.csv", heard.append, {"t": "--scale t=1"})   # the user's own factor: no ask
    assert len(heard) == 3 and "after --scale t=1" in heard[2] and "is t in" not in heard[2]


def test_a_column_the_user_scaled_is_not_asked_about_that_unit_again():
    """A new user's trial: a shaft at 12000 rpm scaled with --scale v=0.10472 was still asked 'is
    v in rpm (--scale v=0.10472)?', which invites scaling twice; a shaft at 3000 rpm (314 rad/s)
    was warned about at all."""
    from fricgen._validate import rotary_axis
    t = np.arange(5000) / 1000.0
    heard = []
    with rotary_axis(True):
        for rpm in (3000.0, 12000.0):
            v = rpm * np.pi / 30 * np.cos(np.pi * t)
            check_bounds({"t": t, "v": v, "force": np.ones_like(t)}, "log.csv", warn=heard.append,
                         scaled={"v": "--scale v=0.10472"})
    assert len(heard) == 1 and "after --scale v=0.10472" in heard[0]
    assert "is v in" not in heard[0] and "above the 1000 rad/s" in heard[0]


def test_a_value_at_a_physical_bound_but_for_rounding_is_within_it():
    """A sweep whose fastest speed is 20 m/s gives a textbook law v_sat = 20.000000000000004:
    at the 20 m/s bound, not "20 m/s, above the 20 m/s"; a real excess is still refused."""
    from fricgen._validate import physical_problem
    assert physical_problem("v_sat", "v_sat", 20.000000000000004) == ""
    assert physical_problem("v_sat", "v_sat", 20.1) == "v_sat is 20.1 m/s, above the 20 m/s of any real axis"
    assert physical_problem("v_sat", "v_sat", 1e-7 * (1 - 1e-12)) == ""


def test_a_sweep_joined_twice_gets_one_warning(tmp_path, capsys):
    v = np.concatenate([np.geomspace(0.002, 0.5, 12), -np.geomspace(0.002, 0.5, 12)])
    f = np.sign(v) * (2.0 + 8.0 * np.abs(v)) + 0.01 * np.random.default_rng(1000).standard_normal(v.size)
    rows = "".join(f"{a!r},{b!r}\n" for a, b in zip(v.tolist(), f.tolist()))
    (tmp_path / "once.csv").write_text("v,f\n" + rows)
    (tmp_path / "twice.csv").write_text("v,f\n" + rows + rows)
    for name, warned in (("once.csv", False), ("twice.csv", True)):
        assert main(["train", str(tmp_path / name), "-o", str(tmp_path / (name + ".json"))]) == 0
        err = capsys.readouterr().err
        assert ("24 of 48 rows repeat an earlier row exactly" in err) is warned, err


def test_a_position_in_whole_counts_is_named_as_encoder_counts():
    """x of whole numbers too fast for metres: the hint names encoder counts and the size of one
    count, not a unit (4096 counts per 5 mm is no power of 1000)."""
    t = np.arange(2000) / 1000.0
    counts = np.round(4096 / 0.005 * 0.002 * np.sin(2 * np.pi * t))     # 2 mm, 1.2 um a count
    with pytest.raises(DataError, match=r"x holds whole numbers: encoder counts\? --scale x=M "
                                        r"converts them, M the radians \(2 pi over the counts per "
                                        r"turn\) or the metres of one count \(") as err:
        check_bounds({"t": t, "x": counts, "force": np.ones_like(t)}, "log.csv")
    assert "0.001" not in str(err.value)       # no power of 1000: a plausible wrong size


def _one_column_log(rng):
    """A log of an axis written here (2 kg, Coulomb 10 N smoothed over 2 mm/s, viscous 20 N s/m,
    reversals), 1 kHz: t, its position, velocity and force."""
    t = np.arange(0, 12, 1e-3)
    x = 0.1 * np.sin(2 * np.pi * 0.5 * t) + 0.05 * np.sin(2 * np.pi * 0.23 * t)
    v = np.gradient(x, t)
    f = 2 * np.gradient(v, t) + 10 * np.tanh(v / 0.002) + 20 * v + 0.3 * rng.standard_normal(t.size)
    return t, x, v, f


@pytest.mark.parametrize("named, swapped", [("x", False), ("x", True), ("v", False), ("v", True)])
def test_a_velocity_in_the_x_column_or_a_position_in_v_is_named(tmp_path, capsys, named, swapped):
    """A log of x alone whose column holds the velocity (or of v alone holding the position)
    trained on with the mass -6 kg, or was refused for the force's sign: it is now one line
    that names the column, exit 2, nothing written; the right column trains."""
    t, x, v, f = _one_column_log(np.random.default_rng(11))
    motion = {("x", False): x, ("x", True): v, ("v", False): v, ("v", True): x}[named, swapped]
    (tmp_path / "log.csv").write_text(f"t,{named},force\n" + "".join(
        f"{a!r},{b!r},{c!r}\n" for a, b, c in zip(t.tolist(), motion.tolist(), f.tolist())))
    code = main(["train", str(tmp_path / "log.csv"), "-o", str(tmp_path / "m.json")])
    out, err = capsys.readouterr()
    if not swapped:
        assert code == 0 and (tmp_path / "m.json").exists()
        assert "mass      2" in out and "--gravity" not in out + err    # no weight in this log
        return
    held, column = ("velocity", "v") if named == "x" else ("position", "x")
    assert code == 2 and not (tmp_path / "m.json").exists()
    assert f"{named} holds a {held}" in _one_line(err) and f"is it the {column} column?" in err


def test_a_log_whose_v_and_force_are_swapped_is_refused(tmp_path, capsys):
    """t, v, force with v and the force swapped trained on (a new user's trial): one line that
    names the swap, exit 2, nothing written."""
    t, _, v, f = _one_column_log(np.random.default_rng(12))
    (tmp_path / "log.csv").write_text("t,v,force\n" + "".join(
        f"{a!r},{b!r},{c!r}\n" for a, b, c in zip(t.tolist(), f.tolist(), v.tolist())))
    assert main(["train", str(tmp_path / "log.csv"), "-o", str(tmp_path / "m.json")]) == 2
    assert "are the v and force (or current) columns swapped?" in _one_line(capsys.readouterr().err)
    assert not (tmp_path / "m.json").exists()


@pytest.mark.parametrize("in_degrees, hint", [("v", "is v in deg/s and x in rad? --scale v=0.0174533"),
                                              ("x", "is x in degrees and v in rad/s? --scale x=0.0174533")])
def test_a_joint_log_half_in_degrees_names_degrees(in_degrees, hint):
    """dx/dt 57.3 (or 1/57.3) times v is a column in degrees beside one in radians: the refusal
    names degrees and the --scale that converts them (a new user's trial)."""
    from fricgen.data.motionlog import check_units
    t = np.arange(2000) / 500.0
    q = 0.8 * np.sin(2 * np.pi * 0.3 * t)
    dq = np.gradient(q, t)
    x, v = (q, np.degrees(dq)) if in_degrees == "v" else (np.degrees(q), dq)
    with pytest.raises(DataError, match=re.escape(hint)):
        check_units(x, v, 1 / 500.0)


def test_a_small_sweep_with_v_and_f_swapped_is_refused_and_a_real_one_is_not():
    """Under 20 rows no running median: a 'force' whose line on the 'speed' reaches 0 before
    v = 0 (no Coulomb level), on speeds that never near 0, is the columns swapped."""
    speed = np.array([0.01, 0.03, 0.1, 0.3, 1.0, 2.0])
    force = 1.2 + 0.5 * np.exp(-speed / 0.05) + 0.6 * speed
    v, f = np.concatenate([speed, -speed]), np.concatenate([force, -force])
    check_sweep_shape(v, f, "sweep.csv")                       # as measured: passes
    with pytest.raises(DataError, match="are the columns v and f swapped"):
        check_sweep_shape(f, v, "sweep.csv")
    warned = []
    check_sweep_shape(f, v, "sweep.csv", accept_unusual=True, warn=warned.append)
    assert len(warned) == 1


@pytest.mark.parametrize("rotary, columns, hint", [
    (True, {"x": 100.0 * 57.29578}, "; is x in deg (--scale x=0.0174533)?"),
    (True, {"v": 1500.0 * 30 / np.pi ** 2}, "; is v in rpm (--scale v=0.10472) or deg/s (--scale v=0.0174533)?"),
    (False, {"x": 40.0}, "--scale x=0.001 converts it; or is the axis a joint or shaft (--rotary), x in rad, "
                         "or in deg (--scale x=0.0174533)?"),
    (False, {"v": 114.6}, "; or is the axis a joint or shaft (--rotary), v in rad/s, or in rpm (--scale "
                          "v=0.10472) or deg/s (--scale v=0.0174533)?"),
])
def test_a_shaft_too_fast_for_its_units_is_asked_about_degrees_rpm_or_rotary(rotary, columns, hint):
    """A new user's trial: a shaft's x in degrees was asked 'is x in mrad?', rpm 'is v in
    mrad/s?', a shaft in rad without --rotary 'is x in mm?': each hint, followed, trained a
    silently wrong model. A joint's sweep in deg/s, asked only of mm/s and rad/s, trained with
    --rotary at 114.6 rad/s, its viscous friction 57 times too small."""
    from fricgen._validate import rotary_axis
    t = np.arange(5000) / 1000.0
    (name, amplitude), = columns.items()
    wave = amplitude * (np.sin(np.pi * t) if name == "x" else np.cos(np.pi * t) * np.pi)
    with rotary_axis(rotary), pytest.raises(DataError) as refused:
        check_bounds({"t": t, name: wave, "force": np.ones_like(t)}, "log.csv")
    assert hint in str(refused.value) and "mrad" not in str(refused.value)


def test_a_hand_edit_of_the_laws_record_is_said_not_silently_ignored(tmp_path, capsys):
    """training.coulomb is a record of the fitted law, outside the model_hash: edited, it
    changes nothing eval and emit compute, and one warning line says so; the unedited file and
    one whose record still gives its force warn of nothing."""
    v = np.concatenate([np.geomspace(0.002, 0.5, 8), -np.geomspace(0.002, 0.5, 8)])
    (tmp_path / "sweep.csv").write_text("v,f\n" + "".join(
        f"{a!r},{float(np.sign(a) * 2.0 + 10.0 * a)!r}\n" for a in v.tolist()))
    assert main(["train", str(tmp_path / "sweep.csv"), "-o", str(tmp_path / "m.json")]) == 0
    model = json.loads((tmp_path / "m.json").read_text())
    assert model["training"]["coulomb"] == pytest.approx(2.0)
    model["training"]["coulomb"] = 3.0
    (tmp_path / "edited.json").write_text(json.dumps(model))
    capsys.readouterr()
    answers = []
    for name in ("m.json", "edited.json"):
        assert main(["emit", str(tmp_path / name), "-o", str(tmp_path / name.replace(".json", "_c"))]) == 0
        answers.append(capsys.readouterr().err)
    warned = [[line for line in err.splitlines() if "warning" in line] for err in answers]
    assert warned[0] == [] and len(warned[1]) == 1
    assert warned[1][0].startswith(f"fricgen: warning: {tmp_path / 'edited.json'}: training's law")
    assert (tmp_path / "m_c" / "friction_model.c").read_text() == \
        (tmp_path / "edited_c" / "friction_model.c").read_text()


def test_a_freshly_trained_record_is_not_taken_for_an_edit_where_one_direction_is_slower(tmp_path, capsys):
    """A per-direction Stribeck law whose v < 0 sweep stops short of the v > 0 one: its record
    was checked up to the faster direction's speed, beyond that curve's v_sat, where the model
    runs on along its slope and the law along its curve, and a file fresh from train was called
    'edited by hand?'."""
    def law(speed, coulomb):
        return coulomb + 1.5 * np.exp(-(speed / 0.2) ** 2) + 10.0 * speed
    up, down = np.geomspace(0.005, 0.5, 12), np.geomspace(0.005, 0.1, 12)
    rows = [(a, float(law(a, 2.0))) for a in up.tolist()] + [(-a, -float(law(a, 1.0))) for a in down.tolist()]
    (tmp_path / "sweep.csv").write_text("v,f\n" + "".join(f"{a!r},{b!r}\n" for a, b in rows))
    assert main(["train", str(tmp_path / "sweep.csv"), "--asymmetric", "-o", str(tmp_path / "m.json")]) == 0
    assert "static" in json.loads((tmp_path / "m.json").read_text())["training"]["negative"]
    capsys.readouterr()
    assert main(["emit", str(tmp_path / "m.json"), "-o", str(tmp_path / "c")]) == 0
    assert "edited by hand" not in capsys.readouterr().err


def test_a_tiny_mass_of_a_linear_model_asks_whether_the_axis_is_rotary():
    """A rotary calibration trained as linear gave a mass of 0.0002 kg that the model's own
    check refused as 'an edited record?'; it now asks whether that is a joint's or a shaft's
    inertia, trained with --rotary."""
    record = {"speed_min": 0.01, "speed_max": 1.0, "mass": 2e-4, "mass_se": None,
              "mass_from": "data", "force_constant": None, "offset": None, "offset_se": None}
    with pytest.raises(ModelError, match="inertia in kg m\\^2\\? train it with --rotary"):
        Axis.from_dict(record)


def linear_axis_log(seed=1000, seconds=8.0):
    """A 10 kg linear axis at 1 kHz, a sum of sines to 0.23 m/s, Coulomb 20 N, Stribeck peak
    30 N at 0.01 m/s, viscous 50 N s/m, 0.5 N of noise: columns t, x, v, force."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, 1e-3)
    parts = ((0.15, 0.5), (0.08, 1.3))
    v = sum(a * np.sin(2 * np.pi * f * t) for a, f in parts)
    x = sum(-a / (2 * np.pi * f) * np.cos(2 * np.pi * f * t) for a, f in parts)
    accel = sum(a * 2 * np.pi * f * np.cos(2 * np.pi * f * t) for a, f in parts)
    friction = np.sign(v) * (20.0 + 10.0 * np.exp(-(v / 0.01) ** 2)) + 50.0 * v
    return {"t": t, "x": x, "v": v, "force": 10.0 * accel + friction + 0.5 * rng.standard_normal(t.size)}


@pytest.mark.parametrize("with_x", [True, False])
def test_a_logs_v_swapped_with_the_force_is_named_before_the_bounds(with_x):
    """v and the force swapped in a linear axis's log: the bounds read the force, 40 'm/s', as a
    velocity in mm/s and said so ("is v in mm/s? --scale v=0.001"), whose scale would have
    given a plausible axis. The swap is named first, with x beside them or without."""
    log = linear_axis_log()
    swapped = {**log, "v": log["force"], "force": log["v"]}
    if not with_x:
        del swapped["x"]
    with pytest.raises(DataError, match="v and the force look swapped"):
        check_columns(swapped, "log.csv", True, warn=lambda line: None)
    check_columns(log, "log.csv", True, warn=lambda line: None)


def test_a_logs_x_swapped_with_the_force_is_named_without_v():
    """x and the force swapped in a log of t, x and force: the bounds read the force's rate, 1800
    'm/s', as a position in mm ("is x in mm?"). Friction and inertia explain dx/dt from the
    force's derivative far better than the force from dx/dt: the swap is named; the log as
    written passes."""
    log = linear_axis_log()
    del log["v"]
    with pytest.raises(DataError, match="x and the force look swapped"):
        check_columns({**log, "x": log["force"], "force": log["x"]}, "log.csv", True, warn=lambda line: None)
    check_columns(log, "log.csv", True, warn=lambda line: None)


@pytest.mark.parametrize("mass", [None, 10.0])
def test_a_log_that_holds_no_friction_is_refused_in_one_line(mass):
    """A new user's trial: v of another axis beside this one's force, given the mass, trained a
    model of F_c 0 and B 0.39 +- 0.35 that explained nothing, and without the mass was told of
    units. A log whose force, less the inertia's, follows neither sgn(v) nor v (here an axis
    without friction: inertia and noise) is refused in one line that says so; the same axis
    with friction trains."""
    log = linear_axis_log(seconds=20.0)
    t = log["t"]
    parts = ((0.15, 0.5), (0.08, 1.3))
    accel = sum(a * 2 * np.pi * f * np.cos(2 * np.pi * f * t) for a, f in parts)
    frictionless = {**log, "force": 10.0 * accel + 0.5 * np.random.default_rng(5).standard_normal(t.size)}
    with pytest.raises(DataError, match=r"the log holds no friction: .*neither 3 standard errors "
                                        r"from 0\)"):
        train(frictionless, mass=mass, warn=lambda line: None)
    assert train(log, mass=mass, warn=lambda line: None).model is not None


@pytest.mark.parametrize("shift, said", [(0, None), (10, "leads the motion by 10 samples (10 ms)"),
                                         (-6, "lags the motion by 6 samples (6 ms)"), (1, None)])
def test_a_force_column_off_its_motion_by_a_few_samples_is_warned_about(shift, said):
    """A new user's trial: the force 10 ms ahead of v at 1 kHz trained a 3 kg axis as 3.15 kg
    and its viscous friction as 3.1 of 4 N s/m without a word. The force fits the motion far
    better shifted back: one warning line names the shift; in time, or a sample off, none."""
    log = linear_axis_log(seconds=8.0)
    force = np.roll(log["force"], -shift)          # row k holds the force of row k + shift
    warned = []
    check_timing({"t": log["t"], "v": log["v"], "force": force}, "log.csv", warned.append)
    assert warned == [] if said is None else (len(warned) == 1 and said in warned[0])


def test_a_filtered_velocity_columns_lag_is_not_taken_for_the_forces():
    """A log of x, a drive's velocity filtered 3 samples late and the force in time: the
    velocity's lag had been warned of as the force leading the motion by 3 samples ("shift one
    column", which would have made the log wrong). The motion is x's where the log has x."""
    log = linear_axis_log(seconds=8.0)
    x = np.cumsum(log["v"]) * float(np.median(np.diff(log["t"])))
    late = np.concatenate([np.full(3, log["v"][0]), log["v"][:-3]])
    warned = []
    check_timing({"t": log["t"], "x": x, "v": late, "force": log["force"]}, "log.csv", warned.append)
    assert warned == []
    check_timing({"t": log["t"], "v": late, "force": log["force"]}, "log.csv", warned.append)
    assert len(warned) == 1 and "leads the motion by 3 samples" in warned[0]


def test_a_delay_beyond_the_first_search_is_located_not_told_as_its_edge():
    """A force 120 samples behind its motion had been told as 50 samples off (the first
    search's edge): the search goes on where its best lies at the edge."""
    log = linear_axis_log(seconds=8.0)
    warned = []
    check_timing({"t": log["t"], "v": log["v"], "force": np.roll(log["force"], -120)}, "log.csv",
                 warned.append)
    assert len(warned) == 1 and "leads the motion by 120 samples" in warned[0]


def test_a_causally_filtered_velocity_without_x_is_warned_about():
    """A drive's velocity through a causal 10 ms filter, no x, on speed steps of a 4 kg axis
    with a Stribeck dip: the curve's misfit in the check's Coulomb + viscous law hid the shift
    (a new user's axis trained a mass 22 % high without a word); with Stribeck drops in the law
    one warning names it. The same log in time gets none."""
    rng = np.random.default_rng(1000)
    levels = [0.005, 0.01, 0.02, 0.05, 0.1, 0.2, -0.005, -0.01, -0.02, -0.05, -0.1, -0.2]
    knots_v = np.concatenate([[0.0], np.repeat(levels, 2), [0.0]])
    knots_t = np.concatenate([[0.0], np.cumsum(np.tile([0.15, 0.7], len(levels))), [0.15 + 0.85 * len(levels)]])
    t = np.arange(0.0, knots_t[-1], 1e-3)
    v = np.interp(t, knots_t, knots_v)
    accel = np.gradient(v, t)
    friction = np.sign(v) * (10.0 + 5.0 * np.exp(-(v / 0.01) ** 2)) + 40.0 * v
    force = 4.0 * accel + friction + 0.3 * rng.standard_normal(t.size)
    measured = v + 2e-4 * rng.standard_normal(t.size)
    k = 1e-3 / (0.01 + 1e-3)
    filtered = np.copy(measured)
    for n in range(1, v.size):
        filtered[n] = filtered[n - 1] + k * (measured[n] - filtered[n - 1])
    warned = []
    check_timing({"t": t, "v": measured, "force": force}, "log.csv", warned.append)
    assert warned == []
    check_timing({"t": t, "v": filtered, "force": force}, "log.csv", warned.append)
    assert len(warned) == 1 and "leads the motion by" in warned[0]
