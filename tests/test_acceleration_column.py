"""A log's own acceleration column (a, ddq): the inertia is identified against it, so that a force
from which a rigid-body model was removed with that acceleration leaves its residual inertia
against the same signal; a column that is no dv/dt of the log is refused in one line, and one
that explains the force clearly less well than dv/dt of v (a lagging estimate) is not used."""
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
    with pytest.raises(DataError, match=r"acceleration column \(a\) is not its dv/dt: it follows "
                                        r"dv/dt with slope 5[0-9]\..*deg/s\^2\? --scale a=0\.0174533"):
        fricgen.train({**columns, "ddq": np.degrees(columns["ddq"])}, warn=lambda line: None)


@pytest.mark.parametrize("edit", [lambda c: c["dq"], lambda c: c["tau"], lambda c: 1.4 * c["ddq"],
                                  lambda c: 0.7 * c["ddq"]], ids=["dq", "tau", "1.4 a", "0.7 a"])
def test_another_quantity_as_the_acceleration_is_refused(edit):
    columns, _ = _joint_log(1003)
    with pytest.raises(DataError, match=r"acceleration column \(a\) is not its dv/dt"):
        fricgen.train({**columns, "ddq": edit(columns)}, warn=lambda line: None)


def _raw_log(seed, column):
    """A joint's raw log, its torque INERTIA dv/dt plus friction and noise, on a faster move
    (0.5-2.5 Hz), with ``column(t, dv/dt, rng)`` as its acceleration column."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 10.0, 1.0 / RATE)
    w = 2 * np.pi * np.array([0.5, 1.3, 2.5])
    amp, phase = rng.uniform(0.2, 0.4, 3), rng.uniform(0, 2 * np.pi, 3)
    v = (amp[:, None] * np.sin(w[:, None] * t + phase[:, None])).sum(axis=0)
    dv_dt = (amp[:, None] * w[:, None] * np.cos(w[:, None] * t + phase[:, None])).sum(axis=0)
    tau = INERTIA * dv_dt + np.sign(v) * 0.3 + 0.2 * v + 0.01 * rng.standard_normal(t.size)
    return {"t": t, "dq": v + 0.001 * rng.standard_normal(t.size), "ddq": column(t, dv_dt, rng),
            "tau": tau}


def _lagging(t, dv_dt, rng, tau=0.02):
    """dv/dt through a causal first-order filter of time constant ``tau`` (a drive's estimate)."""
    k = (t[1] - t[0]) / (tau + t[1] - t[0])
    out = np.empty_like(dv_dt)
    out[0] = dv_dt[0]
    for n in range(1, dv_dt.size):
        out[n] = out[n - 1] + k * (dv_dt[n] - out[n - 1])
    return out


def _double_differenced(t, dv_dt, rng, step=2 * np.pi / 2 ** 16):
    """The second difference of the position in counts of ``step`` rad (a 16-bit encoder)."""
    x = np.cumsum(np.cumsum(dv_dt) * (t[1] - t[0])) * (t[1] - t[0])
    return np.gradient(np.gradient(np.round(x / step) * step, t), t)


def test_a_lagging_acceleration_column_is_not_used():
    """A causal 20 ms filter: it had been used, the inertia 4 % high and F_v 21 % low."""
    warned = []
    report = fricgen.train(_raw_log(1005, _lagging), warn=warned.append)
    body = report.identification.body
    assert abs(body.mass - INERTIA) < max(3 * body.mass_se, 0.01 * INERTIA)
    assert not report.identification.acceleration_given
    assert any("acceleration column leaves" in line and "not used" in line for line in warned)
    assert report.model.force(np.array([0.5])) == pytest.approx(0.3 + 0.2 * 0.5, abs=0.01)


def test_a_double_differenced_acceleration_column_leaves_the_inertia_unbiased():
    """The counts' noise of a second difference: at 7 samples it pulled the inertia 26 % low
    (errors in the variables); the column is smoothed at the window that explains the force
    best."""
    report = fricgen.train(_raw_log(1006, _double_differenced), warn=lambda line: None)
    body = report.identification.body
    assert abs(body.mass - INERTIA) < max(3 * body.mass_se, 0.01 * INERTIA)


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
