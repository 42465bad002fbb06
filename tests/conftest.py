"""Shared fixtures: the paper benchmark and fitted models of every headline kind."""
import numpy as np
import pytest

from fricgen.data import synthesize_benchmark
from fricgen.fit import ELMRegressor, default_estimator as default_elm
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
