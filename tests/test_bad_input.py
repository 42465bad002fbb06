"""Every input a user can type: one row per input, the exit code, the one stderr line, and
nothing written. Extend the tables when a new input is found."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import copy_of
from fricgen.cli import main
from fricgen.model import FrictionModel


@pytest.fixture(scope="module")
def work(cli_inputs, tmp_path_factory):
    """A folder with a sweep, a model, a log and every malformed file the rows below read."""
    d = copy_of(cli_inputs, tmp_path_factory.mktemp("bad") / "work")
    rows = (d / "sweep.csv").read_text().splitlines()
    body = rows[1:]
    files = {
        "comma_decimal.csv": "v;f\n" + "\n".join(r.replace(",", ";").replace(".", ",") for r in body),
        "quoted_comma.csv": "v,f\n" + "\n".join('"%s","%s"' % tuple(c.replace(".", ",") for c in r.split(","))
                                                for r in body),
        "all_zero_v.csv": "v,f\n" + "0,1\n" * 50,
        "all_zero_f.csv": "v,f\n" + "".join(f"{s * v:g},0\n" for s in (1, -1) for v in (0.001, 0.01, 0.1, 0.3, 0.5)),
        "long_cell.csv": "v,f\n" + "1" * 200_000 + ",1\n" + "\n".join(body[:40]),
        "tiny_values.csv": "v,f\n" + "\n".join(f"{1e-300 * (k + 1)},{1e-300 * (k + 2)}" for k in range(60)),
        "duplicate_columns.csv": "v,f,f\n" + "\n".join(r + ",0" for r in body),
        "huge_forces.csv": "v,f\n" + "\n".join(f"{r.split(',')[0]},{float(r.split(',')[1]) * 1e306}"
                                                for r in body),
        "falling.csv": "v,f\n" + "\n".join(f"{r.split(',')[0]},{float(r.split(',')[1]) - 115 * float(r.split(',')[0])!r}"
                                            for r in body),
        "one_speed.csv": "v,f\n" + "0.05,3\n" * 60,
        "int400.json": (d / "model.json").read_text().replace('"viscous": ', '"viscous": ' + "9" * 400 + ', "x": '),
        "unicode_digits.csv": "v,f\n" + "\n".join(body[:20]) + "\n0.01,\uff11\n" + "\n".join(body[20:]),
        "underscores.csv": "v,f\n" + "\n".join(body[:20]) + "\n0.01,1_0\n" + "\n".join(body[20:]),
        "ragged.csv": "v,f\n" + "\n".join(body[:30]) + "\n0.01,1,2\n" + "\n".join(body[30:]),
        "status_row.csv": "v,f\nOK,OK\n" + "\n".join(body),
        "text_in_force.csv": "v,f,state\n" + "\n".join(r + ",OK" for r in body[:20]) + "\n0.01,ERR,fault\n"
                             + "\n".join(r + ",OK" for r in body[20:]),
        "semicolon_cells.csv": "v;x,f\n" + "\n".join(body),
        "big_int.json": '{"format": "fricgen-model", "format_version": 1, "name": "m", "viscous": '
                        + "9" * 5001 + "}",
        "inf_number.json": '{"format": "fricgen-model", "format_version": 1, "name": "m", '
                           '"aim": {"kind": "elm"}, "viscous": 1e400}',
        "nested.json": "[" * 100_000,
        "nan.json": (d / "model.json").read_text().replace('"viscous": ', '"viscous": NaN, "x": '),
    }
    for name, text in files.items():
        (d / name).write_text(text + "\n")
    (d / "non_utf8.csv").write_bytes(b"v,f\n" + b"\xff\xfe,1\n" * 30)
    (d / "non_utf8.json").write_bytes(b"\xff\xfe{}")
    log = (d / "log.csv").read_text().splitlines()
    ms = [log[0]] + [",".join([repr(1000 * float(line.split(",")[0]))] + line.split(",")[1:])
                     for line in log[1:]]
    (d / "log_ms.csv").write_text("\n".join(ms) + "\n")
    (d / "log_no_time.csv").write_text("\n".join(line.partition(",")[2] for line in log) + "\n")
    cells = log[50].split(",")
    cells[log[0].split(",").index("i")] = "nan"
    (d / "log_nan.csv").write_text("\n".join(log[:50] + [",".join(cells)] + log[51:]) + "\n")
    _motion_log_files(d, log)
    _matlab_files(d, log)
    _trial_files(d, log)
    _plausibility_files(d, log)
    (d / "log_swapped.csv").write_text("\n".join(log[:100] + [log[101], log[100]] + log[102:]) + "\n")
    (d / "log_short.csv").write_text("\n".join(log[:16]) + "\n")
    (d / "log_repeated_t.csv").write_text("\n".join(log[:100] + [log[100]] + log[100:]) + "\n")
    (d / "log_units.csv").write_text("\n".join([log[0].replace("i", "I [Nm]")] + log[1:]) + "\n")
    (d / "log_percent.csv").write_text("\n".join([log[0].replace("i", "Iq [%]")] + log[1:]) + "\n")
    _edited_columns(d, log, "log_v_zero.csv", v=lambda v, x: 0.0)
    _edited_columns(d, log, "log_x_inverted.csv", x=lambda v, x: -x)
    columns = log[0].split(",")
    for col in ("i", "x"):
        k = columns.index(col)
        body = [line.split(",") for line in log[1:]]
        for cells_k in body:
            cells_k[k] = "1.5"
        (d / f"log_constant_{col}.csv").write_text("\n".join([log[0]] + [",".join(c) for c in body]) + "\n")
    model = json.loads((d / "model.json").read_text())
    for name, edit in (("huge_weights.json", lambda m: m["aim"]["output_weights"].__setitem__(0, 3e38)),
                       ("kind_list.json", lambda m: m["aim"].__setitem__("kind", [])),
                       ("effect_dict.json", lambda m: m.__setitem__("effects", [{"effect": {}}])),
                       ("version_true.json", lambda m: m.__setitem__("format_version", True)),
                       ("negative_b.json", lambda m: m.__setitem__("viscous", -m["viscous"])),
                       ("pushing_offset.json", lambda m: m.__setitem__("aim", {
                           "kind": "stribeck", "shape": "gauss", "offset": -0.5, "amplitudes": [0.3],
                           "stribeck": [0.2], "slope": 0.0})),
                       ("tiny_stribeck.json", lambda m: m.__setitem__("aim", {
                           "kind": "stribeck", "shape": "gauss", "offset": 0.99, "amplitudes": [0.01],
                           "stribeck": [1e-40], "slope": 0.0})),
                       ("zero_stribeck.json", lambda m: m.__setitem__("aim", {
                           "kind": "stribeck", "shape": "gauss", "offset": 0.99, "amplitudes": [0.01],
                           "stribeck": [0.0], "slope": 0.0})),
                       ("undetermined_source.json", lambda m: (m.__setitem__("aim", {
                           "kind": "stribeck", "shape": "gauss", "offset": 0.6, "amplitudes": [0.3, 0.1],
                           "stribeck": [0.2, 0.01], "slope": 0.0}), m["training"].__setitem__(
                           "standard_errors", {"amplitudes_newton": [0.01, 0.02],
                                               "stribeck_m_per_s": [0.001, None]}))),
                       ("model_table.json", lambda m: m.__setitem__("effects", [
                           {"effect": "table_velocity", "parameters": {"lo": 1, "hi": 0, "values": [1, 2]}}]))):
        edited = json.loads(json.dumps(model))
        edit(edited)
        (d / name).write_text(json.dumps(edited))
    undetermined = d / "undetermined_source.json"        # as training would have written it
    undetermined.write_text(FrictionModel.from_dict(json.loads(undetermined.read_text())).to_json())
    (d / "duplicate_key.json").write_text((d / "model.json").read_text().replace(
        '"viscous": ', '"viscous": 1.0, "viscous": ', 1))
    _dump_files(d)
    return d


def _dump_files(d):
    """Adaptation dumps (fric_adapt_export's text) of model.json gone wrong, and a good one."""
    from fricgen.control.readback import dump_text
    from fricgen.control.regressor import parameter_names, trained_parameters
    m = FrictionModel.load(d / "model.json")
    theta = trained_parameters(m)
    good = dump_text(m.model_hash, theta)
    (d / "dump.txt").write_text(good)
    (d / "dump_other_model.txt").write_text(dump_text("0123456789abcdef", theta))
    (d / "dump_short.txt").write_text(dump_text(m.model_hash, theta[:-1]))
    (d / "dump_not_hex.txt").write_text(good.replace("theta ", "theta 3e0zcc24 "))
    (d / "dump_nan.txt").write_text(dump_text(m.model_hash, np.append(theta[:-1], np.nan)))
    negative_b = theta.copy()
    negative_b[parameter_names(m).index("B")] *= -1.0
    (d / "dump_negative_b.txt").write_text(dump_text(m.model_hash, negative_b))


def _edited_columns(d, log, name, **edits):
    """log.csv with the named columns replaced by edit(v, x) of each row."""
    header = log[0].split(",")
    rows = []
    for line in log[1:]:
        cells = line.split(",")
        v, x = (float(cells[header.index(c)]) for c in ("v", "x"))
        for column, edit in edits.items():
            cells[header.index(column)] = repr(float(edit(v, x)))
        rows.append(",".join(cells))
    (d / name).write_text("\n".join([log[0]] + rows) + "\n")


def _matlab_files(d, log):
    """log.csv as MATLAB files: with scalars and variables that are no columns; as
    v7.3 (its header), truncated, and without variables."""
    from scipy.io import savemat
    header = log[0].split(",")
    cols = {h: np.array([float(line.split(",")[k]) for line in log[1:]])[:, None] for k, h in enumerate(header)}
    savemat(d / "log.mat", {**cols, "phi": 20.0, "zero": 0.0, "note": "axis 1", "meta": {"rate": 1e3},
                            "gains": np.ones((3, 4)), "short": np.arange(7.0)})
    raw = (d / "log.mat").read_bytes()
    (d / "v73.mat").write_bytes(raw[:124] + b"\x00\x02IM" + b"\x89HDF\r\n\x1a\n" + bytes(100))
    (d / "truncated.mat").write_bytes(raw[:300])
    savemat(d / "no_variables.mat", {})


def _trial_files(d, log):
    """The files of TRIAL_ROWS: symbolic links that lead nowhere, log.csv without t."""
    (d / "broken_link").symlink_to(d / "nothing_here")
    (d / "loop_link").symlink_to(d / "loop_link")
    (d / "empty.csv").write_text("")
    (d / "header_only.csv").write_text("v,f\n")
    (d / "header_only_log.csv").write_text("t,x,v,i\n\n")
    (d / "blank.csv").write_text("\n\n")
    sweep = (d / "sweep.csv").read_text().split("\n", 1)[1]
    (d / "velocity_friction.csv").write_text("velocity,friction\n" + sweep)
    from fricgen.data import prepare, read_sweep_csv
    from fricgen.fit.elm import ELMRegressor
    data = prepare(read_sweep_csv(d / "sweep.csv"), vs_max=0.02)
    FrictionModel.fit(data, ELMRegressor(n_hidden=20, random_state=0), name="big").save(d / "elm20.json")
    (d / "tab_comma.csv").write_text("v\tf\n" + "0,0125\t5,75\n" * 30)
    (d / "log_no_t.csv").write_text("\n".join(line.partition(",")[2] for line in log) + "\n")


def _plausibility_files(d, log):
    """The files of PLAUSIBILITY_ROWS: the sweep with v and f swapped, in mm/s, with thousands
    separators; the model hand-edited; a drive export timed in ms beside a current file timed in
    s; and a folder holding a report.md the user wrote."""
    rows = [line.split(",") for line in (d / "sweep.csv").read_text().splitlines()[1:]]
    v, f = np.array(rows, dtype=float).T
    (d / "sweep_swapped.csv").write_text("v,f\n" + "".join(f"{b!r},{a!r}\n" for a, b in zip(v.tolist(), f.tolist())))
    (d / "sweep_mm.csv").write_text("v,f\n" + "".join(f"{1000 * a!r},{b!r}\n" for a, b in zip(v.tolist(), f.tolist())))
    (d / "thousands.csv").write_text("v,f\n" + "".join(f"{1000 * a:,.3f},{100 * b:,.2f}\n"
                                                        for a, b in zip(v.tolist(), f.tolist())))
    t_log, _, v_log = np.array([line.split(",")[:3] for line in log[1:]], dtype=float).T
    a_log = np.gradient(v_log, t_log)
    for name, header, a in (("log_accel_v.csv", "a", v_log), ("log_accel_deg.csv", "a", np.degrees(a_log)),
                            ("log_accel_unit.csv", "a [rad/s]", a_log), ("log_two_v.csv", "speed", 2 * v_log)):
        (d / name).write_text("\n".join([f"{log[0]},{header}"] + [f"{line},{value!r}" for line, value
                                                                  in zip(log[1:], a.tolist())]) + "\n")
    model = json.loads((d / "model.json").read_text())
    for name, key, value in (("dropped_decimal.json", "viscous", float(str(model["viscous"]).replace(".", ""))),
                             ("v_sat_edited.json", "v_sat", 45.6375)):
        (d / name).write_text(json.dumps({**model, key: value}))
    aim = json.loads(json.dumps(model["aim"]))
    aim["input_weights"][0] = 1e39
    (d / "float32_overflow.json").write_text(json.dumps({**model, "aim": aim}))
    header = log[0].split(",")
    cells = [line.split(",") for line in log[1:]]
    col = {h: [c[k] for c in cells] for k, h in enumerate(header)}
    (d / "drive_ms.csv").write_text("# drive export\nTime [ms],Pos,Speed\n" + "".join(
        f"{1000 * float(t)!r},{x},{v}\n" for t, x, v in zip(col["t"], col["x"], col["v"])))
    (d / "current.csv").write_text("Stamp,Current\n" + "".join(f"{t},{i}\n" for t, i in zip(col["t"], col["i"])))
    (d / "thousands_quoted.csv").write_text("v,f\n" + "".join(f'{a!r},"{1000 * b:,.1f}"\n'
                                                               for a, b in zip(v.tolist(), f.tolist())))
    slow = np.abs(v) < 0.015
    (d / "sweep_slow_mm.csv").write_text("v,f\n" + "".join(f"{1000 * a!r},{b!r}\n"
                                                           for a, b in zip(v[slow].tolist(), f[slow].tolist())))
    (d / "sweep_current.csv").write_text("v,i\n" + "".join(f"{a!r},{2 * b!r}\n"
                                                           for a, b in zip(v.tolist(), f.tolist())))
    (d / "notes").mkdir()
    (d / "notes" / "report.md").write_text("# my own notes\n")


def _motion_log_files(d, log):
    """The files of the motion-log and vendor-export rows: log.csv as t,v,force; as a vendor's
    drive file (preamble, own names) and load-cell file; and an asymmetric model.json."""
    from fricgen.model import Direction, FrictionModel
    header = log[0].split(",")
    cols = {h: [line.split(",")[k] for line in log[1:]] for k, h in enumerate(header)}
    force = [repr(20 * float(i)) for i in cols["i"]]
    (d / "log_force.csv").write_text("t,v,force\n" + "\n".join(
        ",".join(r) for r in zip(cols["t"], cols["v"], force)) + "\n")
    (d / "drive.csv").write_text("# drive export\n# 1 kHz\nTime,Speed\n" + "\n".join(
        ",".join(r) for r in zip(cols["t"], cols["v"])) + "\n")
    (d / "load.csv").write_text("Stamp,Load\n" + "\n".join(
        ",".join(r) for r in zip(cols["t"], force)) + "\n")
    mm = [header] + [[repr(float(c) * (1000.0 if h in ("x", "v", "x_d") else 1.0)) for h, c in zip(header, row)]
                     for row in (line.split(",") for line in log[1:])]
    (d / "log_mm.csv").write_text("\n".join(",".join(r) for r in mm) + "\n")        # x and v in mm
    ma = [header] + [[repr(float(c) * (1000.0 if h == "i" else 1.0)) for h, c in zip(header, row)]
                     for row in (line.split(",") for line in log[1:])]
    (d / "log_mA.csv").write_text("\n".join(",".join(r) for r in ma) + "\n")        # i in mA
    lines = (d / "load.csv").read_text().splitlines()
    lines[5] = lines[5].partition(",")[0] + ",nan"          # data row 5
    (d / "load_nan.csv").write_text("\n".join(lines) + "\n")
    (d / "jitter.csv").write_text("t,v,force\n" + "\n".join(
        f"{float(t) + (0.5 if k > 10 else 0.0)!r},{v},{f}"
        for k, (t, v, f) in enumerate(zip(cols["t"], cols["v"], force))) + "\n")
    m = FrictionModel.load(d / "model.json")
    negative = Direction(m.aim, m.scaling, 1.1 * m.viscous, m.v_sat)
    (d / "asym.json").write_text(FrictionModel.from_directions(m.positive, negative, name="fa").to_json())


OUT = "OUT"          # stands for a fresh output path in the rows below
LOG = ["--mass", "4", "--force-constant", "20"]
DRIVE = ["drive.csv", "--skip", "2", "--columns", "t=Time,v=Speed", "--mass", "4"]
MERGE = ["--merge", "load.csv", "--merge-columns", "t=Stamp,force=Load"]
DIAG = ["--mass", "4", "--force-constant", "20"]

LONG = "a" * 300     # a file name longer than a file system allows

#: Rows from a new-user trial: (row id, argv, words of the one error line; WORK/ is the work
#: folder).
TRIAL_ROWS = [
    ("-o a name over 255 bytes", ["train", "sweep.csv", "-o", LONG + ".json"],
     f"-o {LONG}.json: File name too long"),
    ("folder -o a name over 255 bytes", ["emit", "model.json", "-o", LONG], f"-o {LONG}: File name too long"),
    ("folder -o a broken symbolic link", ["emit", "model.json", "-o", "broken_link"],
     "-o WORK/broken_link: is a broken symbolic link"),
    ("-o a symbolic link that loops, --force", ["train", "sweep.csv", "-o", "loop_link", "--force"],
     "-o WORK/loop_link: is a symbolic link that loops"),
    ("--scale of a quantity the file lacks", ["train", "sweep.csv", "--scale", "x=1000", "-o", OUT],
     "--scale: x is not a column of WORK/sweep.csv (its columns: v, f)"),
    ("--scale of a quantity neither file has", ["train", *DRIVE, *MERGE, "--scale", "i=2", "-o", OUT],
     "--scale: i is a column of neither WORK/drive.csv (t, v) nor WORK/load.csv (t, force)"),
    ("train, an empty file", ["train", "empty.csv", "-o", OUT], "WORK/empty.csv: empty file"),
    ("train, a header and no rows", ["train", "header_only.csv", "-o", OUT],
     "WORK/header_only.csv: a header and no data rows"),
    ("diagnose, a header and a blank line", ["diagnose", "header_only_log.csv", "--model", "model.json",
                                             *DIAG, "-o", OUT],
     "WORK/header_only_log.csv: a header and no data rows"),
    ("train, a file of blank lines", ["train", "blank.csv", "-o", OUT],
     "WORK/blank.csv: the header line is blank; the first line must name the columns"),
    ("a tab-separated sweep with decimal commas, all at one speed", ["train", "tab_comma.csv", "-o", OUT],
     "the points are all at one speed: a friction law needs two speeds or more"),
    ("emit --adapt, a 20-neuron ELM", ["emit", "elm20.json", "-o", OUT, "--adapt"],
     "the model has 21 output parameters; online adaptation holds at most 18 (FRIC_ADAPT_MAX_PARAMS)"),
    ("a sweep with its own column names", ["train", "velocity_friction.csv", "-o", OUT],
     "missing column 'f' of a sweep, or t, v or x, and force or i of a motion log (header is "
     "velocity,friction); its names read as a sweep's? --columns 'v=velocity,f=friction'"),
    ("a log without t", ["train", "log_no_t.csv", *LOG, "-o", OUT],
     "a motion log needs t, v or x, and force or i: missing t (header is x,v,i,x_d)"),
    ("a sweep of the current", ["train", "sweep_current.csv", "--force-constant", "0.5", "-o", OUT],
     "missing t (header is v,i); a sweep of the current? --columns f=i --scale f=K reads it, K the "
     "force constant"),
    ("train, constant current", ["train", "log_constant_i.csv", *LOG, "-o", OUT],
     "the current i is constant (1.5 A) over 98 % of the log"),
    ("--merge with a short common time", ["train", *DRIVE, *MERGE, "--merge-shift", "2.9", "-o", OUT],
     "WORK/drive.csv + WORK/load.csv: the axis moves steadily in only 95 rows (about 32 independent "
     "samples"),
    ("--merge of a log of the wrong sign", ["train", *DRIVE, *MERGE, "--scale", "v=\u22121", "-o", OUT],
     "WORK/drive.csv + WORK/load.csv: the force has the opposite sign of v"),
    ("--merge of no force", ["train", "drive.csv", "--skip", "2", "--columns", "t=Time,v=Speed", "--merge",
                             "load.csv", "--merge-columns", "t=Stamp,x=Load", "-o", OUT],
     "WORK/drive.csv + WORK/load.csv: a motion log needs t, v or x, and force or i: missing force or i"),
    ("diagnose, a mass 100 times off", ["diagnose", "log.csv", "--model", "model.json", "--mass", "400",
                                        "--force-constant", "20", "-o", OUT], "WORK/log.csv: phi i is 0.0"),
]

#: Well-formed input that cannot be right (the cases of the plausibility issue): (row id, argv,
#: words of the one error line).
DRIVE_MS = ["drive_ms.csv", "--skip", "1", "--columns", "t=Time [ms],x=Pos,v=Speed", "--scale", "t=0.001",
            "--merge", "current.csv", "--merge-columns", "t=Stamp,i=Current"]
PLAUSIBILITY_ROWS = [
    ("a log's acceleration column holding v", ["train", "log_accel_v.csv", *LOG, "-o", OUT],
     "the log's acceleration column (a) is not its dv/dt: it follows dv/dt with slope"),
    ("a log's acceleration in deg/s^2", ["train", "log_accel_deg.csv", *LOG, "-o", OUT],
     "in deg/s^2? --scale a=0.0174533 converts it"),
    ("two velocity columns that differ", ["train", "log_two_v.csv", *LOG, "-o", OUT],
     "columns 'v' and 'speed' both read as 'v' and differ: name the one to use (--columns v=COLUMN)"),
    ("a log's acceleration column in rad/s", ["train", "log_accel_unit.csv", *LOG, "-o", OUT],
     "column 'a [rad/s]' is read as a, an acceleration, but its unit rad/s is a velocity's"),
    *[(f"swapped sweep columns, {' '.join(m) or 'default'}", ["train", "sweep_swapped.csv", *m, "-o", OUT],
       "are the columns v and f swapped? (--accept-unusual to use the data as they are)")
      for m in ([], ["--method", "elm_auto"], ["--method", "stribeck"], ["--symmetric"])],
    ("a sweep in mm/s", ["train", "sweep_mm.csv", "-o", OUT],
     "m/s, above the 20 m/s of any real axis; is v in mm/s? --scale v=0.001 converts it"),
    ("a decimal point dropped from viscous", ["eval", "dropped_decimal.json"],
     "the largest force on [0, v_sat] is"),
    ("a decimal point dropped from viscous, emitted", ["emit", "dropped_decimal.json", "-o", OUT],
     "above the 100000 N of any real axis"),
    ("v_sat edited, k_in not", ["eval", "v_sat_edited.json"], "the normalization [F9] needs k_in = 1/v_sat"),
    ("a weight beyond float32, eval", ["eval", "float32_overflow.json"],
     "aim.input_weights[0] is beyond 3.403e+38, the largest float32"),
    ("--scale t applies to both files", ["diagnose", *DRIVE_MS, "--model", "model.json", *DIAG, "-o", OUT],
     "is one timed in ms? (--scale applies to both files; --merge-scale t=FACTOR to the --merge file alone)"),
    ("--merge-shift off by half a second", ["train", *DRIVE, *MERGE, "--merge-shift", "0.5", "-o", OUT],
     "--merge-shift 0.5 s looks off: the force of WORK/load.csv fits the motion of WORK/drive.csv best at a "
     "shift of about"),
    ("diagnose -o over a report.md fricgen did not write", ["diagnose", "log.csv", "--model", "model.json",
                                                            *DIAG, "-o", "notes"],
     "-o WORK/notes/report.md: was not written by fricgen; refusing to overwrite it (--force to do so)"),
    ("a typo in --columns", ["train", *DRIVE[:3], "--columns", "t=Time,v=Sped", "--mass", "4", "-o", OUT],
     "--columns: v='Sped': WORK/drive.csv has no such column (header is Time,Speed); did you mean 'Speed'?"),
    ("a CSV with thousands separators", ["train", "thousands.csv", "-o", OUT],
     "3 cells, the header names 2; are its numbers written with ',' between thousands (1,740.65)?"),
    ("a CSV with quoted thousands separators", ["train", "thousands_quoted.csv", "-o", OUT],
     "are its numbers written with ',' between thousands (1,740.65)?"),
    ("a slow sweep in mm/s", ["train", "sweep_slow_mm.csv", "-o", OUT],
     "above the 5 m/s of most axes: is v in m/min (--scale v=0.0166667) or mm/s (--scale v=0.001), "
     "or the axis a joint or shaft (--rotary) in rad/s, or in rpm (--scale v=0.10472) or deg/s "
     "(--scale v=0.0174533)? (--accept-unusual"),
    ("--merge-scale without --merge", ["train", *DRIVE, "--merge-scale", "t=0.001", "-o", OUT],
     "need --merge FILE"),
    ("--merge-scale of a quantity the merge file lacks", ["train", *DRIVE, *MERGE, "--merge-scale", "v=2",
                                                          "-o", OUT],
     "--merge-scale: v is not a column of WORK/load.csv (its columns: t, force)"),
]

#: (row id, argv (files relative to the work folder), words of the one error line)
ROWS = [
    ("a ';' export with decimal commas forced to ','", ["train", "comma_decimal.csv", "--delimiter", ",",
                                                        "-o", OUT],
     "the header 'v;f' does not split at ','; say which delimiter it uses (--delimiter)"),
    ("';' in header cells", ["train", "semicolon_cells.csv", "-o", OUT],
     "(header is v;x,f); it looks ';'-separated: say --delimiter ';'"),
    ("quoted comma decimals", ["train", "quoted_comma.csv", "-o", OUT], "non-numeric"),
    ("all v = 0", ["train", "all_zero_v.csv", "-o", OUT], "a friction sweep needs motion"),
    ("all f = 0, accepted as unusual", ["train", "all_zero_f.csv", "--accept-unusual", "-o", OUT],
     "the force is 0 at every moving point: the data hold no friction"),
    ("non-UTF-8 CSV", ["train", "non_utf8.csv", "-o", OUT], "not UTF-8 text"),
    ("cell of 200000 digits", ["train", "long_cell.csv", "-o", OUT], "NaN or infinite"),
    ("values around 1e-300", ["train", "tiny_values.csv", "-o", OUT], "below the 1e-06 m/s of any real axis"),
    ("duplicate column names", ["train", "duplicate_columns.csv", "-o", OUT], "appears more than once"),
    ("forces scaled by 1e306", ["train", "huge_forces.csv", "-o", OUT], "above the 100000 N of any real axis"),
    ("force falling at high speed", ["train", "falling.csv", "--vs-max", "0.02", "-o", OUT],
     "friction must oppose the motion"),
    ("a sweep at one speed", ["train", "one_speed.csv", "-o", OUT], "all at one speed"),
    ("a log with t in ms", ["train", "log_ms.csv", *LOG, "-o", OUT], "dx/dt is 0.001 times v"),
    ("a row of the wrong width", ["train", "ragged.csv", "-o", OUT], "3 cells, the header names 2"),
    ("a status row under the header", ["train", "status_row.csv", "-o", OUT],
     "line 2: non-numeric or missing cell 'OK' in column 'v'"),
    ("text in the force beside a status column", ["train", "text_in_force.csv", "-o", OUT],
     "line 22: non-numeric or missing cell 'ERR' in column 'f'"),
    ("digits of another script", ["train", "unicode_digits.csv", "-o", OUT], "non-numeric"),
    ("'_' in a number", ["train", "underscores.csv", "-o", OUT], "non-numeric"),
    ("--C without ridge", ["train", "sweep.csv", "-o", OUT, "--C", "10"], "--C sets the C of --solver ridge"),
    ("--neurons 0", ["train", "sweep.csv", "-o", OUT, "--neurons", "0"], "--neurons: must be an integer >= 1"),
    ("--neurons 5000", ["train", "sweep.csv", "-o", OUT, "--neurons", "5000"], "<= 4096"),
    ("--max-neurons 0", ["train", "sweep.csv", "-o", OUT, "--max-neurons", "0"],
     "--max-neurons: must be an integer >= 1"),
    ("--max-neurons with elm", ["train", "sweep.csv", "-o", OUT, "--method", "elm", "--max-neurons", "5"],
     "--max-neurons caps --method auto"),
    ("velocity sign flipped", ["train", "sweep.csv", "-o", OUT, "--scale", "v=-1"],
     "the force has the opposite sign of v"),
    ("--max-neurons with stribeck", ["train", "sweep.csv", "-o", OUT, "--method", "stribeck",
                                     "--max-neurons", "5"], "--method stribeck has no neurons"),
    ("--w-max 2", ["train", "sweep.csv", "-o", OUT, "--w-max", "2"], "--w-max: w_max=2.0 too small"),
    ("--seed -1", ["train", "sweep.csv", "-o", OUT, "--method", "elm", "--seed", "-1"], "--seed: must be"),
    ("--delimiter of another name", ["train", "sweep.csv", "-o", OUT, "--delimiter", "x"],
     "--delimiter: invalid choice: 'x'"),
    ("--delimiter ';' on a ','-separated sweep", ["train", "sweep.csv", "-o", OUT, "--delimiter", ";"],
     "does not split at ';'"),
    ("--neurons with --method stribeck", ["train", "sweep.csv", "-o", OUT, "--method", "stribeck",
                                          "--neurons", "3"], "configure --method elm, not --method stribeck"),
    ("--vs-max nan", ["train", "sweep.csv", "-o", OUT, "--vs-max", "nan"], "--vs-max: must be"),
    ("5001-digit integer in model.json", ["eval", "big_int.json"], "not valid JSON"),
    ("10**400 in model.json", ["eval", "inf_number.json"], "must be"),
    ("400-digit integer in model.json", ["eval", "int400.json"], "model.viscous must be finite"),
    ("100000 nested [", ["eval", "nested.json"], "nested too deeply"),
    ("non-UTF-8 model.json", ["emit", "non_utf8.json", "-o", OUT], "not UTF-8 text"),
    ("NaN in model.json", ["emit", "nan.json", "-o", OUT], "NaN is not a JSON number"),
    ("weights of 3e38", ["emit", "huge_weights.json", "-o", OUT], "the float32 C needs it below"),
    ("a key twice in model.json", ["eval", "duplicate_key.json"], "key 'viscous' appears twice"),
    ("negative viscous coefficient", ["emit", "negative_b.json", "-o", OUT], "friction must oppose the motion"),
    ("emit --v-max in mm/s", ["emit", "model.json", "-o", OUT, "--dtype", "q15", "--v-max", "300"],
     "--v-max: must be a finite number > 0 and <= 20 m/s, got 300"),
    ("an edited offset that makes the friction push", ["emit", "pushing_offset.json", "-o", OUT],
     "it pushes the axis instead of opposing the motion"),
    ("a Stribeck velocity of 1e-40", ["eval", "tiny_stribeck.json"], "aim.stribeck[0] is 1e-40 (normalized)"),
    ("a Stribeck velocity of 1e-40, emitted", ["emit", "tiny_stribeck.json", "-o", OUT],
     "aim.stribeck[0] is 1e-40 (normalized)"),
    ("a Stribeck velocity of 0, emitted", ["emit", "zero_stribeck.json", "-o", OUT],
     "aim.stribeck"),
    ("a source the training data did not determine, emitted",
     ["emit", "undetermined_source.json", "-o", OUT],
     "source 2 of the grey-box curve (v_s = "),
    ("aim.kind a list", ["eval", "kind_list.json"], "aim.kind must be one of"),
    ("effect name an object", ["eval", "effect_dict.json"], "unknown effect {}"),
    ("format_version true", ["eval", "version_true.json"], "unknown format_version True"),
    ("-o empty", ["emit", "model.json", "-o", ""], "-o: empty path"),
    ("-o a folder name for a file", ["train", "sweep.csv", "-o", "OUT/"], "names a folder"),
    ("-o under a file", ["train", "sweep.csv", "-o", "UNDER_INPUT"], "sweep.csv is not a folder"),
    ("-o in /proc", ["train", "sweep.csv", "-o", "/proc/m.json"], "cannot write in /proc"),
    ("--w-max 1e300", ["train", "sweep.csv", "-o", OUT, "--w-max", "1e300"], "--w-max: must be"),
    ("demo -o a file", ["demo", "--seeds", "1", "-o", "model.json"], "is not a folder"),
    ("reproduce -o in /proc", ["reproduce", "--quick", "-o", "/proc/r"], "cannot write in /proc"),
    ("synth --noise -1", ["synth", "--noise", "-1", "-o", OUT], "--noise: must be"),
    ("synth --noise nan", ["synth", "--noise", "nan", "-o", OUT], "--noise: must be"),
    ("synth --seed -1", ["synth", "--seed", "-1", "-o", OUT], "--seed: must be"),
    ("synth-log --duration inf", ["synth-log", "--duration", "inf", "-o", OUT], "--duration: must be"),
    ("synth-log --duration 1e9", ["synth-log", "--duration", "1e9", "-o", OUT], "<= 1200 s"),
    ("synth-log shorter than a log", ["synth-log", "--duration", "0.5", "-o", OUT],
     "--duration: must be >= 0.999 s, the 1000 samples a log needs at 1000 Hz, got 0.5"),
    ("--seed in fullwidth digits", ["synth", "--seed", "\uff11", "-o", OUT], "--seed: must be an integer"),
    ("synth-log negative mass", ["synth-log", "--effect", "inertia_mismatch", "--magnitude", "-5",
                                 "-o", OUT], "--magnitude: must be a finite number > 0"),
    ("synth-log --magnitude nan", ["synth-log", "--magnitude", "nan", "-o", OUT], "--magnitude: must be"),
    ("simulate --ts 5e-324", ["simulate", "--ts", "5e-324"], "--ts: must be a finite number >= 1e-06"),
    ("simulate --duration 1e9", ["simulate", "--duration", "1e9"], "--duration: must be"),
    ("simulate of 300000 samples", ["simulate", "--ts", "1e-5", "--duration", "3"], "samples"),
    ("diagnose, t in ms", ["diagnose", "log_ms.csv", "--model", "model.json", *DIAG, "-o", OUT],
     "dx/dt is 0.001 times v"),
    ("diagnose, NaN row", ["diagnose", "log_nan.csv", "--model", "model.json", *DIAG, "-o", OUT], "NaN"),
    ("diagnose, time steps back", ["diagnose", "log_swapped.csv", "--model", "model.json", *DIAG, "-o", OUT],
     "t goes back by"),
    ("diagnose, a time repeated", ["diagnose", "log_repeated_t.csv", "--model", "model.json", *DIAG, "-o", OUT],
     "t repeats at data rows 100 and 101"),
    ("diagnose, a current in Nm", ["diagnose", "log_units.csv", "--model", "model.json", *DIAG, "-o", OUT],
     "column 'I [Nm]' is read as i, a current, but its unit Nm is a force's: are the columns swapped?"),
    ("diagnose, a current in %", ["diagnose", "log_percent.csv", "--model", "model.json", *DIAG, "-o", OUT],
     "column 'Iq [%]' (i) is in %, a unit of no size the file gives: --scale i=FACTOR brings it to SI"),
    ("diagnose, v logged as 0", ["diagnose", "log_v_zero.csv", "--model", "model.json", *DIAG, "-o", OUT],
     "column 'v' is 0 throughout while x travels"),
    ("diagnose, x inverted", ["diagnose", "log_x_inverted.csv", "--model", "model.json", *DIAG, "-o", OUT],
     "is x or v inverted?"),
    ("diagnose, shorter than the window", ["diagnose", "log_short.csv", "--model", "model.json", *DIAG,
                                           "-o", OUT], "need at least"),
    ("diagnose, constant current", ["diagnose", "log_constant_i.csv", "--model", "model.json", *DIAG,
                                    "-o", OUT], "current i is constant"),
    ("diagnose, constant position", ["diagnose", "log_constant_x.csv", "--model", "model.json", *DIAG,
                                     "-o", OUT], "the position x is constant (1.5 m) over 98 % of the log"),
    ("train, constant position", ["train", "log_constant_x.csv", "--mass", "4", "--force-constant", "20",
                                  "-o", OUT], "the position x is constant (1.5 m) over 98 % of the log"),
    ("diagnose --max-effects 0", ["diagnose", "log.csv", "--model", "model.json", *DIAG, "--max-effects", "0",
                                  "-o", OUT], "--max-effects: must be an integer >= 1 and <= 8"),
    ("diagnose --max-effects 2.5", ["diagnose", "log.csv", "--model", "model.json", *DIAG, "--max-effects",
                                    "2.5", "-o", OUT], "--max-effects: must be an integer"),
    ("diagnose --max-effects 99", ["diagnose", "log.csv", "--model", "model.json", *DIAG, "--max-effects",
                                   "99", "-o", OUT], "<= 8"),
    ("diagnose --pitch 0", ["diagnose", "log.csv", "--model", "model.json", *DIAG, "--pitch", "0",
                            "-o", OUT], "--pitch: must be a finite number > 0 and <= 1000 m, got 0"),
    ("diagnose --pitch nan", ["diagnose", "log.csv", "--model", "model.json", *DIAG, "--pitch", "nan",
                              "-o", OUT], "--pitch: must be a finite number"),
    ("diagnose, reversed table", ["diagnose", "log.csv", "--model", "model_table.json", *DIAG, "-o", OUT],
     "hi must be > lo"),
    ("diagnose --mass 1e308", ["diagnose", "log.csv", "--model", "model.json", "--mass", "1e308",
                               "--force-constant", "20", "-o", OUT], "--mass: must be"),
    ("demo --seeds 0", ["demo", "--seeds", "0"], "--seeds: must be an integer >= 1"),
    ("reproduce --jobs 0", ["reproduce", "--jobs", "0", "-o", OUT], "--jobs: must be"),
    ("unknown option", ["train", "sweep.csv", "--nuerons", "3"], "unrecognized arguments"),
    ("log of current with neither --mass nor --force-constant", ["train", "log.csv", "-o", OUT],
     "the log has a current i but no force: it determines M/K"),
    ("log without time, read as a sweep", ["train", "log_no_time.csv", "--columns", "f=i", "-o", OUT],
     "column 'x' holds a position, and the file has no time column"),
    ("--sample-rate 0", ["train", "log_no_time.csv", "--sample-rate", "0", "-o", OUT],
     "--sample-rate: must be a finite number > 0"),
    ("--sample-rate on a timed log", ["train", "log.csv", *LOG, "--sample-rate", "1000", "-o", OUT],
     "log.csv has a time column t already"),
    ("--sample-rate with --merge", ["train", "log_no_time.csv", "--sample-rate", "1000", "--merge",
                                    "log.csv", "-o", OUT], "--sample-rate gives a file without a time"),
    ("log of force with --force-constant", ["train", "log_force.csv", *LOG, "-o", OUT],
     "--force-constant applies to a current column"),
    ("sweep with --mass", ["train", "sweep.csv", "--mass", "4", "-o", OUT], "apply to a motion log"),
    ("--mass 0", ["train", "log.csv", "--mass", "0", "-o", OUT], "--mass: must be a finite number > 0"),
    ("--force-constant inf", ["train", "log.csv", "--mass", "4", "--force-constant", "inf", "-o", OUT],
     "--force-constant: must be"),
    ("log with a gap 11 rows in (a run too short)", ["train", "jitter.csv", "--mass", "4", "-o", OUT],
     "run 1 of 2 (data rows 1 to 11, where t restarts or pauses) has 11 rows, need at least 28"),
    ("--asymmetric on one direction", ["train", "sweep.csv", "--asymmetric", "-o", OUT],
     "needs a sweep of each direction"),
    ("--asymmetric and --symmetric", ["train", "sweep.csv", "--asymmetric", "--symmetric", "-o", OUT],
     "not allowed with argument"),
    ("asymmetric ELM model as q15", ["emit", "asym.json", "--dtype", "q15", "-o", OUT],
     "curves are both grey-box"),
    ("vendor file without --skip (its preamble found), without a force", ["train", "drive.csv", "--columns",
                                                                           "t=Time,v=Speed", "--mass", "4", "-o", OUT],
     "missing force or i (header is Time,Speed)"),
    ("--skip -1", ["train", *DRIVE, "--skip", "-1", "-o", OUT], "--skip: must be an integer >= 0"),
    ("--skip past the end", ["train", "sweep.csv", "--skip", "100000", "-o", OUT], "fewer than the 100000"),
    ("--columns without =", ["train", *DRIVE, "--columns", "v", "-o", OUT], "expected NAME=VALUE"),
    ("--columns unknown quantity", ["train", *DRIVE, "--columns", "spede=Speed", "-o", OUT],
     "'spede' is not one of t, x, v, a, f, force, i"),
    ("--columns a quantity twice", ["train", *DRIVE, "--columns", "v=Time,v=Speed", "-o", OUT],
     "v is given twice"),
    ("--columns a column twice", ["train", "drive.csv", "--skip", "2", "--columns", "t=Time,x=time",
                                  "-o", OUT], "'time' is mapped to more than one quantity"),
    ("--columns a column the file lacks", ["train", "drive.csv", "--skip", "2", "--columns",
                                           "t=Time,v=Velocity", "-o", OUT],
     "--columns: v='Velocity': WORK/drive.csv has no such column (header is Time,Speed)"),
    ("--columns onto an existing name", ["train", "log.csv", *LOG, "--columns", "v=x", "-o", OUT],
     "column 'v' appears twice once the columns are named"),
    ("--scale not a number", ["train", *DRIVE, *MERGE, "--scale", "v=rpm", "-o", OUT], "is not a number"),
    ("MATLAB v7.3 file", ["train", "v73.mat", *LOG, "-o", OUT], "WORK/v73.mat: a MATLAB v7.3 (HDF5) file, "
     "which fricgen does not read; save it in MATLAB with save(FILE, '-v7')"),
    ("MATLAB file truncated", ["train", "truncated.mat", *LOG, "-o", OUT],
     "WORK/truncated.mat: not a readable MATLAB file"),
    ("MATLAB file without variables", ["train", "no_variables.mat", *LOG, "-o", OUT],
     "WORK/no_variables.mat: a MATLAB file without variables"),
    ("MATLAB file --skip", ["train", "log.mat", "--skip", "2", *LOG, "-o", OUT],
     "WORK/log.mat is a MATLAB file: it has no preamble lines to skip"),
    ("MATLAB file --merge-skip", ["train", *DRIVE, "--merge", "log.mat", "--merge-skip", "1", "-o", OUT],
     "WORK/log.mat is a MATLAB file: it has no preamble lines to skip"),
    ("MATLAB struct as column", ["train", "log.mat", "--columns", "x=meta", *LOG, "-o", OUT],
     "WORK/log.mat: variable 'meta' is a 1x1 struct; a column is a real vector (N,1) or (1,N)"),
    ("MATLAB text as column", ["train", "log.mat", "--columns", "x=note", *LOG, "-o", OUT],
     "WORK/log.mat: variable 'note' is text"),
    ("MATLAB matrix as column", ["train", "log.mat", "--columns", "x=gains", *LOG, "-o", OUT],
     "WORK/log.mat: variable 'gains' is a 3x4 matrix, not a vector"),
    ("MATLAB scalar as column", ["train", "log.mat", "--columns", "i=phi", *LOG, "-o", OUT],
     "WORK/log.mat: variable 'phi' is a scalar (1x1), not a column"),
    ("MATLAB variable the file lacks", ["train", "log.mat", "--columns", "i=current", *LOG, "-o", OUT],
     "WORK/log.mat: no variable 'current' (its vectors: t, x, v, i, x_d, short)"),
    ("MATLAB vectors of unequal length", ["train", "log.mat", "--columns", "x=short", *LOG, "-o", OUT],
     "WORK/log.mat: variables 'short' (7 values) and 't' (3001 values) differ in length"),
    ("--scale by a MATLAB variable that is no scalar", ["train", "log.mat", "--scale", "i=gains", *LOG,
                                                        "-o", OUT],
     "--scale: i='gains' is neither a number nor a scalar variable of WORK/log.mat (gains is a 3x4 "
     "matrix, not a vector) (its scalars: phi, zero)"),
    ("--scale by a MATLAB scalar of 0", ["train", "log.mat", "--scale", "i=zero", *LOG, "-o", OUT],
     "--scale: i=zero, the variable of WORK/log.mat, must be finite and not 0, got 0"),
    ("--scale by a name, of a CSV", ["train", "log.csv", "--scale", "i=phi", *LOG, "-o", OUT],
     "--scale: i='phi' is not a number"),
    ("diagnose, a MATLAB v7.3 file", ["diagnose", "v73.mat", "--model", "model.json", *DIAG, "-o", OUT],
     "WORK/v73.mat: a MATLAB v7.3 (HDF5) file"),
    ("diagnose, a force log given a force constant", ["diagnose", "log_force.csv", "--model", "model.json",
                                                      *DIAG, "-o", OUT],
     "--force-constant applies to a current column i; the log's force column is in N already"),
    ("--scale 0", ["train", *DRIVE, *MERGE, "--scale", "v=0", "-o", OUT], "must be finite and not 0"),
    ("--scale inf", ["train", *DRIVE, *MERGE, "--scale", "force=inf", "-o", OUT], "must be finite and not 0"),
    ("--scale of an unknown quantity", ["train", *DRIVE, *MERGE, "--scale", "rpm=2", "-o", OUT],
     "--scale: 'rpm' is not one of"),
    ("--merge-shift without --merge", ["train", *DRIVE, "--merge-shift", "0.004", "-o", OUT],
     "need --merge FILE"),
    ("--merge-shift nan", ["train", *DRIVE, *MERGE, "--merge-shift", "nan", "-o", OUT], "--merge-shift: must be"),
    ("--merge-shift with '_'", ["train", *DRIVE, *MERGE, "--merge-shift", "0_1", "-o", OUT],
     "--merge-shift: must be a finite number"),
    ("--merge without its time column", ["train", *DRIVE, "--merge", "load.csv", "-o", OUT],
     "no time column 't' to merge on (map one: --merge-columns t=NAME)"),
    ("--merge with no common time", ["train", *DRIVE, *MERGE, "--merge-shift", "1e5", "-o", OUT],
     "share no time span"),
    ("--merge of a column in both files", ["train", *DRIVE, "--merge", "log_force.csv", "-o", OUT],
     "column 'v' is in"),
    ("train, a log in mm with the mass in kg", ["train", "log_mm.csv", *LOG, "-o", OUT],
     "is v in mm/s? --scale v=0.001 converts it"),
    ("train, a log with i in mA", ["train", "log_mA.csv", *LOG, "-o", OUT],
     "the log accelerates as if the mass were"),
    ("train, the mass in tonnes", ["train", "log.csv", "--mass", "0.004", "--force-constant", "20", "-o", OUT],
     "the log accelerates as if the mass were"),
    ("--merge file with a NaN", ["train", *DRIVE, "--merge", "load_nan.csv", "--merge-columns",
                                 "t=Stamp,force=Load", "--merge-shift", "-0.002", "-o", OUT],
     "WORK/load_nan.csv: column 'force' holds NaN or infinite value at data row 5"),
    ("--merge-skip past the end", ["train", *DRIVE, *MERGE, "--merge-skip", "100000", "-o", OUT],
     "fewer than the 100000"),
    ("--merge file missing", ["train", *DRIVE, "--merge", "nothing.csv", "-o", OUT], "cannot read"),
    ("-o is the --merge file", ["train", *DRIVE, *MERGE, "-o", "load.csv"], "load.csv"),
    ("synth-log --magnitude 0", ["synth-log", "--effect", "constant_load", "--magnitude", "0", "-o", OUT],
     "--magnitude: must be a finite number > 0 and <= 100, got 0"),
    ("synth-log negative friction source", ["synth-log", "--effect", "extra_friction_source",
                                            "--magnitude", "-1", "-o", OUT],
     "--magnitude: must be a finite number > 0"),
    ("synth-log force constant near 0", ["synth-log", "--effect", "force_constant_mismatch", "--magnitude",
                                         "6.6", "-o", OUT],
     "--magnitude: must be a finite number > 0 and <= 5.33 for force_constant_mismatch, got 6.6"),
    ("readback, a dump of another model", ["readback", "dump_other_model.txt", "--model", "model.json",
                                            "-o", OUT], "the dump was adapted from model 0123456789abcdef"),
    ("readback, a parameter missing", ["readback", "dump_short.txt", "--model", "model.json", "-o", OUT],
     "parameters, this model adapts"),
    ("readback, a word not hex", ["readback", "dump_not_hex.txt", "--model", "model.json", "-o", OUT],
     "'3e0zcc24' is not 8 hex digits"),
    ("readback, a NaN parameter", ["readback", "dump_nan.txt", "--model", "model.json", "-o", OUT],
     "is nan, not a finite number"),
    ("readback, an adapted B that reverses the friction", ["readback", "dump_negative_b.txt", "--model",
                                                            "model.json", "-o", OUT],
     "the adapted parameters make a model that cannot be used: viscous = -"),
    ("readback, a CSV for the dump", ["readback", "sweep.csv", "--model", "model.json", "-o", OUT],
     "not an adaptation dump"),
    ("readback, no such dump", ["readback", "no_dump.txt", "--model", "model.json", "-o", OUT],
     "no_dump.txt: No such file or directory"),
    ("readback, -o the model itself", ["readback", "dump.txt", "--model", "model.json", "-o", "model.json"],
     "model.json; refusing to overwrite it (--force to do so)"),
    ("synth-log mass 5 times nominal", ["synth-log", "--effect", "inertia_mismatch", "--magnitude", "14",
                                        "-o", OUT], "<= 13.3 for inertia_mismatch, got 14"),
]


@pytest.mark.parametrize("argv, words", [r[1:] for r in TRIAL_ROWS + PLAUSIBILITY_ROWS + ROWS],
                         ids=[r[0] for r in TRIAL_ROWS + PLAUSIBILITY_ROWS + ROWS])
def test_bad_input_is_one_line_exit_2_and_nothing_written(work, tmp_path, argv, words):
    out = tmp_path / "out"
    special = {OUT: str(out), OUT + "/": str(out) + "/", "UNDER_INPUT": str(work / "sweep.csv" / "m.json")}
    argv = [special.get(a) or (str(work / a) if a and os.path.lexists(work / a) else a) for a in argv]
    words = words.replace("WORK/", f"{work}/")
    before = sorted(os.listdir(work))
    proc = subprocess.run([sys.executable, "-m", "fricgen", *argv], capture_output=True, text=True,
                          stdin=subprocess.DEVNULL, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and proc.stderr.startswith("fricgen: error: "), proc.stderr
    assert words in proc.stderr, proc.stderr
    assert proc.stdout == ""
    assert not out.exists() and sorted(os.listdir(work)) == before


@pytest.mark.parametrize("threads", ["0", "two", "1e3", "\uff12", ""])
def test_bad_blas_threads_is_one_line_exit_2_and_nothing_written(work, tmp_path, threads):
    env = dict(os.environ, FRICGEN_BLAS_THREADS=threads)
    proc = subprocess.run([sys.executable, "-m", "fricgen", "train", str(work / "sweep.csv"), "-o",
                           str(tmp_path / "m.json")], env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and proc.stderr.startswith(
        "fricgen: error: FRICGEN_BLAS_THREADS must be an integer from 1 to 1024"), proc.stderr
    assert not (tmp_path / "m.json").exists()


def test_eval_with_stdin_closed_is_one_line(work):
    proc = subprocess.run(f'"{sys.executable}" -m fricgen eval "{work / "model.json"}" <&-',
                          shell=True, capture_output=True, text=True)
    assert proc.returncode == 2 and proc.stderr == ("fricgen: error: stdin: closed; pipe velocities "
                                                    "into fricgen eval, one per line\n")


def test_a_gross_outlier_row_does_not_move_b(work, tmp_path, capsys):
    # one row 1e308,1e308 among 300 used to turn B from 58 into 1.0 N s/m
    rows = (work / "sweep.csv").read_text().splitlines()
    (tmp_path / "spiked.csv").write_text("\n".join(rows[:150] + ["1e308,1e308"] + rows[150:]) + "\n")
    assert main(["train", str(work / "sweep.csv"), "-o", str(tmp_path / "a.json"), "--vs-max", "0.02"]) == 0
    assert main(["train", str(tmp_path / "spiked.csv"), "-o", str(tmp_path / "b.json"), "--vs-max", "0.02"]) == 0
    report = capsys.readouterr().out
    assert "1 point: gross outliers" in report
    clean, spiked = (json.loads((tmp_path / n).read_text())["viscous"] for n in ("a.json", "b.json"))
    assert spiked == pytest.approx(clean, rel=1e-12)
    assert 55 < clean < 60


def test_eval_streams_with_constant_memory_and_exact_forces(work):
    # 300000 velocities through the chunked reader equal the model evaluated at once
    v = np.random.default_rng(5).uniform(-0.2, 0.2, 300_000)
    proc = subprocess.run([sys.executable, "-m", "fricgen", "eval", str(work / "model.json")],
                          input="\n".join(repr(float(x)) for x in v), capture_output=True, text=True)
    assert proc.returncode == 0
    forces = np.array(proc.stdout.split(), dtype=float)
    np.testing.assert_array_equal(forces, FrictionModel.load(work / "model.json").force(v))


@pytest.mark.parametrize("argv", [["demo", "--seeds", "1", "-o", OUT],
                                  ["simulate", "--backend", "c", "--duration", "0.1", "--plot", OUT]],
                         ids=["demo", "simulate --backend c"])
def test_no_working_c_compiler_is_one_line_and_nothing_written(tmp_path, argv):
    out = tmp_path / "out"
    env = dict(os.environ, CC="false")
    proc = subprocess.run([sys.executable, "-m", "fricgen", *[str(out) if a == OUT else a for a in argv]],
                          env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2
    errors = [line for line in proc.stderr.splitlines() if line.startswith("fricgen: error:")]
    assert errors == [proc.stderr.splitlines()[-1]] and "cannot compile the emitted C" in errors[0]
    assert "Traceback" not in proc.stderr and not out.exists()


def test_eval_of_a_model_with_effects_says_they_are_not_applied(work, tmp_path):
    model = json.loads((work / "model.json").read_text())
    model["effects"] = [{"effect": "constant_load", "parameters": {"load": 1.0}}]
    del model["model_hash"]         # removed with the edit: said, as the edit cannot be told
    (tmp_path / "m.json").write_text(json.dumps(model))
    runs = [subprocess.run([sys.executable, "-m", "fricgen", "eval", str(path)], input="0.01\n\n-0.02\n",
                           capture_output=True, text=True) for path in (work / "model.json", tmp_path / "m.json")]
    assert all(r.returncode == 0 for r in runs) and runs[0].stdout == runs[1].stdout
    assert len(runs[1].stdout.split()) == 2          # blank lines are skipped
    warning, note = runs[1].stderr.splitlines()[:2]
    assert runs[0].stderr == "" and "holds no model_hash" in warning
    assert note.startswith("fricgen: note: eval gives F(v)") and "constant_load" in note


@pytest.mark.parametrize("quantum", [0.0, 0.05], ids=["noise-free", "quantized to 0.05 N"])
def test_a_spike_is_rejected_where_most_residuals_are_zero(tmp_path, capsys, quantum):
    # noise-free or quantized force: most residuals from the running median are exactly 0, and a
    # robust scale of 0 used to reject nothing (one +50 N row gave errors of 0.5 N to 4000 N)
    v = np.linspace(0.0005, 0.08, 300)
    truth = 2.0 + 1.5 * np.exp(-(v / 0.01) ** 2) + 15.0 * v
    f = np.round(truth / quantum) * quantum if quantum else truth.copy()
    f[50] += 50.0                   # at 0.0137 m/s, within v_sat
    (tmp_path / "s.csv").write_text("v,f\n" + "\n".join(f"{a!r},{b!r}" for a, b in zip(v.tolist(), f.tolist())) + "\n")
    assert main(["train", str(tmp_path / "s.csv"), "-o", str(tmp_path / "m.json"), "--vs-max", "0.01"]) == 0
    out = capsys.readouterr().out
    assert "1 training points rejected as gross outliers" in out or "1 point: gross outliers" in out
    check = np.linspace(0.002, 0.03, 50)
    error = FrictionModel.load(tmp_path / "m.json").force(check) - (
        2.0 + 1.5 * np.exp(-(check / 0.01) ** 2) + 15.0 * check)
    assert np.max(np.abs(error)) < 0.1
