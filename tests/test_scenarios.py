"""The randomized test-log generator (fricgen.sim.scenarios)."""
import numpy as np
import pytest

from fricgen.data import MotionLog
from fricgen.effects import EFFECTS
from fricgen.model import FrictionModel
from fricgen.sim.scenarios import NAMED, OUT_OF_VOCABULARY, Scenario, make_scenario


def test_named_effects_are_the_vocabulary():
    assert set(NAMED) == set(EFFECTS)
    assert not set(OUT_OF_VOCABULARY) & set(EFFECTS)


def test_scenario_shape_and_determinism():
    a = make_scenario(3, ("constant_load",), duration_s=5.0, rate_hz=500.0)
    b = make_scenario(3, ("constant_load",), duration_s=5.0, rate_hz=500.0)
    assert isinstance(a, Scenario) and isinstance(a.log, MotionLog)
    assert isinstance(a.model, FrictionModel)
    assert a.hidden == ("constant_load",)
    assert np.array_equal(a.log.i, b.log.i) and np.array_equal(a.log.x, b.log.x)
    assert a.conditions == b.conditions


def test_hidden_effect_changes_the_log():
    null = make_scenario(4, (), duration_s=5.0, rate_hz=500.0)
    load = make_scenario(4, ("constant_load",), duration_s=5.0, rate_hz=500.0)
    shift = float(np.mean(load.log.i - null.log.i)) * load.force_constant
    assert abs(shift) > 0.1 * null.conditions["plant"]["coulomb"]


@pytest.mark.parametrize("bad", [("nope",), ("constant_load", "constant_load")])
def test_bad_hidden_names(bad):
    with pytest.raises(ValueError):
        make_scenario(0, bad, duration_s=5.0)
