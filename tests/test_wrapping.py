"""A single-turn position that wraps (``data.wrapping``): the period found from the jumps, the
turns added back before anything differentiates x, and logs that only look like it left alone."""
import numpy as np
import pytest

import fricgen
from fricgen.cli import main
from fricgen.data.table import table_csv_text
from fricgen.data.wrapping import unwrapped, wrap_period

RATE = 1000.0


def joint_log(seed=1, seconds=8.0):
    """A joint turning several times each way (rad, Nm): inertia, Coulomb + viscous, noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, 1 / RATE)
    v = 6 * np.sin(2 * np.pi * 0.25 * t) + 1.0
    x = 0.3 + np.cumsum(v) / RATE
    f = 0.002 * np.gradient(v, t) + np.sign(v) * (0.3 + 0.05 * np.abs(v))
    return {"t": t, "x": x, "force": f + 0.01 * rng.standard_normal(t.size)}


@pytest.mark.parametrize("period, name, to_wrap", [
    (2 * np.pi, "2 pi", lambda x: np.mod(x, 2 * np.pi)),
    (2 * np.pi, "2 pi", lambda x: np.mod(x + np.pi, 2 * np.pi) - np.pi),
    (360.0, "360", lambda x: np.mod(np.degrees(x), 360.0) - 180.0),
    (4096.0, "2^12", lambda x: np.floor(np.mod(x / (2 * np.pi) * 4096, 4096))),
])
def test_the_period_is_found_and_the_turns_added_back(period, name, to_wrap):
    x = joint_log()["x"]
    wrapped = to_wrap(x)
    found = wrap_period(wrapped)
    assert found is not None and found[:2] == (period, name)
    lines = []
    back = unwrapped({"x": wrapped}, lines.append)["x"]
    truth = to_wrap(x) + np.round((x * period / (2 * np.pi) - to_wrap(x)) / period) * period \
        if name != "360" else None
    steps = np.abs(np.diff(back))
    assert steps.max() < 0.02 * period                  # no jump is left
    assert len(lines) == 1 and f"period of {name} ({found[2]} times)" in lines[0]
    if truth is not None:
        assert np.allclose(back - back[0], truth - truth[0], atol=1.0)


def test_a_turn_sampled_four_times_is_unwrapped_and_degrees_are_asked_about():
    x = np.cumsum(np.full(400, 90.0))                  # 90 degrees a sample
    lines = []
    back = unwrapped({"x": np.mod(x, 360.0)}, lines.append)["x"]
    assert np.allclose(back - back[0], x - x[0])
    assert len(lines) == 1 and "x in degrees? fricgen reads rad: --scale x=0.0174533" in lines[0]


def test_a_position_flickering_across_the_wrap_at_rest_is_unwrapped_to_rest():
    x = np.where(np.arange(2000) % 3 == 0, 2 * np.pi - 1e-4, 1e-4)
    back = unwrapped({"x": x}, lambda line: None)["x"]
    assert np.ptp(back) < 1e-3


@pytest.mark.parametrize("seed", [1000, 1001, 1002])
def test_a_noisy_position_resting_on_the_wrap_is_unwrapped(seed):
    """At rest on +-pi, the angle's noise carries it back and forth across the wrap: the sign of
    the motion over each jump is the noise's, yet every jump is a turn (it had been stitched
    as resets: -1197 to 925 rad/s and a model of nothing, written)."""
    rng = np.random.default_rng(seed)
    moving = np.pi + np.concatenate([np.linspace(-3.0, 0.0, 1500), np.zeros(3000),
                                     np.linspace(0.0, 3.0, 1500)])
    x = moving + 2e-5 * rng.standard_normal(moving.size)
    wrapped = np.mod(x + np.pi, 2 * np.pi) - np.pi
    found = wrap_period(wrapped)
    assert found is not None and found[:2] == (2 * np.pi, "2 pi") and found[2] > 2
    back = unwrapped({"x": wrapped}, lambda line: None)["x"]
    assert np.allclose(back - back[0], x - x[0], atol=1e-9)


@pytest.mark.parametrize("x", [
    np.cumsum(np.full(2000, 1e-3)),                                      # no wrap
    np.concatenate([np.linspace(0, 3, 500), np.linspace(0.5, 2, 500),    # runs whose position
                    np.linspace(2.9, 0, 500)]),                          # resets, by unequal jumps
    np.random.default_rng(0).standard_normal(2000),                      # noise about a rest
    np.concatenate([np.linspace(0, 5, 1000), np.linspace(0, 0.02, 1000)]),   # a reset, then a crawl
])
def test_a_position_that_does_not_wrap_is_left_alone(x):
    lines = []
    assert wrap_period(x) is None
    assert unwrapped({"x": x}, lines.append)["x"] is x and lines == []


def test_a_wrapped_log_trains_the_model_of_the_unwrapped_one(tmp_path, capsys):
    log = joint_log()
    wrapped = {**log, "x": np.mod(log["x"], 2 * np.pi)}
    lines = []
    straight = fricgen.train(log, rotary=True, warn=lines.append)
    assert lines == []
    turned = fricgen.train(wrapped, rotary=True, warn=lines.append)
    assert any("wraps at a period of 2 pi" in line for line in lines)
    assert turned.identification.body.mass == pytest.approx(straight.identification.body.mass, rel=1e-9)
    v = np.linspace(-5, 5, 11)
    assert np.allclose(turned.model.force(v), straight.model.force(v), rtol=1e-9)
    # the command line unwraps before its checks: a 10 kHz log's jump would read as 6e4 rad/s
    path = tmp_path / "joint.csv"
    path.write_text(table_csv_text({"t": wrapped["t"], "q": wrapped["x"], "tau": wrapped["force"]}))
    assert main(["train", str(path), "-o", str(tmp_path / "m.json")]) == 0
    assert "x wraps at a period of 2 pi" in capsys.readouterr().err
    mass = fricgen.FrictionModel.load(tmp_path / "m.json").training["axis"]["mass"]
    assert mass == pytest.approx(straight.identification.body.mass, rel=1e-6)


def _zeroed(x, at):
    """x set to 0 at row ``at`` and counting on from there."""
    out = x.copy()
    out[at:] -= x[at]
    return out


@pytest.mark.slow
@pytest.mark.parametrize("reset", [
    lambda x: _zeroed(x, int(np.argmax(x))),                   # zeroed where it is farthest out
    lambda x: x - 0.5 * (np.arange(x.size) >= 5000),           # homed by 0.5 rad, 4 % of the range
    lambda x: _zeroed(_zeroed(x, 1500), 6000),                 # zeroed twice
])
def test_a_reset_of_the_position_while_the_time_runs_is_stitched(reset):
    log = joint_log()
    reset = reset(log["x"])
    lines = []
    straight = fricgen.train(log, rotary=True, warn=lambda line: None)
    stitched = fricgen.train({**log, "x": reset}, rotary=True, warn=lines.append)
    assert any("taken for a reset of the position and stitched" in line for line in lines)
    assert stitched.identification.body.mass == pytest.approx(straight.identification.body.mass, rel=1e-3)
    v = np.linspace(-5, 5, 11)
    assert np.allclose(stitched.model.force(v), straight.model.force(v), rtol=1e-3, atol=1e-4)


def test_runs_joined_end_to_end_keep_their_positions():
    t = np.concatenate([np.arange(0, 1, 1e-3)] * 2)            # the time restarts with each run
    x = np.concatenate([np.linspace(0, 5, 1000), np.linspace(0, 5, 1000)])
    lines = []
    assert unwrapped({"t": t, "x": x}, lines.append)["x"] is x and lines == []


def test_a_counts_step_out_of_rest_is_motion_not_a_reset():
    t = np.arange(0, 2, 1e-3)
    counts = np.floor(np.where(t < 1, 0.0, (t - 1) * 3.0))     # at rest, then creeping 3 counts/s
    x = counts * 1e-4                                            # a 0.1 mm count; range 3 counts
    lines = []
    assert unwrapped({"t": t, "x": x}, lines.append)["x"] is x and lines == []
