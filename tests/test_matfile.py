"""MATLAB files as exports: vectors as columns, scalars as --scale factors, the bad files refused."""
import json

import numpy as np
import pytest
from scipy.io import savemat

from fricgen.cli import main
from fricgen.data import read_log, read_log_csv
from fricgen.data.export import ExportLayout, merge_on_time, parse_scales, read_export
from fricgen.data.matfile import is_matfile, read_matfile
from fricgen.data.table import table_csv_text
from fricgen.errors import DataError, UsageError
from fricgen.sim.logsynth import LogSpec, synthesize_log

GTAU = 35.15        # N/V, as EMPS's gtau
N = 50


def _emps_like(path, **more):
    """A small file of EMPS's layout (t, qm, vir, gtau) and the variables no column is made of."""
    rng = np.random.default_rng(0)
    variables = {"t": np.arange(N) * 1e-3, "qm": rng.normal(size=(N, 1)), "vir": rng.normal(size=(1, N)),
                 "counts": np.arange(N, dtype=np.int16), "gtau": GTAU, "kp": np.array([[2.0]]),
                 "note": "EMPS-like", "meta": {"rate": 1000.0}, "gains": np.ones((3, 4)),
                 "cells": np.array([1, "a"], dtype=object), "short": np.arange(7.0)}
    variables.update(more)
    savemat(path, variables)
    return variables


def test_vectors_are_columns_and_scalars_are_not(tmp_path):
    written = _emps_like(tmp_path / "e.mat")
    mat = read_matfile(tmp_path / "e.mat")
    assert mat.scalars == {"gtau": GTAU, "kp": 2.0}
    assert set(mat.vectors) == {"t", "qm", "vir", "counts", "short"}
    assert mat.others["gains"] == "a 3x4 matrix, not a vector"
    columns = read_export(tmp_path / "e.mat", ExportLayout(columns={"x": "qm", "force": "VIR"}))
    assert set(columns) == {"t", "x", "force", "counts"}        # 'short' is of another length
    np.testing.assert_array_equal(columns["t"], written["t"])
    np.testing.assert_array_equal(columns["x"], written["qm"].ravel())
    np.testing.assert_array_equal(columns["force"], written["vir"].ravel())
    np.testing.assert_array_equal(columns["counts"], np.arange(N, dtype=float))


def test_scale_by_a_scalar_variable_multiplies_by_its_value(tmp_path):
    written = _emps_like(tmp_path / "e.mat")
    layout = ExportLayout(columns={"x": "qm", "force": "vir"})
    scales = parse_scales(["force=gtau,x=1e-3"])
    assert scales == {"force": "gtau", "x": 1e-3}
    columns = read_export(tmp_path / "e.mat", layout, scales)
    np.testing.assert_array_equal(columns["force"], written["vir"].ravel() * GTAU)
    np.testing.assert_array_equal(columns["x"], written["qm"].ravel() * 1e-3)


def test_a_matlab_file_is_known_by_its_header_under_any_name(tmp_path):
    _emps_like(tmp_path / "e.mat")
    (tmp_path / "e.dat").write_bytes((tmp_path / "e.mat").read_bytes())
    (tmp_path / "e.csv").write_text("t,x\n0,1\n")
    assert is_matfile(tmp_path / "e.dat") and not is_matfile(tmp_path / "e.csv")
    layout = ExportLayout(columns={"x": "qm"})
    a, b = (read_export(tmp_path / name, layout) for name in ("e.mat", "e.dat"))
    assert a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)


def test_a_matlab_file_merges_with_a_csv_on_time(tmp_path):
    written = _emps_like(tmp_path / "e.mat")
    t = written["t"]
    (tmp_path / "cell.csv").write_text(table_csv_text({"stamp": t, "load": 3 * t}))
    first = read_export(tmp_path / "e.mat", ExportLayout(columns={"x": "qm"}))
    second = read_export(tmp_path / "cell.csv", ExportLayout(columns={"t": "stamp", "force": "load"}))
    merged = merge_on_time(first, second, names=("e.mat", "cell.csv"))
    np.testing.assert_array_equal(merged["x"], written["qm"].ravel())
    np.testing.assert_allclose(merged["force"], 3 * t, rtol=1e-12)


@pytest.mark.parametrize("layout, scales, error, words", [
    ({"x": "gains"}, {}, DataError, "variable 'gains' is a 3x4 matrix, not a vector"),
    ({"x": "meta"}, {}, DataError, "variable 'meta' is a 1x1 struct"),
    ({"x": "note"}, {}, DataError, "variable 'note' is text"),
    ({"x": "cells"}, {}, DataError, "variable 'cells' is a 1x2 cell array"),
    ({"x": "gtau"}, {}, DataError, "variable 'gtau' is a scalar (1x1), not a column"),
    ({"x": "qq"}, {}, DataError, "no variable 'qq' (its vectors: t, qm, vir, counts, short)"),
    ({"x": "short"}, {}, DataError, "variables 'short' (7 values) and 't' (50 values) differ in length"),
    ({"force": "vir"}, {"force": "kv"}, UsageError,
     "--scale: force='kv' is neither a number nor a scalar variable of FILE (its scalars: gtau, kp)"),
    ({"force": "vir"}, {"force": "gains"}, UsageError, "(gains is a 3x4 matrix, not a vector)"),
])
def test_a_variable_that_cannot_serve_is_named_with_its_shape(tmp_path, layout, scales, error, words):
    _emps_like(tmp_path / "e.mat")
    with pytest.raises(error) as info:
        read_export(tmp_path / "e.mat", ExportLayout(columns=layout), scales)
    assert words.replace("FILE", str(tmp_path / "e.mat")) in str(info.value)
    assert "\n" not in str(info.value)


def test_a_name_as_factor_of_a_csv_is_not_a_number(tmp_path):
    (tmp_path / "s.csv").write_text("v,f\n1,2\n2,3\n")
    with pytest.raises(UsageError, match=r"^--scale: f='gtau' is not a number$"):
        read_export(tmp_path / "s.csv", scales={"f": "gtau"})


def test_a_zero_scalar_is_no_factor(tmp_path):
    _emps_like(tmp_path / "e.mat", zero=0.0)
    with pytest.raises(UsageError, match="force=zero, the variable of .* must be finite and not 0, got 0"):
        read_export(tmp_path / "e.mat", ExportLayout(columns={"force": "vir"}), {"force": "zero"})


def test_names_that_differ_only_in_case_are_refused(tmp_path):
    savemat(tmp_path / "c.mat", {"T": np.arange(3.0), "t": np.arange(3.0)})
    with pytest.raises(DataError, match="variables 'T' and 't' differ only in case"):
        read_matfile(tmp_path / "c.mat")


@pytest.fixture(scope="module")
def log_files(tmp_path_factory):
    """One synthesized log (3 s, 1 kHz) as CSV, and as a MATLAB file of a vendor's names with
    the current in mA and the factor to A as a scalar variable."""
    d = tmp_path_factory.mktemp("matlog")
    log = synthesize_log(LogSpec(duration=3.0))
    milli = log.i * 1e3
    (d / "log.csv").write_text(table_csv_text({"t": log.t, "x": log.x, "v": log.v, "i": milli * 1e-3}))
    savemat(d / "log.mat", {"time": log.t[:, None], "pos": log.x[:, None], "vel": log.v[:, None],
                            "cur_mA": milli[:, None], "mA": 1e-3})
    savemat(d / "pos.mat", {"time": log.t, "pos": log.x, "vel": log.v})
    savemat(d / "drive.mat", {"stamp": log.t, "cur_mA": milli, "mA": 1e-3})
    savemat(d / "named.mat", {"t": log.t, "x": log.x, "v": log.v, "i": log.i, "x_d": log.extra["x_d"]})
    (d / "named.csv").write_text(table_csv_text({"t": log.t, "x": log.x, "v": log.v, "i": log.i,
                                                 "x_d": log.extra["x_d"]}))
    return d


def test_training_on_a_matlab_file_equals_training_on_the_csv(log_files, tmp_path):
    # the same log as one CSV, one MATLAB file, and two MATLAB files merged on their (equal) clocks
    common = ["--mass", "4", "--force-constant", "20", "--method", "elm", "--neurons", "12",
              "--vs-max", "0.02", "--symmetric"]
    assert main(["train", str(log_files / "log.csv"), *common, "-o", str(tmp_path / "csv.json")]) == 0
    assert main(["train", str(log_files / "log.mat"), "--columns", "t=time,x=pos,v=vel,i=cur_mA",
                 "--scale", "i=mA", *common, "-o", str(tmp_path / "mat.json")]) == 0
    assert main(["train", str(log_files / "pos.mat"), "--columns", "t=time,x=pos,v=vel", "--merge",
                 str(log_files / "drive.mat"), "--merge-columns", "t=stamp,i=cur_mA", "--scale", "i=mA",
                 *common, "-o", str(tmp_path / "merged.json")]) == 0
    models = [json.loads((tmp_path / name).read_text()) for name in ("csv.json", "mat.json", "merged.json")]
    assert [m["training"].pop("source") for m in models] == ["log.csv", "log.mat", "pos.mat"]
    assert models[0] == models[1] == models[2]


def test_diagnose_reads_a_log_from_a_matlab_file(log_files):
    mat, csv = read_log(log_files / "named.mat"), read_log_csv(log_files / "named.csv")
    for k in ("t", "x", "v", "i"):
        np.testing.assert_array_equal(getattr(mat, k), getattr(csv, k))
    assert mat.extra.keys() == csv.extra.keys() == {"x_d"}
    with pytest.raises(DataError, match="log.mat: no variable 't'"):
        read_log(log_files / "log.mat")
