"""A sweep whose force holds a constant beside the friction (a sensor's zero, an incline, a
cable): one direction's points reach v = 0 below 0, which no curve that opposes the motion
holds (``fit.textbook_laws.pushing_offset``); the curves are fitted to the force less it and
``training.axis.offset`` carries it."""
import numpy as np
import pytest

import fricgen
from fricgen.cli import main
from fricgen.model import FrictionModel


def offset_sweep(seed, offset=-0.3, points=12, coulomb=0.2, viscous=8.0, noise=0.01):
    rng = np.random.default_rng(seed)
    speed = np.geomspace(0.01, 0.5, points)
    v = np.concatenate([speed, -speed])
    return {"v": v, "f": np.sign(v) * coulomb + viscous * v + offset + noise * rng.standard_normal(v.size)}


def textbook_rms(columns):
    """The RMS residual of per-direction Coulomb + viscous by ordinary least squares."""
    v, f = columns["v"], columns["f"]
    basis = np.column_stack([v > 0, (v > 0) * v, v < 0, (v < 0) * v]).astype(float)
    coef, *_ = np.linalg.lstsq(basis, f, rcond=None)
    return float(np.sqrt(np.mean((f - basis @ coef) ** 2)))


@pytest.mark.parametrize("seed", [1000, 1001, 1002])
def test_a_constant_force_beside_the_friction_is_carried_not_clamped(seed):
    """It was clamped: the forward F_c at 0, F_v 4 % low, 8 times the textbook fit's error."""
    columns = offset_sweep(seed)
    report = fricgen.train(columns, warn=lambda line: None)
    axis = report.training["axis"]
    assert abs(axis["offset"] + 0.3) < 3 * axis["offset_se"] + 0.005
    model = report.model
    assert model.force(np.array([1e-4, -1e-4])) == pytest.approx([0.2, -0.2], abs=0.02)
    residual = model.force_with_offset(columns["v"]) - columns["f"]
    assert np.sqrt(np.mean(residual ** 2)) <= 1.05 * textbook_rms(columns)


@pytest.mark.parametrize("offset", [0.0, 0.1])
def test_a_sweep_whose_directions_both_oppose_the_motion_keeps_no_offset(offset):
    """An offset smaller than the Coulomb level is held in the per-direction curves, as ever."""
    report = fricgen.train(offset_sweep(1003, offset=offset), warn=lambda line: None)
    assert report.training["axis"]["offset"] is None


def test_train_reports_the_offset_and_eval_adds_it(tmp_path, capsys):
    columns = offset_sweep(1004)
    np.savetxt(tmp_path / "s.csv", np.column_stack([columns["v"], columns["f"]]), delimiter=",",
               header="v,f", comments="")
    assert main(["train", str(tmp_path / "s.csv"), "-o", str(tmp_path / "m.json")]) == 0
    assert "where no friction pushes the axis" in capsys.readouterr().out
    model = FrictionModel.load(tmp_path / "m.json")
    assert model.axis_offset == pytest.approx(-0.3, abs=0.01)
    assert model.force_with_offset(0.25) == pytest.approx(0.2 + 8.0 * 0.25 - 0.3, abs=0.02)


def test_a_one_way_sweep_whose_force_pushes_at_rest_is_refused_in_one_line(tmp_path, capsys):
    """One direction cannot tell a constant force from friction: it had trained a 2-source
    curve of -0.146 N below its slowest point (pushing the axis), and emit took it."""
    columns = offset_sweep(1005)
    forward = columns["v"] > 0
    np.savetxt(tmp_path / "s.csv", np.column_stack([columns["v"][forward], columns["f"][forward]]),
               delimiter=",", header="v,f", comments="")
    assert main(["train", str(tmp_path / "s.csv"), "-o", str(tmp_path / "m.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "pushing the axis" in err[0] and "sweep both directions" in err[0]
    assert not (tmp_path / "m.json").exists()


@pytest.mark.parametrize("offset", [0.0, -0.3])
def test_a_sweep_with_a_row_at_rest_trains(offset):
    """A row at v = 0 beside the moving points: the gross outliers found on the whole sweep
    had been handed to the law choice, which scores the moving points alone (IndexError)."""
    columns = offset_sweep(1003, offset=offset, points=5)
    columns = {"v": np.append(columns["v"], 0.0), "f": np.append(columns["f"], 0.0)}
    model = fricgen.train(columns, warn=lambda line: None).model
    v = np.array([0.02, 0.2, -0.02, -0.2])
    assert model.force(v) == pytest.approx(np.sign(v) * 0.2 + 8.0 * v, abs=0.05)


@pytest.mark.parametrize("seed", [1004, 1005])
def test_a_load_beside_the_friction_is_found_from_three_speeds_each_way(seed):
    """A vertical axis's sweep of 3 speeds each way: rest levels were asked of 4 points a
    direction, and the downward curve, clamped at 0, was refused as a model in other units."""
    columns = offset_sweep(seed, offset=-0.8, points=3)
    report = fricgen.train(columns, warn=lambda line: None)
    axis = report.training["axis"]
    assert abs(axis["offset"] + 0.8) < 3 * axis["offset_se"] + 0.005
    assert report.model.force(np.array([1e-4, -1e-4])) == pytest.approx([0.2, -0.2], abs=0.03)


@pytest.mark.parametrize("points, stribeck", [(3, 1.5), (6, 0.0), (12, 1.5)])
def test_forces_written_as_magnitudes_are_refused_and_named(points, stribeck):
    """A spreadsheet's habit: the forces at v < 0 written as magnitudes. The sweep is refused,
    and the refusal asks about magnitudes (it had named only swapped columns or units)."""
    rng = np.random.default_rng(1000 + points)
    speed = np.geomspace(0.01, 1.0, points)
    level = 2.0 + stribeck * np.exp(-speed / 0.05) + 0.8 * speed
    columns = {"v": np.concatenate([speed, -speed]),
               "f": np.concatenate([level, 1.1 * level]) + 0.02 * rng.standard_normal(2 * points)}
    with pytest.raises(fricgen.FricgenError, match="are the forces at v < 0 magnitudes, where "
                                                    "friction opposes the motion and is negative"):
        fricgen.train(columns, warn=lambda line: None)


def test_a_loaded_sweep_that_trains_gets_no_magnitudes_question():
    """A vertical axis's sweep has one sign too, from its load: it trains, nothing asked."""
    columns = offset_sweep(1000, offset=0.8, coulomb=0.2, viscous=0.5)
    assert np.all(columns["f"] > 0)
    report = fricgen.train(columns, warn=lambda line: None)
    assert report.training["axis"]["offset"] == pytest.approx(0.8, abs=0.02)


@pytest.mark.parametrize("drift, warned", [(0.0, True), (0.02, False)])
def test_speeds_held_twice_far_apart_are_warned_of(drift, warned):
    """Both directions written as magnitudes, |v| too: one direction with every speed twice,
    10 and 14 N forward, 7 and 10 N back. One curve was fitted between them without a word. A
    second pass of the same direction, 2 % warmer, is no such sweep."""
    rng = np.random.default_rng(1000)
    speed = np.geomspace(0.01, 0.2, 8)
    forward = 10.0 + 4.0 * np.exp(-(speed / 0.02) ** 2) + 40.0 * speed
    second = (1 + drift) * forward if drift else 0.7 * forward
    columns = {"v": np.concatenate([speed, speed]),
               "f": np.concatenate([forward, second]) + 0.02 * rng.standard_normal(16),
               "F_std": np.full(16, 0.5), "n": np.full(16, 1500.0)}
    report = fricgen.train(columns, warn=lambda line: None)
    said = [w for w in report.warnings if "8 speeds v > 0 more than once" in w]
    assert bool(said) == warned
    if warned:
        assert "both directions written as magnitudes" in said[0]
