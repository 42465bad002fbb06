"""A log of normal operation less the position force it holds (``less_position_force``, what a
fleet's worker trains): the cogging found in what the friction model leaves, with the position
integrated from the velocity of a log that has none, is taken out before the friction is fitted,
so that a cogging that changes between two logs of an axis leaves its friction parameters where
they were; a log without cogging is trained as before."""
import math

import numpy as np
import pytest

from independent_axis import fleet_axis, fleet_log, write_fleet_log

from fricgen.cli.train import train_argv
from fricgen.fleet.identification import TRAIN_FIT, friction_parameters
from fricgen.training.with_cogging import log_position

COGGING, PITCH = 0.6, 0.03     # N, m: the fundamental's amplitude, a quarter of it at the second


def trained(tmp_path, axis, seed, name):
    path = tmp_path / f"{name}.csv"
    write_fleet_log(path, fleet_log(axis, seed))
    return train_argv([str(path), *TRAIN_FIT, "-o", "unused.json"])


@pytest.fixture(scope="module")
def axis():
    return dict(fleet_axis(11), cogging=COGGING, pitch=PITCH)


@pytest.fixture(scope="module")
def pair(axis, tmp_path_factory):
    """Two logs of the axis whose cogging alone differs (2.5 times the amplitude, a new phase)."""
    folder = tmp_path_factory.mktemp("position_force")
    grown = dict(axis, cogging=2.5 * COGGING, phase=1.0)
    return trained(folder, axis, 1, "before"), trained(folder, grown, 2, "after")


def test_a_change_of_the_cogging_alone_leaves_the_friction_parameters(pair):
    before, after = (friction_parameters(r) for r in pair)
    for name in ("coulomb_pos", "coulomb_neg", "static_pos", "static_neg"):
        combined = math.hypot(before[name + "_se"], after[name + "_se"])
        assert abs(after[name] - before[name]) < 3 * combined, name


def test_the_map_taken_out_is_the_axis_cogging(pair):
    for report, amplitude in zip(pair, (COGGING, 2.5 * COGGING)):
        m = report.model.cogging_map
        assert m is not None and abs(m.period / PITCH - 1) < 0.01
        assert abs(m.rms / (amplitude * math.sqrt((1 + 0.25 ** 2) / 2)) - 1) < 0.1


def test_a_current_log_with_its_force_constant_gets_the_same_map(axis, pair, tmp_path):
    log = fleet_log(axis, 1)
    path = tmp_path / "current.csv"
    np.savetxt(path, np.column_stack([log["t"], log["v"], log["force"] / 20.0]), delimiter=",",
               header="t,v,i", comments="", fmt="%.9g")
    report = train_argv([str(path), *TRAIN_FIT, "--force-constant", "20", "-o", "unused.json"])
    assert report.model.cogging_map is not None
    assert report.model.cogging_map.rms == pytest.approx(pair[0].model.cogging_map.rms, rel=1e-3)


def test_a_log_without_cogging_is_trained_as_before(tmp_path):
    report = trained(tmp_path, fleet_axis(11), 1, "plain")
    assert report.model.cogging_map is None


def test_the_position_of_a_log_without_one_is_its_velocity_integrated():
    t = np.linspace(0.0, 2.0, 2001)
    v = np.cos(t)
    assert np.max(np.abs(log_position({"t": t, "v": v}) - np.sin(t))) < 1e-6
    assert log_position({"t": t, "v": v, "x": np.sin(t) + 5})[0] == 5
