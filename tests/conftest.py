"""Shared fixtures: the paper benchmark and fitted models of every headline kind, and the
emitted C implementations of a model with their Python twins."""
import shutil
import subprocess

import numpy as np
import pytest

from fricgen import codegen
from fricgen.codegen import fixedpoint as fx
from fricgen.codegen.cbuild import STRICT_WARNINGS
from fricgen.codegen.twin import force_f32
from fricgen.data import synthesize_benchmark
from fricgen.fit import ELMRegressor, default_elm
from fricgen.fit.elm import EnlargedScheme
from fricgen.friction import preset
from fricgen.model import FrictionModel


@pytest.fixture(scope="session")
def paper_friction():
    return preset("paper3")


@pytest.fixture(scope="session")
def bench(paper_friction):
    return synthesize_benchmark(paper_friction, seed=0)


def fit_model(bench, name="fm", **elm):
    """A FrictionModel fitted to the benchmark with the given ELM options (default: fricgen's)."""
    estimator = ELMRegressor(random_state=0, **elm) if elm else default_elm(0)
    return FrictionModel.fit(bench.dataset, estimator, name=name)


@pytest.fixture(scope="session")
def default_model(bench):
    return fit_model(bench)


def with_axis(model, offset, speed_max=0.3):
    """``model`` with the axis record ``fricgen train`` writes (speeds 1 mm/s to ``speed_max``),
    holding the constant force ``offset`` (N): its adaptation adapts the offset too."""
    from dataclasses import replace

    from fricgen.axis import Axis
    axis = Axis(speed_min=1e-3, speed_max=speed_max, offset=offset).to_dict()
    return replace(model, training={**model.training, "axis": axis})


@pytest.fixture(scope="session")
def offset_model(default_model):
    """The default model with a recorded axis whose offset is 1.5 N."""
    return with_axis(default_model, 1.5)


@pytest.fixture(scope="session")
def model10(bench):
    """A 10-neuron enlarged ELM with C by leave-one-out: the firmware and fixed-point model."""
    return fit_model(bench, n_hidden=10, scheme=EnlargedScheme(w_max=30.0), solver="loo")


@pytest.fixture(scope="session")
def axis2_model():
    """A second axis beside model10: 6 neurons fitted to the exponential-Stribeck variant of the
    benchmark (another noise draw), so its forces differ from model10's everywhere but at 0."""
    other = synthesize_benchmark(preset("paper3", "exponential"), seed=1)
    return fit_model(other, name="axis2", n_hidden=6, scheme=EnlargedScheme(w_max=20.0), solver="loo")


#: The C implementations of a model: float with libm's expf or the fast sigmoid, fixed point.
IMPLEMENTATIONS = ("libm", "fast", "q15", "q31")
#: Two models emitted into one folder and linked into one program: each implementation beside
#: itself, and mixtures of implementations in one folder.
AXIS_PAIRS = [(impl, impl) for impl in IMPLEMENTATIONS] + [("libm", "fast"), ("q15", "q31"), ("fast", "q15")]
#: The C type of each implementation's input and output.
CTYPES = {"libm": "float", "fast": "float", "q15": "int16_t", "q31": "int32_t"}


def emit_impl(model, folder, name, impl):
    """Emit ``model`` as ``name`` into ``folder`` in the implementation ``impl``."""
    options = {"activation_impl": impl} if CTYPES[impl] == "float" else {"dtype": impl}
    return codegen.emit(model, folder, name, **options)


def force_fn(name, impl):
    """The emitted force function of model ``name`` in implementation ``impl``."""
    return f"{name}_force" if CTYPES[impl] == "float" else f"{name}_force_{impl}"


def impl_inputs(model, impl, v):
    """The velocities ``v`` (m/s) as the inputs of ``impl``: float32, or fixed-point integers."""
    if CTYPES[impl] == "float":
        return np.asarray(v, dtype=np.float32)
    spec = fx.FixedSpec.of(model, impl)
    return fx.to_fixed(v, spec.f_v, spec.bits)


def impl_twin(model, impl, inputs):
    """The Python twin of ``impl``: float32 forces, or the fixed-point integers."""
    if CTYPES[impl] == "float":
        return force_f32(model, inputs, impl)
    return fx.force_q(fx.FixedSpec.of(model, impl), inputs)


@pytest.fixture(scope="session")
def cli_inputs(tmp_path_factory):
    """What a user has after the documented workflow: sweep.csv (fricgen synth), model.json
    (fricgen train on it) and log.csv (fricgen synth-log, 3 s). Copy it before changing it."""
    from fricgen.cli import main
    d = tmp_path_factory.mktemp("cli_inputs")
    assert main(["synth", "-o", str(d / "sweep.csv")]) == 0
    assert main(["train", str(d / "sweep.csv"), "-o", str(d / "model.json"), "--vs-max", "0.02",
                 "--method", "elm_auto"]) == 0
    assert main(["synth-log", "--duration", "3", "-o", str(d / "log.csv")]) == 0
    return d


def copy_of(folder, target):
    """A fresh copy of the files of ``folder`` in the new folder ``target``."""
    shutil.copytree(folder, target)
    return target


@pytest.fixture(scope="session")
def xt(bench):
    """The benchmark's [F9] training data (x, t)."""
    return bench.dataset.x, bench.dataset.t


@pytest.fixture(scope="session")
def null_problem():
    """The residual problem of [C1] of an 8 s synthesized log with nothing hidden, under the
    nominal model (the effects' fits are tested on targets built on it)."""
    from fricgen.diagnose.residual import ResidualProblem
    from fricgen.sim.logsynth import LogSpec, nominal_model, synthesize_log
    model = nominal_model()
    spec = LogSpec(effect="none", seed=5, duration=8.0)
    log = synthesize_log(spec, model)
    return ResidualProblem(log, model, spec.mass, spec.force_constant, 21, 0.3)


#: Tests of more than a few seconds (wheel install, cross builds under QEMU, sanitizer fuzz, the
#: quick paper reproduction, the diagnosis matrices: test_diagnose's 40 logs took 400 s on a busy
#: 2-core machine, long closed loops): ``-m "not slow"`` skips them.
SLOW_MODULES = {"test_install", "test_firmware", "test_flag_matrix", "test_hardening", "test_experiments",
                "test_bad_input",
                "test_diagnose", "test_diagnose_scenarios", "test_static_c"}
SLOW_TESTS = {"test_emulated_asymmetric_fast_model_is_bit_equal_to_python_twin",
              "test_errors_and_parameters_stay_bounded_under_law_c_with_a_constant_disturbance",
              "test_closed_loop_c_equals_float32_twin_and_float64_controller",
              "test_long_logs_are_feasible",
              "test_grey_box_firmware_on_the_emulated_cortex_m4f_equals_its_twin",
              "test_the_folder_builds_as_a_cmake_library_of_two_axes",
              "test_the_zephyr_branch_builds_with_zephyrs_library_functions_stubbed",
              "test_run_ups_of_the_independent_simulator_succeed_over_noise_draws",
              # the scenario diagnoses of tests/test_sensor_delay.py (six 15 s logs)
              "test_a_hidden_sensor_delay_is_named", "test_a_hidden_frictional_lag_is_named_as_itself",
              "test_the_delay_is_considered_only_when_asked_for",
              "test_the_cli_considers_the_delay_with_its_flag"}


def pytest_collection_modifyitems(config, items):
    for item in items:
        module = getattr(item, "module", None)             # a doctest item has none
        if module is None:
            continue
        if module.__name__.rpartition(".")[2] in SLOW_MODULES or item.originalname in SLOW_TESTS:
            item.add_marker(pytest.mark.slow)


def assert_builds_strictly(folder, source, cc) -> None:
    """``source`` in ``folder`` compiles with ``cc -std=c99`` and the strict warning flags of the
    emitted C, without a single warning."""
    proc = subprocess.run([cc, "-std=c99", *STRICT_WARNINGS, "-c", str(source), "-o", "/dev/null"],
                          cwd=folder, capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr


def assert_cli_names_only_with(flag: str, effect: str, scenario, folder) -> None:
    """``fricgen diagnose`` on the scenario's log saves ``effect`` in model.json with ``flag``
    and not without it."""
    import json
    from fricgen.cli import main
    from fricgen.data.motionlog import log_csv_text
    model_path, log_path = folder / "model.json", folder / "log.csv"
    scenario.model.save(model_path)
    log_path.write_text(log_csv_text(scenario.log))
    common = [str(log_path), "--model", str(model_path), "--mass", str(scenario.mass),
              "--force-constant", str(scenario.force_constant), "--json"]
    for flags, named in (([], False), ([flag], True)):
        out = folder / ("with" if flags else "without")
        assert main(["diagnose", *common, *flags, "-o", str(out)]) == 0
        saved = json.loads((out / "model.json").read_text())
        assert (effect in [e["effect"] for e in saved.get("effects", [])]) == named, flags
