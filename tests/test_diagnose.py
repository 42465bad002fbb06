"""fricgen diagnose on logs with exactly one hidden effect (or none): the right name and nothing
more, the parameters within stated tolerances, and the held-out gap well reduced.

One vectorized simulation makes every log (10 cases x 4 settings of seed, magnitude, noise).
"""
import json
import math

import numpy as np
import pytest

from fricgen.diagnose.diagnoser import Diagnoser, diagnose
from fricgen.effects import EFFECTS, ExtraFrictionSource, Signals
from fricgen.sim.logsynth import HIDDEN_EFFECTS, LogSpec, nominal_model, synthesize_logs, truth_parameters

#: (seed, magnitude, noise scale): the reference size twice, a large effect under twice the
#: sensor noise, a half-size effect under half the noise.
SETTINGS = [(0, 1.0, 1.0), (1, 1.0, 1.0), (2, 2.0, 2.0), (3, 0.5, 0.5)]
CASES = [(e, s, m, n) for (s, m, n) in SETTINGS for e in HIDDEN_EFFECTS]
DURATION = 10.0


@pytest.fixture(scope="module")
def model():
    return nominal_model()


@pytest.fixture(scope="module")
def results(model):
    specs = [LogSpec(effect=e, seed=s, magnitude=m, noise=n, duration=DURATION) for e, s, m, n in CASES]
    logs = synthesize_logs(specs, model)
    return {case: (spec, log, diagnose(log, model, spec.mass, spec.force_constant))
            for case, spec, log in zip(CASES, specs, logs)}


def _ids():
    return [f"{e}-seed{s}-mag{m:g}-noise{n:g}" for e, s, m, n in CASES]


@pytest.mark.parametrize("case", CASES, ids=_ids())
def test_the_hidden_effect_is_named(results, case):
    spec, log, d = results[case]
    assert d.effect_ == spec.effect, [(s.effect, s.p_value, s.reason) for s in d.steps_]
    assert [s.effect for s in d.effects_] == ([] if spec.effect == "none" else [spec.effect])
    if spec.effect != "none":
        assert d.p_value_ < d.alpha and d.summary()["candidates"][0]["effect"] == spec.effect
    else:           # whatever was considered was refused, for a stated reason
        assert d.model_.effects == () and all(s.reason for s in d.steps_)


def _relative_error(fit, truth, scale):
    return abs(fit - truth) / scale


@pytest.mark.parametrize("case", [c for c in CASES if c[0] != "none"], ids=[i for i, c in zip(_ids(), CASES) if c[0] != "none"])
def test_parameters_are_recovered_within_tolerance(results, case, model):
    """The values the selection fits to the force residual. The output-error refinement that
    follows fits the simulations instead: on frictional_lag-seed3-mag0.5 it takes tau 46 % above
    the generator's, where both the fit part's and the held-out gap are smaller."""
    spec, log, d = results[case]
    fit, truth = d.selected_[0].parameters(), truth_parameters(spec)
    e = spec.effect
    if e in ("position_ripple", "position_friction"):
        assert _relative_error(fit["amplitude"], truth["amplitude"], truth["amplitude"]) < 0.10
        assert _relative_error(fit["period"], truth["period"], truth["period"]) < 0.01
        assert abs((fit["phase"] - truth["phase"] + math.pi) % (2 * math.pi) - math.pi) < 0.15
    elif e == "direction_asymmetry":
        assert abs(fit["gain_negative"] - truth["gain_negative"]) < 0.1 * truth["gain_negative"] + 0.01
        assert abs(fit["gain_positive"]) < 0.01
    elif e == "constant_load":
        assert _relative_error(fit["load"], truth["load"], truth["load"]) < 0.05
    elif e == "inertia_mismatch":        # within 15 % of the mass error
        assert _relative_error(fit["mass"], truth["mass"], truth["mass"] - spec.mass) < 0.15
    elif e == "force_constant_mismatch":  # within 10 % of the force-constant error
        assert _relative_error(fit["force_constant"], truth["force_constant"],
                               truth["force_constant"] - spec.force_constant) < 0.10
    elif e == "extra_friction_source":   # the source's force curve within 10 %, vs within 25 %
        v = np.linspace(0.005, 0.2, 200)
        sig = Signals(model, v=v)
        got = ExtraFrictionSource(**fit).force(sig)
        want = ExtraFrictionSource(**truth).force(sig)
        assert np.sqrt(np.mean((got - want) ** 2)) < 0.1 * np.sqrt(np.mean(want ** 2))
        assert _relative_error(fit["vs"], truth["vs"], truth["vs"]) < 0.25
    elif e == "frictional_lag":
        assert _relative_error(fit["tau"], truth["tau"], truth["tau"]) < 0.15
    elif e == "thermal_drift":
        assert _relative_error(fit["rate"], truth["rate"], truth["rate"]) < 0.10
    else:
        pytest.fail(f"no tolerance stated for {e}")


@pytest.mark.parametrize("case", CASES, ids=_ids())
def test_the_held_out_gap_shrinks_to_six_tenths_or_less(results, case):
    spec, log, d = results[case]
    if spec.effect == "none":           # nothing added, no change claimed
        assert d.gap_after_ == d.gap_before_ and d.fitted_ is None and d.parameters() == {}
        assert d.model_.effects == ()
    else:
        # 0.6: with the simulations driven by the smoothed current, a mass error and a lag
        # reach 0.53 on two of these logs; benchmarks/diagnose_confusion.py counts the halvings
        assert d.gap_after_ <= 0.6 * d.gap_before_, (d.gap_before_, d.gap_after_)
        assert d.force_gap_after_ < d.force_gap_before_
        assert [x["effect"] for x in d.model_.effects] == [spec.effect]


def test_where_points_at_the_effect(results):
    """The localization names the axis each effect lives on (reference magnitude, seed 0)."""
    expect = {"position_ripple": "position, periodic", "thermal_drift": "time, friction level",
              "direction_asymmetry": "direction of motion", "extra_friction_source": "speed"}
    for effect, axis in expect.items():
        spec, log, d = results[(effect, 0, 1.0, 1.0)]
        assert d.where_.startswith(axis), d.where_
        assert d.localization_[0]["share"] > 0.5, (effect, d.localization_[0])
    spec, log, d = results[("none", 0, 1.0, 1.0)]
    assert d.where_.startswith("nowhere"), d.where_


def test_a_second_diagnosis_of_the_augmented_model_finds_nothing_more(results, model):
    spec, log, d = results[("position_ripple", 0, 1.0, 1.0)]
    again = diagnose(log, d.model_, spec.mass, spec.force_constant)
    assert again.effect_ == "none"
    assert again.gap_before_ == pytest.approx(d.gap_after_, rel=1e-9)


def test_summary_has_the_documented_keys(results):
    spec, log, d = results[("constant_load", 0, 1.0, 1.0)]
    s = d.summary()
    assert list(s) == ["effect", "p_value", "parameters", "effects", "refused", "where", "where_after",
                       "gap_before", "gap_after", "gap_selected", "fit_gap_before", "fit_gap_after", "gap_metric", "alpha", "min_size", "min_gain", "candidates"]
    # every named effect but those asked for is a candidate; the truth axes hide each but the
    # sensor delay and the saturation (the scenario generator's oov:sensor_delay and
    # oov:actuator_saturation, tests/test_sensor_delay.py, tests/test_actuator_saturation.py)
    # and the pre-sliding (static plants; tests/test_diagnose_bristles.py)
    from fricgen.diagnose.diagnoser import ASKED_FOR
    assert ASKED_FOR == ("sensor_delay", "actuator_saturation", "presliding")
    assert {c["effect"] for c in s["candidates"]} | {"none"} == set(EFFECTS) - set(ASKED_FOR) | {"none"}
    assert set(EFFECTS) | {"none"} == set(HIDDEN_EFFECTS) | {"sensor_delay", "actuator_saturation", "presliding"}
    first = s["effects"][0]
    assert first["effect"] == s["effect"] and first["parameters"] == s["parameters"]
    assert first["p_value"] == s["p_value"] < s["alpha"] and 0.5 < first["share"] <= 1.0
    # the steps hold the selection's gaps (gap_after is the refined one)
    assert first["held_out_gain"] == pytest.approx(1 - s["gap_selected"] / s["gap_before"])
    assert all(r["reason"] for r in s["refused"])
    # each refusal names the effects it was fitted with: the load for those after it, none for
    # the first step's alternatives to the load; one that passed names the load it gave way to
    assert any("constant_load" in r["beside"] for r in s["refused"])
    for r in s["refused"]:
        assert r["effect"] not in r["beside"]
        assert "constant_load" in r["beside"] or r["beside"] == []
        assert not r["reason"].startswith("passes") or "constant_load" in r["reason"]
    json.dumps(s)


def test_invalid_settings_are_refused(results):
    spec, log, d = results[("none", 0, 1.0, 1.0)]
    with pytest.raises(ValueError, match="holdout"):
        Diagnoser(holdout=0.9).fit(log, d.problem_.signals.model, 4.0, 20.0)
    with pytest.raises(ValueError, match="candidates"):
        Diagnoser(candidates=["gremlins"]).fit(log, d.problem_.signals.model, 4.0, 20.0)
    for bad in (0, 9, 2.5, True):
        with pytest.raises(ValueError, match="max_effects"):
            Diagnoser(max_effects=bad).fit(log, d.problem_.signals.model, 4.0, 20.0)
    with pytest.raises(ValueError, match="alpha"):
        Diagnoser(alpha=0.0).fit(log, d.problem_.signals.model, 4.0, 20.0)


@pytest.mark.parametrize("p, sentence, cell", [(0.0012, "p = 0.0012", "0.0012"), (0.0, "p < 1e-300", "< 1e-300"),
                                                (0.5, "p = 0.5", "0.5")])
def test_a_p_value_that_underflows_is_written_as_a_bound(p, sentence, cell):
    from fricgen.diagnose.decision import p_text, p_value_text
    assert p_text(p) == sentence and p_value_text(p) == cell
