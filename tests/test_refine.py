"""The output-error refinement of the selected effects (fricgen.diagnose.refine)."""
from dataclasses import replace

import numpy as np
import pytest

from fricgen.diagnose.diagnoser import Diagnoser
from fricgen.diagnose.refine import MAX_SEGMENTS, _free, fit_part_segments, output_error_fit
from fricgen.diagnose.residual import ResidualProblem
from fricgen.effects import ConstantLoad, ExtraFrictionSource, ForceConstantMismatch, ThermalDrift
from fricgen.effects.tables import TABLES
from fricgen.sim.logsynth import LogSpec, nominal_model, synthesize_log, truth_effects
from fricgen.sim.scenarios import make_scenario

HORIZON, SUBSTEPS = 20, 4


@pytest.fixture(scope="module")
def phi_log():
    """A log of an axis whose force constant is off the nominal one, the model and the truth."""
    model = nominal_model()
    spec = LogSpec(effect="force_constant_mismatch", seed=3, duration=6.0)
    return synthesize_log(spec, model), model, spec, truth_effects(spec)[0]


def problem_of(log, model, spec):
    return ResidualProblem(log, model, spec.mass, spec.force_constant, 21, 0.3)


def test_a_force_constant_off_the_truth_is_drawn_back_to_it(phi_log):
    log, model, spec, truth = phi_log
    p = problem_of(log, model, spec)
    start = replace(truth, force_constant=1.04 * truth.force_constant)
    (refined,), before, after = output_error_fit(p, [], [start], HORIZON, SUBSTEPS)
    assert after < 0.8 * before
    assert abs(refined.force_constant - truth.force_constant) < 0.25 * abs(
        start.force_constant - truth.force_constant)
    assert refined.nominal_force_constant == truth.nominal_force_constant     # fixed: kept


def test_the_held_out_part_is_not_read(phi_log):
    """Scrambling the current of the held-out part leaves the refined values bit for bit."""
    log, model, spec, truth = phi_log
    p = problem_of(log, model, spec)
    scrambled = log.i.copy()
    scrambled[p.split:] = np.random.default_rng(0).permutation(scrambled[p.split:])
    q = problem_of(replace(log, i=scrambled), model, spec)
    start = [replace(truth, force_constant=1.04 * truth.force_constant)]
    a = output_error_fit(p, [], start, HORIZON, SUBSTEPS)
    b = output_error_fit(q, [], start, HORIZON, SUBSTEPS)
    assert a[0][0].force_constant == b[0][0].force_constant
    assert a[1:] == b[1:]
    starts = fit_part_segments(p, HORIZON)
    assert starts.max() + HORIZON + p.window // 2 < p.split


def test_long_fit_parts_are_spread_over_at_most_max_segments():
    p = type("P", (), {"split": 10 ** 6, "window": 21})()
    starts = fit_part_segments(p, 7)
    assert starts.size == MAX_SEGMENTS and starts[0] == 0
    assert np.all(np.diff(starts) >= 7) and starts[-1] > 0.99 * (10 ** 6 - 28)


def test_structural_zeros_fixed_fields_and_tables_stay_put():
    drift = ThermalDrift(rate=0.01, offset=0.0, t0=3.0, time_constant=0.0)
    assert _free(drift) == [("rate", -1), ("time_constant", -1)]    # fitted as 1 / T, from 0
    assert _free(replace(drift, rate=0.0)) == [("time_constant", -1)]
    extra = ExtraFrictionSource(fc=1.0, fs=2.0, vs=0.01, B=0.0)
    assert [n for n, _ in _free(extra)] == ["fc", "fs", "vs"]
    assert _free(ForceConstantMismatch(force_constant=21.0, nominal_force_constant=20.0)) == [
        ("force_constant", -1)]
    table = next(iter(TABLES.values()))(lo=0.0, hi=1.0, values=(0.1, 0.2, 0.3))
    assert _free(table) == []


def test_nothing_free_comes_back_unchanged(phi_log):
    log, model, spec, _ = phi_log
    p = problem_of(log, model, spec)
    load = ConstantLoad(load=0.0)
    (same,), before, after = output_error_fit(p, [], [load], HORIZON, SUBSTEPS)
    assert same is load and before == after


def test_a_linear_drift_becomes_the_saturating_one_the_log_holds():
    """Selection may keep a drift linear; its time constant is refitted from 0 (as 1 / T)."""
    sc = make_scenario(1, ("thermal_drift",), rate_hz=500.0, duration_s=8.0)
    true = sc.conditions["magnitudes"]["thermal_drift"]
    p = ResidualProblem(sc.log, sc.model, sc.mass, sc.force_constant, 11, 0.3)
    t_split, t_end = p.signals.t[p.split], p.signals.t[-1]
    # the straight line through the true level at the split
    level = true["level"] * -np.expm1(-t_split / true["time_constant"])
    linear = ThermalDrift(rate=level / t_split, offset=0.0, t0=0.0, time_constant=0.0)
    # with diagnose's own substeps: at 4 the simulated error is rough enough on some machines
    # for least_squares to stop on its cost tolerance after its first step
    (refined,), before, after = output_error_fit(p, [], [linear], 10, Diagnoser().substeps)
    assert after < before and 0.0 < refined.time_constant < 10.0 * true["time_constant"]

    def at_end(drift):
        return drift.rate * drift._shape(t_end, drift.time_constant)
    true_end = true["level"] * -np.expm1(-t_end / true["time_constant"])
    assert abs(at_end(refined) - true_end) < 0.5 * abs(at_end(linear) - true_end)


def test_the_diagnosis_reports_the_refined_values_and_their_gap(phi_log):
    log, model, spec, truth = phi_log
    kw = dict(candidates=["force_constant_mismatch", "constant_load"], tables=False, substeps=SUBSTEPS)
    plain = Diagnoser(refine=False, **kw).fit(log, model, spec.mass, spec.force_constant)
    refined = Diagnoser(**kw).fit(log, model, spec.mass, spec.force_constant)
    assert plain.effect_ == refined.effect_ == "force_constant_mismatch"
    assert np.isnan(plain.fit_gap_after_) and plain.gap_selected_ == plain.gap_after_
    assert refined.gap_selected_ == plain.gap_after_
    assert refined.fit_gap_after_ <= refined.fit_gap_before_
    phi = refined.model_.effects[-1]["parameters"]["force_constant"]
    assert phi == refined.added_[0].force_constant == refined.effects_[0].fitted.force_constant
    assert abs(phi - truth.force_constant) <= abs(plain.added_[0].force_constant - truth.force_constant) + 1e-3


def test_the_cli_says_what_the_refinement_changed(phi_log, tmp_path, capsys):
    import json

    from fricgen.cli import main
    from fricgen.data.motionlog import log_csv_text
    log, model, spec, _ = phi_log
    model.save(tmp_path / "model.json")
    (tmp_path / "log.csv").write_text(log_csv_text(log))
    args = ["diagnose", str(tmp_path / "log.csv"), "--model", str(tmp_path / "model.json"),
            "--mass", str(spec.mass), "--force-constant", str(spec.force_constant)]
    assert main(args + ["-o", str(tmp_path / "a"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["effect"] == "force_constant_mismatch"
    assert summary["fit_gap_after"] < summary["fit_gap_before"]
    assert summary["gap_selected"] > 0 and summary["gap_after"] > 0
    assert main(args + ["-o", str(tmp_path / "b")]) == 0
    printed = capsys.readouterr().out
    assert f"refined    the parameters above were fitted again to simulations of the fit part (its gap {summary['fit_gap_before']:.4g}" in printed
    assert "The parameters above were fitted again to simulations of the fit part" in (tmp_path / "b" / "report.md").read_text()


def test_refined_values_that_grow_the_held_out_gap_are_not_kept(phi_log, monkeypatch):
    """A refinement that lowers the fit part's gap at the held-out part's expense (there, by
    a force constant made far worse) leaves the selection's values in the model, and says so."""
    from fricgen.diagnose import diagnoser
    from fricgen.diagnose.report import refinement_note
    log, model, spec, _ = phi_log
    worse = lambda p, base, chosen, *args: ([replace(e, force_constant=0.5 * e.force_constant)
                                            for e in chosen], 1.0, 0.5)
    monkeypatch.setattr(diagnoser, "output_error_fit", worse)
    d = Diagnoser(candidates=["force_constant_mismatch"], tables=False).fit(log, model, spec.mass,
                                                                            spec.force_constant)
    assert [s.effect for s in d.effects_] == ["force_constant_mismatch"]
    assert not d.refinement_kept and d.gap_refined_ > 1.1 * d.gap_selected_
    assert d.gap_after_ == d.gap_selected_ and d.effects_[0].fitted == d.selected_[0]
    assert d.model_.effects[0]["parameters"]["force_constant"] == d.selected_[0].force_constant
    assert "which are kept" in refinement_note(d)
