"""A second calibration with the first map fed forward (``identify_cogging(fed_forward=...)``,
``fricgen train --cogging --fed-forward MODEL``): the drive's current holds the whole cogging
again while the velocity barely ripples; the feedforward, read at the encoder's counts, adds
lines of its own (the count's aliases less the map's harmonics), which the second map must not
take for cogging."""
from dataclasses import replace

import numpy as np
import pytest

from fricgen.cli import main
from fricgen.errors import DataError
from fricgen.fit.cogging import identify_cogging
from fricgen.model import FrictionModel
from fricgen.sim.servo_axis import TWO_PI, calibration_move, map_feedforward, random_axis


@pytest.fixture(scope="module")
def axis():
    """A 14-bit axis whose second calibration shows a feedforward line (harmonic 970)."""
    return random_axis(2, bits=14)


@pytest.fixture(scope="module")
def passes(axis):
    """The first calibration's log (one turn each way at 1 rad/s), its fit, and the second's
    log, that map fed forward."""
    first = calibration_move(axis, turns=1.0, speed=1.0, every=1)
    fit = identify_cogging(first["t"], first["x"], axis.kt * first["i"], TWO_PI)
    second = calibration_move(axis, turns=1.0, speed=1.0, every=1,
                              feedforward=map_feedforward(axis, fit.map))
    return first, fit, second


def test_the_second_map_keeps_the_first_maps_harmonics(axis, passes):
    _, first, log = passes
    force = axis.kt * log["i"]
    anew = identify_cogging(log["t"], log["x"], force, TWO_PI)
    again = identify_cogging(log["t"], log["x"], force, fed_forward=first.map,
                             fed_forward_friction=first.friction)
    assert set(again.map.harmonics) <= set(first.map.harmonics)
    assert set(again.friction.harmonics) <= set(first.friction.harmonics)
    assert again.period == TWO_PI and again.inertia_source == "undetermined"
    assert axis.map_error(again.map) < axis.map_error(first.map) / 2
    # the feedforward's lines at the encoder's alias -+ the map's harmonics (970 of the turn) are
    # no cogging of the second map fitted anew either (``encoder_alias``)
    assert 970 not in anew.map.harmonics and axis.map_error(anew.map) < axis.map_error(first.map) / 2


def test_a_period_other_than_the_fed_forward_maps_is_refused(axis, passes):
    _, first, log = passes
    with pytest.raises(DataError, match="not the fed-forward map's"):
        identify_cogging(log["t"], log["x"], axis.kt * log["i"], TWO_PI / 2, fed_forward=first.map)


@pytest.fixture(scope="module")
def first_model(axis, passes, tmp_path_factory):
    """The first calibration trained by the CLI (first.json), the second's log as a CSV, and
    what the refusals below are given: first.json without its map (plain.json) and as a linear
    axis's (linear.json), and the second log's current less the feedforward (feedback.csv)."""
    folder = tmp_path_factory.mktemp("second_pass")
    first, fit, second = passes
    feedforward = map_feedforward(axis, fit.map)
    feedback = second["i"] - np.array([feedforward(x) for x in second["x"]])
    for name, log, current in (("first.csv", first, first["i"]), ("second.csv", second, second["i"]),
                               ("feedback.csv", second, feedback)):
        np.savetxt(folder / name, np.column_stack([log["t"], log["x"], current]), delimiter=",",
                   header="t,x,i", comments="", fmt="%.10g")
    assert main(["train", str(folder / "first.csv"), "--cogging", "--rotary", "--force-constant",
                 str(axis.kt), "-o", str(folder / "first.json")]) == 0
    model = FrictionModel.load(folder / "first.json")
    replace(model, cogging_map=None, cogging_friction=None).save(folder / "plain.json")
    replace(model, training={**model.training, "units": "linear", "accept_unusual": True}).save(
        folder / "linear.json")
    return folder


def test_train_fed_forward_keeps_the_models_harmonics(axis, first_model, capsys):
    folder = first_model
    assert main(["train", str(folder / "second.csv"), "--cogging", "--rotary", "--force-constant",
                 str(axis.kt), "--fed-forward", str(folder / "first.json"),
                 "-o", str(folder / "second.json")]) == 0
    first, second = (FrictionModel.load(folder / f) for f in ("first.json", "second.json"))
    assert set(second.cogging_map.harmonics) <= set(first.cogging_map.harmonics)
    assert axis.map_error(second.cogging_map) < axis.map_error(first.cogging_map)
    assert "the first map fed forward" in capsys.readouterr().out


def test_a_pitch_typed_to_seven_digits_is_the_fed_forward_maps(axis, first_model, tmp_path):
    folder = first_model
    assert main(["train", str(folder / "second.csv"), "--cogging", "--rotary", "--force-constant",
                 str(axis.kt), "--fed-forward", str(folder / "first.json"), "--pitch", "6.283185",
                 "-o", str(tmp_path / "m.json")]) == 0
    assert FrictionModel.load(tmp_path / "m.json").cogging_map.period == TWO_PI


@pytest.mark.parametrize("argv, message", [
    (["--fed-forward", "first.json"], "--fed-forward is for --cogging's map; give --cogging too"),
    (["--cogging", "--fed-forward", "plain.json"], "the model has no cogging map to have fed forward"),
    (["--cogging", "--fed-forward", "linear.json"], "a linear axis's map (period 6.28319 m); this log is a rotary axis's"),
    (["--cogging", "--fed-forward", "absent.json"], "absent.json"),
    (["--cogging", "--fed-forward", "first.json", "--pitch", "1.0"], "not the fed-forward map's"),
    (["--cogging", "--fed-forward", "first.json", "-o", "first.json"], "first.json"),
    (["--cogging", "--fed-forward", "first.json", "--log", "feedback.csv"], "logged without the feedforward?"),
])
def test_fed_forward_refuses_what_it_cannot_use(axis, first_model, tmp_path, capsys, argv, message):
    """... and a second calibration whose current is the loop's feedback alone (the drive's
    feedforward left out of the log), which has no cogging left to map."""
    folder, argv = first_model, list(argv)
    out = folder / argv.pop(argv.index("-o") + 1) if "-o" in argv else tmp_path / "m.json"
    log_file = folder / argv.pop(argv.index("--log") + 1) if "--log" in argv else folder / "second.csv"
    argv = [str(folder / a) if a.endswith(".json") else a for a in argv if a not in ("-o", "--log")]
    before = out.read_bytes() if out.exists() else None
    assert main(["train", str(log_file), "--rotary", "--force-constant", str(axis.kt),
                 "-o", str(out), *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert (out.read_bytes() == before) if before is not None else not out.exists()
