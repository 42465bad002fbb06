"""A log whose force is the drive's set-point, held over the sample after the one it is logged
at (``train --force-held``): brought to the motion's sample times before inverse dynamics."""
import json

import numpy as np
import pytest

import fricgen
from fricgen.cli import main
from fricgen.data.inverse_dynamics import at_sample_times, identify_log
from independent_axis import counts_friction as law
from independent_axis import counts_log


@pytest.fixture(scope="module")
def held_log():
    """The independent axis's PI loop: its force is logged as it is sent and held for a sample;
    its speed profile has sharp corners at +-0.2 m/s."""
    return counts_log(3, 1000.0, 8.0, substeps=10)


def test_each_row_is_the_mean_with_the_row_before_and_a_runs_first_row_is_kept():
    held = np.array([1.0, 3.0, 5.0, 10.0, 20.0])
    junction = np.array([False, False, False, True, False])
    assert at_sample_times(held, junction).tolist() == [1.0, 2.0, 4.0, 10.0, 15.0]


def test_the_corner_of_the_speed_profile_no_longer_biases_the_fastest_samples(held_log):
    """At the corner m x jerk x half a sample biases the samples as logged; aligned, the bias
    shrinks to a fraction, and the smoothing window (chosen on the force as logged) is the same."""
    def top_bias(ident):
        sweep = ident.friction
        top = np.abs(sweep.v) > 0.198
        return float(np.mean((sweep.f[top] - law(sweep.v[top])) * np.sign(sweep.v[top])))
    logged, aligned = identify_log(held_log), identify_log(held_log, held=True)
    assert top_bias(logged) < -0.05                     # the lead shows at the corner
    assert abs(top_bias(aligned)) < 0.4 * abs(top_bias(logged))
    assert aligned.window == logged.window


def test_train_records_it_and_the_report_says_so(held_log, tmp_path, capsys):
    path = tmp_path / "log.csv"
    np.savetxt(path, np.column_stack([held_log[k] for k in ("t", "x", "force")]), delimiter=",",
               header="t,x,force", comments="", fmt="%.9g")
    out = tmp_path / "m.json"
    assert main(["train", str(path), "--force-held", "-o", str(out)]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if "held over each sample" in line]
    assert len(lines) == 1 and lines[0].startswith("force")
    assert json.loads(out.read_text())["training"]["log"]["force_held"] is True
    assert fricgen.FrictionModel.load(out).training["log"]["force_held"] is True


@pytest.mark.parametrize("extra, words", [
    (["--cogging"], "--force-held with --cogging"),
    (["--dynamic"], "--force-held with --dynamic"),
])
def test_force_held_beside_a_slow_move_is_one_line_and_nothing_written(held_log, tmp_path, capsys,
                                                                      extra, words):
    path = tmp_path / "log.csv"
    rows = slice(0, 2000)
    np.savetxt(path, np.column_stack([held_log[k][rows] for k in ("t", "x", "force")]), delimiter=",",
               header="t,x,force", comments="", fmt="%.9g")
    out = tmp_path / "m.json"
    assert main(["train", str(path), "--force-held", *extra, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0] and not out.exists()


def test_force_held_on_a_sweep_is_one_line_and_nothing_written(tmp_path, capsys):
    path = tmp_path / "sweep.csv"
    v = np.array([0.05, 0.1, 0.2, 0.4, -0.05, -0.1, -0.2, -0.4])
    np.savetxt(path, np.column_stack([v, np.sign(v) * 1.0 + 0.5 * v]), delimiter=",", header="v,f",
               comments="")
    out = tmp_path / "m.json"
    assert main(["train", str(path), "--force-held", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "applies to a motion log" in err[0] and not out.exists()
    sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
    with pytest.raises(ValueError, match="force_held apply to a motion log"):
        fricgen.train(sweep, force_held=True)
