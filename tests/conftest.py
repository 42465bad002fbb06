"""Shared fixtures: the paper benchmark and fitted models of every headline kind."""
import pytest

from fricgen.data import synthesize_benchmark
from fricgen.fit import ELMRegressor, default_estimator as default_elm
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


@pytest.fixture(scope="session")
def model10(bench):
    """A 10-neuron enlarged ELM with C by leave-one-out: the firmware and fixed-point model."""
    return fit_model(bench, n_hidden=10, scheme=EnlargedScheme(w_max=30.0), solver="loo")


@pytest.fixture(scope="session")
def xt(bench):
    """The benchmark's eq. (9) training data (x, t)."""
    return bench.dataset.x, bench.dataset.t


#: Tests of more than a few seconds (wheel install, cross builds under QEMU, sanitizer fuzz, the
#: quick paper reproduction, the diagnosis matrix, long closed loops): ``-m "not slow"`` skips them.
SLOW_MODULES = {"test_install", "test_firmware", "test_hardening", "test_experiments"}
SLOW_TESTS = {"test_the_hidden_effect_is_named",
              "test_errors_and_parameters_stay_bounded_under_law_c_with_a_constant_disturbance",
              "test_closed_loop_c_equals_float32_twin_and_float64_controller"}


def pytest_collection_modifyitems(config, items):
    for item in items:
        if item.module.__name__.rpartition(".")[2] in SLOW_MODULES or item.originalname in SLOW_TESTS:
            item.add_marker(pytest.mark.slow)
