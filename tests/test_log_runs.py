"""A log joined from runs (t restarts, or pauses, between them): no smoothing window spans two
runs, and where every run moves both ways each run's constant force (a sensor zeroed again,
another pose) is identified beside the mass and taken out of the friction; where a run moves one
way only, one line says why the runs share one constant force."""
import numpy as np
import pytest

import fricgen
from fricgen.cli import main
from fricgen.data.motionlog import run_starts

MASS = 2.5                        # kg
OFFSETS = (0.0, 0.9, -0.6)        # N: each run's constant force
TS = 0.002                        # s


def friction(v):
    """An asymmetric friction with a Stribeck drop of power 1.5 (no law of fricgen's), N."""
    s = np.abs(v)
    return np.where(v > 0, 1.5 + 0.8 * np.exp(-(s / 0.04) ** 1.5) + 9.0 * s,
                    -1.3 - 0.7 * np.exp(-(s / 0.04) ** 1.5) + 9.5 * v)


def run(rng, offset, both_ways=True, seconds=10.0, speed=1.0):
    """One run from rest: t from 0, v (noisy) and force (noisy) of the axis; ``both_ways``:
    swinging through reversals, else moving forward at a varying speed; ``speed`` scales v."""
    t = np.arange(0.0, seconds, TS)
    ramp = np.minimum(t / 0.5, 1.0)
    if both_ways:
        v = ramp * (0.25 * np.sin(2 * np.pi * rng.uniform(0.25, 0.4) * t)
                    + 0.06 * np.sin(2 * np.pi * 1.3 * t + rng.uniform(0, 6)))
    else:
        v = ramp * (0.15 + 0.1 * np.sin(2 * np.pi * rng.uniform(0.25, 0.4) * t))
    v = speed * v
    force = MASS * np.gradient(v, TS) + friction(v) + offset
    return {"t": t, "v": v + rng.normal(0.0, 1e-3, t.size),
            "force": force + rng.normal(0.0, 0.1, t.size)}


def joined(runs):
    return {name: np.concatenate([r[name] for r in runs]) for name in runs[0]}


def friction_error(report):
    """RMS (N) of the model plus its offset against the true friction over 0.02-0.3 m/s."""
    v = np.concatenate([-np.geomspace(0.02, 0.3, 30), np.geomspace(0.02, 0.3, 30)])
    offset = report.training["axis"]["offset"] or 0.0
    return float(np.sqrt(np.mean((report.model.force(v) + offset - friction(v)) ** 2)))


QUIET = dict(warn=lambda line: None)


def test_restarts_and_pauses_start_runs_swapped_rows_do_not():
    t = np.arange(100) * 0.01
    assert list(run_starts(np.concatenate([t, t, t + 50.0]), 30)) == [100, 200]
    swapped = t.copy()
    swapped[[40, 41]] = swapped[[41, 40]]
    assert run_starts(swapped, 30).size == 0           # back, but not to a run's first half
    assert list(run_starts(np.concatenate([t, t[3:] - 0.03]), 30)) == [100]   # back to t = 0
    assert run_starts(t, 30).size == 0
    with pytest.raises(fricgen.DataError, match=r"run 2 of 2 \(data rows 101 to 110, where t "
                       r"restarts or pauses\) has 10 rows, need at least 30"):
        run_starts(np.concatenate([t, t[:10]]), 30)


def test_each_runs_constant_force_is_identified_and_taken_out():
    rng = np.random.default_rng(11)
    runs = [run(rng, o) for o in OFFSETS]
    report = fricgen.train(joined(runs), **QUIET)
    body = report.identification.body
    truth = np.subtract(OFFSETS[1:], OFFSETS[0])
    runs_, found, se = (np.array(c) for c in zip(*body.run_offsets))
    assert body.run_reference == 0 and list(runs_) == [1, 2]
    assert np.all(np.abs(found - truth) < 5 * se) and found == pytest.approx(truth, abs=0.03)
    assert body.mass == pytest.approx(MASS, rel=0.03)
    assert report.identification.n_runs == 3
    assert "in 3 runs" in str(report) and "each run less run 1's: run 2 +0.8" in str(report)
    # the same rows on one clock: one run whose offset jumps, which no constant explains
    continuous = {**joined(runs), "t": np.arange(sum(r["t"].size for r in runs)) * TS}
    one_clock = fricgen.train(continuous, **QUIET)
    assert one_clock.identification.body.run_offsets is None
    assert friction_error(report) < 0.06 and 3 * friction_error(report) < friction_error(one_clock)


@pytest.mark.parametrize("seed", [1000, 1001])
def test_runs_that_share_few_speeds_are_doubted_in_one_line(seed):
    """A run of slow swings beside one of fast swings: their constant forces are told apart
    only by the friction curve's shape between their speeds (one more Stribeck term per
    direction moved a new user's by 20 times the offset), which one warning says; runs of
    the same swings (above) share their speeds, and no warning comes."""
    rng = np.random.default_rng(seed)
    lines = []
    report = fricgen.train(joined([run(rng, 0.0, speed=0.2), run(rng, 0.9, speed=3.0)]),
                           warn=lines.append)
    said = [line for line in lines if "the runs' constant forces are told apart only" in line]
    assert report.identification.body.run_offsets is not None and len(said) == 1
    assert "run 2 has" in said[0] or "run 1 has" in said[0]
    lines.clear()
    fricgen.train(joined([run(rng, 0.0), run(rng, 0.9)]), warn=lines.append)
    assert not any("constant forces are told apart" in line for line in lines)


def test_runs_that_move_one_way_share_one_constant_force():
    rng = np.random.default_rng(12)
    report = fricgen.train(joined([run(rng, 0.0, both_ways=False) for _ in range(3)]), **QUIET)
    assert report.identification.body.run_offsets is None
    assert "one constant force for all runs: fewer than two runs move both ways" in str(report)


def test_a_run_one_way_or_short_leaves_the_others_their_offsets():
    """Two swinging runs, one that moves one way, and a short one: the swinging runs keep their
    offsets (the others are taken as the first's), and the short run does not shrink the
    windows of the rest (the mass stays right)."""
    rng = np.random.default_rng(14)
    runs = [run(rng, 0.0), run(rng, 0.0, both_ways=False), run(rng, 0.7),
            run(rng, 0.0, seconds=0.1)]
    report = fricgen.train(joined(runs), **QUIET)
    body = report.identification.body
    assert [r for r, _, _ in body.run_offsets] == [2] and body.run_reference == 0
    assert body.run_offsets[0][1] == pytest.approx(0.7, abs=0.03)
    assert body.mass == pytest.approx(MASS, rel=0.03) and report.identification.window > 7
    assert "runs 2, 4 (one way only, or left out) taken as run 1's" in str(report)


def _write(path, columns):
    np.savetxt(path, np.column_stack([columns[k] for k in ("t", "v", "force")]), delimiter=",",
               header="t,v,force", comments="")
    return str(path)


def test_the_command_line_trains_a_file_of_runs_and_refuses_runs_of_two_rates(tmp_path, capsys):
    rng = np.random.default_rng(13)
    runs = [run(rng, o, seconds=6.0) for o in OFFSETS]
    out = tmp_path / "model.json"
    assert main(["train", _write(tmp_path / "runs.csv", joined(runs)), "-o", str(out)]) == 0
    assert "in 3 runs" in capsys.readouterr().out and out.exists()
    runs[1]["t"] = runs[1]["t"] * 2.0                      # the second run logged at half the rate
    bad = tmp_path / "bad.json"
    assert main(["train", _write(tmp_path / "rates.csv", joined(runs)), "-o", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "runs are sampled at different rates: run 2 every 0.004 s" in err[0]
    assert not bad.exists()
