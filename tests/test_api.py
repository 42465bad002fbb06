"""The public API: every exported name imports, the documented ones carry numpydoc sections that
name every argument, their examples run (doctest), and ``import fricgen`` loads no numerics."""
import doctest
import importlib
import inspect
import re
import subprocess
import sys

import numpy as np
import pytest

import fricgen

#: Modules whose docstring examples run here.
DOCTESTED = ["fricgen", "fricgen.fleet.manifest", "fricgen.fleet.identification", "fricgen.fleet.drift", "fricgen.fleet.store", "fricgen.fleet.run", "fricgen.training.report", "fricgen.training.trainer", "fricgen.model", "fricgen.direction", "fricgen.effects.presliding", "fricgen.c_names", "fricgen.errors", "fricgen.friction",
             "fricgen.data.sweep", "fricgen.data.motionlog", "fricgen.data.benchmark",
             "fricgen.data.training_set", "fricgen.data.stribeck_range", "fricgen.data.viscous",
             "fricgen.fit", "fricgen.fit.base", "fricgen.fit.elm", "fricgen.fit.auto",
             "fricgen.fit.stribeck", "fricgen.fit.default", "fricgen.fit.anfis",
             "fricgen.fit.conditioning", "fricgen.fit.oracle", "fricgen.networks",
             "fricgen.networks.elm", "fricgen.networks.anfis", "fricgen.networks.stribeck",
             "fricgen.effects.base", "fricgen.effects.carried", "fricgen.effects.mechanical", "fricgen.effects.position_series", "fricgen.effects.friction_changes", "fricgen.effects.signals", "fricgen.effects.tables",
             "fricgen.effects.timing", "fricgen.effects.actuator", "fricgen.effects.contact", "fricgen.effects.cogging_map", "fricgen.fit.cogging",
             "fricgen.codegen.render", "fricgen.codegen.package", "fricgen.control.loop", "fricgen.control.backstepping",
             "fricgen.control.c_controller", "fricgen.diagnose.diagnoser", "fricgen.diagnose.report",
             "fricgen.sim.axis", "fricgen.sim.logsynth", "fricgen.sim.scenarios",
             "fricgen.firmware.build", "fricgen.firmware.flag_matrix", "fricgen.paper.experiments",
             "fricgen.paper.report", "fricgen.paper.figures"]
#: Public objects held to numpydoc: Parameters naming every argument, and Examples.
NUMPYDOC = ["train", "FitReport", "FrictionModel", "FrictionModel.force", "FrictionModel.save",
            "FrictionModel.load"]
SUBPACKAGES = ["fit", "data", "codegen", "networks", "effects", "sim", "control", "diagnose",
               "firmware", "paper"]


def test_every_public_name_imports_and_has_a_docstring():
    assert "train" in fricgen.__all__ and "FrictionModel" in fricgen.__all__
    for name in fricgen.__all__:
        value = getattr(fricgen, name)
        assert name == "__version__" or inspect.getdoc(value), name
    for package in SUBPACKAGES:
        module = importlib.import_module(f"fricgen.{package}")
        assert module.__all__, package
        for name in module.__all__:
            assert hasattr(module, name), f"fricgen.{package}.{name}"


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'trian'"):
        fricgen.trian


def test_import_fricgen_and_help_load_no_numpy():
    code = ("import sys, fricgen, fricgen.cli; fricgen.cli.build_parser(['--help']); "
            "print('numpy' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"


def _section(doc: str, title: str) -> str:
    match = re.search(rf"^{title}\n-+\n(.*?)(?=^\w[\w ]*\n-+\n|\Z)", doc, flags=re.S | re.M)
    return match.group(1) if match else ""


def _object(path: str):
    value = fricgen
    for part in path.split("."):
        value = getattr(value, part)
    return value


@pytest.mark.parametrize("path", NUMPYDOC)
def test_numpydoc_names_every_argument(path):
    value = _object(path)
    doc = inspect.getdoc(value)
    arguments = [p for p in inspect.signature(value).parameters if p not in ("self", "cls")]
    documented = re.findall(r"^(\w+) :", _section(doc, "Parameters") + _section(doc, "Attributes"),
                            flags=re.M)
    assert [a for a in arguments if a not in documented] == [], path
    if not path.count("."):
        assert ">>>" in _section(doc, "Examples"), path


def test_the_numpydoc_check_sees_an_undocumented_argument():
    def f(a, b):
        """Do.

        Parameters
        ----------
        a : int
        """
    documented = re.findall(r"^(\w+) :", _section(inspect.getdoc(f), "Parameters"), flags=re.M)
    assert documented == ["a"]


@pytest.mark.parametrize("name", DOCTESTED)
def test_docstring_examples_run(name, tmp_path):
    module = importlib.import_module(name)
    result = doctest.testmod(module, extraglobs={"tmp": tmp_path}, optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0 and result.failed == 0, result


def test_the_api_checks_the_data_as_the_command_line_does(tmp_path, capsys):
    """A current in mA read as A: fricgen.train warns with the line fricgen train prints;
    checks=False leaves the checks out."""
    import warnings
    from fricgen.cli import main
    from fricgen.data.table import table_csv_text
    from fricgen.friction import preset
    from fricgen.sim.identification import SweepRun, simulate_sweep_run
    s = simulate_sweep_run(preset("paper3"), SweepRun(duration=4.0, rate=1000.0))
    columns = {"t": s["t"], "v": s["v"], "i": 1000 * s["force"] / 20.0}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fricgen.train(columns, force_constant=20.0, estimator=fricgen.StribeckRegressor(),
                      source="log.csv")
    api = [str(w.message) for w in caught if "mA" in str(w.message)]
    (tmp_path / "log.csv").write_text(table_csv_text(columns))
    assert main(["train", str(tmp_path / "log.csv"), "--force-constant", "20", "--method",
                 "stribeck", "-o", str(tmp_path / "m.json")]) == 0
    cli = [line for line in capsys.readouterr().err.splitlines() if "mA" in line]
    assert len(api) == 1 and len(cli) == 1
    assert api[0].split("log.csv")[-1] == cli[0].split("log.csv")[-1]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fricgen.train(columns, force_constant=20.0, estimator=fricgen.StribeckRegressor(),
                      checks=False)
    assert not [w for w in caught if "mA" in str(w.message)]


def test_the_api_reads_a_mappings_names_as_a_files_header_is_read():
    """A joint's q, dq, tau (a rotary axis, as the header names it) and a sweep's upper-case F
    train as t, x, v, force and v, f do; two names equal in lower case are refused."""
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 4.0, 4e-3)
    q = 0.5 * np.sin(2.0 * np.pi * 0.5 * t)
    dq = np.gradient(q, t)
    tau = 0.05 * np.gradient(dq, t) + 0.3 * np.tanh(dq / 1e-3) + 0.2 * dq + 0.002 * rng.standard_normal(t.size)
    as_joint = fricgen.train({"t": t, "q": q, "dq": dq, "tau": tau}, warn=lambda line: None)
    as_quantities = fricgen.train({"t": t, "x": q, "v": dq, "force": tau}, rotary=True,
                                  warn=lambda line: None)
    assert as_joint.training["units"] == as_quantities.training["units"] == "rotary"
    grid = np.linspace(-2.0, 2.0, 41)
    np.testing.assert_array_equal(as_joint.model.force(grid), as_quantities.model.force(grid))
    v = np.concatenate([np.geomspace(0.01, 1.0, 8), -np.geomspace(0.01, 1.0, 8)])
    f = np.sign(v) * 2.0 + 3.0 * v
    np.testing.assert_array_equal(fricgen.train({"V": v, "F": f}).model.force(grid),
                                  fricgen.train({"v": v, "f": f}).model.force(grid))
    with pytest.raises(fricgen.DataError, match="two columns are named 'f'"):
        fricgen.train({"v": v, "f": f, "F": f})
