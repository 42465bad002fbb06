"""Units written in a header's names (``data.header_units``): "Speed [rpm]" read as v in rpm and
scaled to SI, the user's --scale first, and a unit that cannot be the column's refused."""
import numpy as np
import pytest

from fricgen.cli import main
from fricgen.data.header_units import UNITS, _key, header_units, is_rotary_unit, named_unit
from fricgen.data.export import KNOWN_NAMES
from fricgen.data.table import header_cells, read_table_csv
from fricgen.errors import DataError
from fricgen.model import FrictionModel

COULOMB, VISCOUS = 0.3, 0.05                 # Nm, Nm s/rad


@pytest.mark.parametrize("cell, name, unit, factor", [
    ("Speed [rpm]", "Speed", "rpm", np.pi / 30),
    ("Torque (N·m)", "Torque", "N·m", 1.0),
    ("Torque [N.m]", "Torque", "N.m", 1.0),
    ("Pos [°]", "Pos", "°", np.pi / 180),
    ("Iq [mA]", "Iq", "mA", 1e-3),
    ("n [U/min]", "n", "U/min", np.pi / 30),
    ("Time (µs)", "Time", "µs", 1e-6),
    ("n [min-1]", "n", "min-1", np.pi / 30),
    ("M [oz-in]", "M", "oz-in", 7.0615518e-3),
    ("Speed [krpm]", "Speed", "krpm", 1000 * np.pi / 30),
])
def test_a_cells_unit_is_read_with_its_factor(cell, name, unit, factor):
    assert named_unit(cell) == (name, unit)
    assert UNITS[_key(unit)][1] == pytest.approx(factor)


def test_rotary_units_name_a_rotary_axis():
    assert is_rotary_unit("Speed [rpm]") and is_rotary_unit("Torque (mNm)") and is_rotary_unit("q [deg]")
    assert not is_rotary_unit("v [m/s]") and not is_rotary_unit("F [N]") and not is_rotary_unit("speed")


def test_only_known_names_and_mapped_cells_are_read_and_a_plain_name_wins():
    cells = ["v", "Speed [rpm]", "Torque [mNm]", "Voltage [V]"]
    mapped, units = header_units(cells, {}, KNOWN_NAMES)
    assert mapped == {"force": "Torque [mNm]"}           # 'v' is there as written: 'Speed' is not v
    assert set(units) == {"force"} and units["force"].factor == pytest.approx(1e-3)
    with pytest.raises(DataError, match="'Voltage \\[V\\]' \\(i\\) is in V, a unit fricgen does not know"):
        header_units(cells, {"i": "Voltage [V]"}, KNOWN_NAMES)
    mapped, units = header_units(cells, {"i": "Voltage [V]"}, KNOWN_NAMES, ["i"])   # --scale i=...
    assert mapped == {"force": "Torque [mNm]"} and "i" not in units


@pytest.mark.parametrize("cells, mapped, words", [
    (["Speed [Nm]", "Torque [rpm]"], {}, "column 'Speed [Nm]' is read as v, a velocity, but its unit Nm"),
    (["t [s]", "q [rad]", "Iq [%]"], {}, "column 'Iq [%]' (i) is in %, a unit of no size"),
    (["t [s]", "Pos [inc]", "I [A]"], {"x": "Pos [inc]"}, "column 'Pos [inc]' (x) is in inc"),
])
def test_a_unit_that_cannot_be_the_columns_is_refused(cells, mapped, words):
    with pytest.raises(DataError) as err:
        header_units(cells, mapped, KNOWN_NAMES)
    assert words in str(err.value)


def test_units_of_a_linear_and_a_rotary_axis_are_refused_unless_one_is_scaled():
    cells = ["Speed [mm/s]", "Torque [Nm]"]
    with pytest.raises(DataError, match="mix a linear axis's \\('Speed \\[mm/s\\]'\\) and a rotary"):
        header_units(cells, {}, KNOWN_NAMES)
    _, units = header_units(cells, {}, KNOWN_NAMES, ["force"])        # --scale force=2pi/lead
    assert units["v"].factor == pytest.approx(1e-3)


def test_a_sizeless_unit_is_read_by_the_users_scale():
    mapped, units = header_units(["t [s]", "Encoder [counts]", "Iq [A]"], {"x": "Encoder [counts]"},
                                 KNOWN_NAMES, ["x"])
    assert mapped == {"i": "Iq [A]", "t": "t [s]"} and set(units) == {"i", "t"}


@pytest.fixture
def export(tmp_path):
    """A drive's sweep export in rpm and mNm, 8 speeds a side."""
    rng = np.random.default_rng(1000)
    speed = np.geomspace(0.05, 3.0, 8)
    v = np.concatenate([speed, -speed])
    f = np.sign(v) * (COULOMB + VISCOUS * np.abs(v)) + 0.003 * rng.standard_normal(v.size)
    path = tmp_path / "export.csv"
    rows = "\n".join(f"{a * 30 / np.pi:.6f},{b * 1000:.5f}" for a, b in zip(v, f))
    path.write_text("Speed [rpm],Torque [mNm]\n" + rows + "\n")
    return path


def _trained(path, capsys, *options):
    """The model trained on ``path`` and what train said on stderr."""
    out = path.parent / "model.json"
    assert main(["train", str(path), "-o", str(out), *options]) == 0
    return FrictionModel.load(out), capsys.readouterr().err


def test_a_sweep_in_rpm_and_mnm_trains_in_si(export, capsys):
    model, err = _trained(export, capsys)
    assert "v read in rpm ('Speed [rpm]'): scaled by 0.10472 to SI" in err
    assert "read in mNm ('Torque [mNm]'): scaled by 0.001 to SI" in err
    assert model.training["units"] == "rotary"
    v = np.array([-2.0, -0.5, 0.5, 2.0])
    assert np.allclose(model.force(v), np.sign(v) * (COULOMB + VISCOUS * np.abs(v)), atol=0.01)


def test_the_users_scale_wins_and_a_different_one_is_named(export, capsys):
    model, err = _trained(export, capsys, "--scale", "v=0.10472")
    assert "v read in" not in err and "is not the factor" not in err
    assert model.force([1.0])[0] == pytest.approx(COULOMB + VISCOUS, abs=0.01)
    model, err = _trained(export, capsys, "--scale", "v=0.0174533", "--accept-unusual")
    assert "--scale v=0.0174533 is not the factor of the header's rpm (0.10472" in err


def _units_row_export(export, units_row, sep=","):
    """``export`` rewritten with plain names and its units on a row of their own."""
    lines = export.read_text().splitlines()
    rows = [line.replace(",", sep) for line in lines[1:]]
    export.write_text("\n".join([f"Speed{sep}Torque", units_row] + rows) + "\n")
    return export


@pytest.mark.parametrize("units_row, sep", [("rpm,mNm", ","), ("[rpm];[mNm]", ";"), ("(rpm)\t(mNm)", "\t")])
def test_a_units_row_under_the_header_is_read_as_the_names_units(export, capsys, units_row, sep):
    model, err = _trained(_units_row_export(export, units_row, sep), capsys)
    assert "v read in rpm ('Speed [rpm]'): scaled by 0.10472 to SI" in err
    v = np.array([-2.0, 0.5, 2.0])
    assert np.allclose(model.force(v), np.sign(v) * (COULOMB + VISCOUS * np.abs(v)), atol=0.01)


def test_a_units_row_after_a_preamble_and_with_a_blank_unit_is_read(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("Drive export v2\nsaved 2026-01-01\nt,Speed,Torque,state\ns,rpm,Nm,\n"
                    "0,10,0.5,1\n0.001,20,0.6,1\n")
    assert header_cells(path) == ["t [s]", "Speed [rpm]", "Torque [Nm]", "state"]
    table = read_table_csv(path, ("speed [rpm]",), keep_extra=True)
    assert list(table) == ["t [s]", "speed [rpm]", "torque [nm]", "state"]
    assert table["speed [rpm]"].tolist() == [10.0, 20.0]


def test_a_units_row_of_no_size_is_refused_in_one_line(export, capsys):
    out = export.parent / "model.json"
    assert main(["train", str(_units_row_export(export, "rpm,%")), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'Torque [%]' (force) is in %, a unit of no size" in err[0]
    assert not out.exists()


@pytest.mark.parametrize("row", [",,", "-,-,-", "N/A,n/a,-", "s,-,"])
def test_a_units_row_of_no_units_is_passed_over(tmp_path, row):
    path = tmp_path / "log.csv"
    path.write_text(f"t,v,f\n{row}\n0,0.1,0.5\n0.001,0.2,0.6\n")
    assert header_cells(path)[1:] == ["v", "f"]
    assert read_table_csv(path, ("v", "f"))["v"].tolist() == [0.1, 0.2]


def test_a_second_row_of_names_is_no_units_row(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("v,f\nspeed,torque\n0.1,0.5\n0.2,0.6\n")
    assert header_cells(path) == ["speed", "torque"]


def test_a_sweeps_force_is_scaled_by_either_of_its_names(export, capsys):
    plain = export.parent / "plain.csv"
    plain.write_text("v,force\n" + "\n".join(export.read_text().splitlines()[1:]) + "\n")
    by_force, _ = _trained(plain, capsys, "--scale", "v=0.10472,force=0.001")
    by_f, _ = _trained(plain, capsys, "--scale", "v=0.10472,f=0.001")
    v = np.array([-2.0, 0.5, 2.0])
    assert np.array_equal(by_force.force(v), by_f.force(v))
    assert np.allclose(by_f.force(v), np.sign(v) * (COULOMB + VISCOUS * np.abs(v)), atol=0.01)


def test_a_skip_that_lands_on_the_units_row_says_so(export, capsys):
    path = _units_row_export(export, "[rpm],[mNm]")
    assert main(["train", str(path), "--skip", "1", "-o", str(export.parent / "m.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "reads as a row of units: are the names on the line above it" in err[0]


@pytest.mark.parametrize("position, velocity, torque, factor, torque_factor", [
    ("Pos [deg]", "Vel [deg/s]", "Trq [Nm]", np.pi / 180, 1.0),
    ("Angle [rad]", "Speed [rad/s]", "Torque [Nm]", 1.0, 1.0),
    ("Pos [mrad]", "Vel [mrad/s]", "Trq [mNm]", 1e-3, 1e-3)])
def test_a_drives_short_names_with_units_are_read(tmp_path, capsys, position, velocity, torque,
                                                  factor, torque_factor):
    """Pos, Angle, Vel and Trq are read as x, v and the force, each scaled by its header's unit
    (``factor``: the angle's, ``torque_factor``: the torque's)."""
    rng = np.random.default_rng(1001)
    t = np.arange(0.0, 8.0, 1e-3)
    x = 1.5 * np.sin(2 * np.pi * 0.5 * t)
    v = np.gradient(x, t)
    f = 0.01 * np.gradient(v, t) + np.tanh(v / 0.01) * COULOMB + VISCOUS * v
    f = f + 0.002 * rng.standard_normal(t.size)
    path = tmp_path / "drive.csv"
    rows = "\n".join(f"{a:.4f},{b / factor:.7f},{c / factor:.7f},{d / torque_factor:.6f}"
                     for a, b, c, d in zip(t, x, v, f))
    path.write_text(f"t [s],{position},{velocity},{torque}\n{rows}\n")
    model, err = _trained(path, capsys)
    assert model.training["units"] == "rotary", err
    speeds = np.array([-2.0, -0.5, 0.5, 2.0])
    assert np.allclose(model.force(speeds), np.sign(speeds) * COULOMB + VISCOUS * speeds, atol=0.02)


def test_a_sweeps_spread_per_point_in_a_header_unit_is_read_and_scaled(tmp_path, capsys):
    """'F_std [mNm]' beside 'Torque [mNm]' had been dropped as a column not used: the points
    were fitted unweighted. It weights the fit as the same spread in Nm does."""
    rng = np.random.default_rng(1000)
    speed = np.geomspace(0.02, 2.0, 6)
    v = np.concatenate([speed, -speed])
    spread = np.where(np.abs(v) > 0.5, 0.05, 0.002)
    f = np.sign(v) * COULOMB + VISCOUS * v + spread * rng.standard_normal(v.size)
    si, milli = tmp_path / "si.csv", tmp_path / "milli.csv"
    rows = list(zip(v.tolist(), f.tolist(), spread.tolist()))
    si.write_text("v,f,F_std\n" + "".join(f"{a!r},{b!r},{c!r}\n" for a, b, c in rows))
    milli.write_text("v,Torque [mNm],F_std [mNm]\n" + "".join(f"{a!r},{1e3 * b!r},{1e3 * c!r}\n"
                                                                for a, b, c in rows))
    for path in (si, milli):
        assert main(["train", str(path), "--rotary", "-o", str(path.with_suffix(".json"))]) == 0
    captured = capsys.readouterr()
    assert "f_std read in mNm ('F_std [mNm]'): scaled by 0.001" in captured.out + captured.err
    probe = np.linspace(-2.0, 2.0, 41)
    assert FrictionModel.load(milli.with_suffix(".json")).force(probe) == pytest.approx(
        FrictionModel.load(si.with_suffix(".json")).force(probe), rel=1e-6, abs=1e-9)


def test_two_columns_of_one_quantity_must_agree():
    """dq beside qd (or tau beside torque) is one quantity read twice: equal, one is kept;
    different (a motor's velocity beside the joint's), which one is meant is named, not guessed."""
    from fricgen.data.export import by_quantity
    t, v = np.arange(5.0), np.linspace(-1.0, 1.0, 5)
    same = by_quantity({"t": t, "dq": v, "qd": v.copy(), "tau": v})
    assert sorted(same) == ["force", "t", "v"] and same["v"] is v
    with pytest.raises(DataError, match="columns 'dq' and 'qd' both read as 'v' and differ"):
        by_quantity({"t": t, "dq": v, "qd": 2 * v, "tau": v})
    with pytest.raises(DataError, match="columns 'force' and 'torque' both read as 'force'"):
        by_quantity({"t": t, "v": v, "force": v, "torque": v + 1})
    chosen = by_quantity({"t": t, "dq": v, "qd": 2 * v, "tau": v, "v": 2 * v}, mapped=("v",))
    assert "dq" not in chosen and "qd" not in chosen and np.array_equal(chosen["v"], 2 * v)


@pytest.mark.parametrize("header, said", [
    ("timestamp,actual_position,actual_velocity,actual_torque",
     "--columns 't=timestamp,x=actual_position,v=actual_velocity,force=actual_torque'"),
    ("Time [s],Motor Current,Joint Velocity", "--columns 't=Time [s],i=Motor Current,v=Joint Velocity'"),
    ("velocity,friction", "its names read as a sweep's? --columns 'v=velocity,f=friction'"),
])
def test_a_header_of_other_names_gets_the_mapping_to_type(tmp_path, capsys, header, said):
    """A vendor's names that hold the common names as words: the refusal writes the --columns
    mapping that reads them (it had named only the missing sweep columns)."""
    (tmp_path / "in.csv").write_text(header + "\n" + "\n".join(
        ",".join(str(0.1 * k + j) for j in range(header.count(",") + 1)) for k in range(30)) + "\n")
    assert main(["train", str(tmp_path / "in.csv"), "-o", str(tmp_path / "m.json")]) == 2
    assert said in capsys.readouterr().err and not (tmp_path / "m.json").exists()


def test_a_header_of_no_known_words_gets_no_mapping():
    from fricgen.data.export import suggested_columns
    assert suggested_columns(["a", "b"]) == "" and suggested_columns(["time", "velocity"]) == ""


@pytest.mark.parametrize("cell", ["", "nan"])
def test_a_dropped_sample_of_a_joint_log_is_named_with_what_to_do(tmp_path, capsys, cell):
    """A blank or NaN velocity in a joint's log (q, dq, tau): the row is named, with the advice
    to delete it (a NaN had been refused as "the joint's speed reaches nan rad/s ... degrees?")."""
    t = (np.arange(400) * 1e-3).tolist()
    rows = [f"{a!r},{np.sin(a):.9g},{np.cos(a):.9g},0.3" for a in t]
    rows[100] = f"{t[100]!r},{np.sin(t[100]):.9g},{cell},0.3"
    (tmp_path / "j.csv").write_text("t,q,dq,tau\n" + "\n".join(rows) + "\n")
    assert main(["train", str(tmp_path / "j.csv"), "-o", str(tmp_path / "m.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and ("line 102" in err[0] or "data row 101" in err[0]) and "rad/s" not in err[0]
    assert err[0].endswith("a sample dropped? delete its row: the time column spaces the others")


@pytest.mark.parametrize("scale, warned", [(1.0, False), (np.degrees(1.0), True)])
def test_a_slow_joint_in_degrees_is_warned_of_by_its_span(tmp_path, capsys, scale, warned):
    """A joint swinging +-0.2 rad at 0.25 rad/s at most: in degrees read as rad it is slower than
    the 20 rad/s refusal, and had trained every number 57 times off without a word; its
    position's span (23 "rad", 3.6 turns) is warned of."""
    rng = np.random.default_rng(1000)
    t = np.arange(0.0, 10.0, 1e-3)
    q = 0.2 * np.sin(2 * np.pi * 0.2 * t)
    dq = np.gradient(q, t)
    tau = 0.05 * np.gradient(dq, t) + np.tanh(dq / 0.01) * (0.4 + 0.2 * np.abs(dq))
    cols = {"t": t, "q": scale * q, "dq": scale * dq, "tau": tau + 0.01 * rng.standard_normal(t.size)}
    (tmp_path / "j.csv").write_text("t,q,dq,tau\n" + "\n".join(
        ",".join(f"{c[k]:.9g}" for c in cols.values()) for k in range(t.size)) + "\n")
    assert main(["train", str(tmp_path / "j.csv"), "-o", str(tmp_path / "m.json")]) == 0
    said = [line for line in capsys.readouterr().err.splitlines() if "position spans" in line]
    assert len(said) == warned
    if warned:
        assert "in degrees (--scale x=0.0174533,v=0.0174533)?" in said[0]
