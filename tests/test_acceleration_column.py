"""A log's own acceleration column (a, ddq): the inertia is identified against it, so that a force
from which a rigid-body model was removed with that acceleration leaves its residual inertia
against the same signal; a column that is no dv/dt of the log is refused in one line."""
import numpy as np
import pytest

import fricgen
from fricgen.cli import main
from fricgen.errors import DataError

RATE, SECONDS = 1000.0, 12.0
INERTIA = 0.05             # kg m^2: what the force holds times the log's own acceleration


def _joint_log(seed):
    """A joint's log whose torque holds INERTIA times its logged acceleration, which is dv/dt
    plus the error of the estimator that made it (band-limited, 30 % of dv/dt's RMS), beside a
    friction of its own law (Coulomb + viscous + a Stribeck drop) and sensor noise: (columns
    with ddq, the torque's friction law)."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, SECONDS, 1.0 / RATE)
    w = 2 * np.pi * np.array([0.13, 0.31, 0.57])
    amp, phase = rng.uniform(0.4, 0.8, 3), rng.uniform(0, 2 * np.pi, 3)
    v = (amp[:, None] * np.sin(w[:, None] * t + phase[:, None])).sum(axis=0)
    dv_dt = (amp[:, None] * w[:, None] * np.cos(w[:, None] * t + phase[:, None])).sum(axis=0)
    error = np.convolve(rng.standard_normal(t.size), np.hanning(151), mode="same")
    logged = dv_dt + 0.3 * error * np.std(dv_dt) / np.std(error)

    def law(v):
        return np.sign(v) * (0.25 + 0.12 * np.exp(-(np.abs(v) / 0.08) ** 2)) + 0.2 * v

    tau = INERTIA * logged + law(v) + 0.01 * rng.standard_normal(t.size)
    v_logged = v + 0.002 * rng.standard_normal(t.size)
    return {"t": t, "dq": v_logged, "ddq": logged, "tau": tau}, law


@pytest.mark.parametrize("seed", [1000, 1001])
def test_the_inertia_is_identified_against_the_logs_acceleration(seed):
    columns, law = _joint_log(seed)
    quiet = {"warn": lambda line: None}
    given = fricgen.train(columns, **quiet)
    body = given.identification.body
    assert given.training["units"] == "rotary"             # ddq names a joint
    assert abs(body.mass - INERTIA) < 3 * body.mass_se and abs(body.mass - INERTIA) < 0.05 * INERTIA
    assert "against the log's acceleration column" in str(given)
    own = fricgen.train({k: c for k, c in columns.items() if k != "ddq"}, **quiet)
    assert abs(own.identification.body.mass - INERTIA) > 3 * abs(body.mass - INERTIA)
    v = np.linspace(0.1, 1.2, 30)
    for report in (given, own):                       # the friction is the law's either way
        assert np.max(np.abs(report.model.force(v) - law(v))) < 0.05


def test_the_acceleration_in_other_units_is_refused():
    columns, _ = _joint_log(1002)
    with pytest.raises(DataError, match=r"column a is not the log's acceleration: dv/dt follows "
                                        r"it with slope 0\.01[5-8].*deg/s\^2\? --scale a=0\.0174533"):
        fricgen.train({**columns, "ddq": np.degrees(columns["ddq"])}, warn=lambda line: None)


@pytest.mark.parametrize("column", ["dq", "tau"])
def test_another_quantity_as_the_acceleration_is_refused(column):
    columns, _ = _joint_log(1003)
    with pytest.raises(DataError, match="column a is not the log's acceleration"):
        fricgen.train({**columns, "ddq": columns[column]}, warn=lambda line: None)


def test_a_header_unit_of_acceleration_is_read(tmp_path, capsys):
    columns, _ = _joint_log(1004)
    path = tmp_path / "joint.csv"
    data = np.column_stack([columns["t"], columns["dq"], np.degrees(columns["ddq"]), columns["tau"]])
    np.savetxt(path, data, delimiter=",", header="t,dq,acc [deg/s^2],tau", comments="")
    out = tmp_path / "model.json"
    assert main(["train", str(path), "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    line = next(line for line in printed.splitlines() if line.startswith("inertia"))
    mass = float(line.split()[1])
    assert abs(mass - INERTIA) < 0.05 * INERTIA and "acceleration column" in line
