"""Paper reproduction: ``fricgen reproduce --quick`` and the paper's findings on fixed seeds."""
import json

import numpy as np
import pytest

from fricgen.cli import main
from fricgen.data import synthesize_benchmark
from fricgen.fit.elm import ELMRegressor
from fricgen.paper.experiments import HEADLINE
from fricgen.paper.figures import FIGURES
from fricgen.friction import preset
from fricgen.fit.anfis import AnfisRegressor

METHODS = ["fuzzy_bell4", "fuzzy_gauss4", "elm_standard", "elm_regularized", "elm_enlarged",
           "elm_enlarged_regularized", "elm_conditioned", "elm_auto", "default", "oracle"]
KEYS = ["method", "n_hidden", "C", "e_train", "e_test", "e_ttest", "e_ttest_newton",
        "e_ttest_newton_median", "beta_norm", "log10_cond", "fit_seconds"]


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("repro")
    code = main(["reproduce", "--quick", "--seeds", "2", "--out", str(out)])
    return code, out


def test_quick_reproduction_writes_every_method_and_figure(quick_run):
    code, out = quick_run
    assert code == 0
    result = json.loads((out / "results.json").read_text())
    assert result["benchmark"]["seeds"] == 2
    assert [m["method"] for m in result["models"]] == METHODS == list(HEADLINE)
    for row in result["models"]:
        assert set(KEYS) <= set(row)
        assert all(np.isfinite(row[k]) for k in ("e_train", "e_test", "e_ttest", "e_ttest_newton"))
    assert {"neurons", "conditioned", "cond_grid", "anfis"} <= set(result["sweeps"])
    assert set(result["sweeps"]["neurons"]["variants"]) >= {"standard_sigmoid", "standard_sine",
                                                             "standard_rbf", "enlarged_regularized"}
    pytest.importorskip("matplotlib")
    for name in FIGURES:
        assert (out / name).stat().st_size > 1000, name
    report = (out / "report.md").read_text()
    assert "Table 2" in report and "elm_auto" in report and "[0.0224, 0.0241, 0.0075]" in report


#: The bound on default / oracle over the quick run's 2 seeds (the ratio of the medians). On
#: seeds 1000-1019 (paper3, gauss) single seeds range from 0.60 to 2.01 (median 1.10), and the
#: ratio over a pair of them exceeds 1.3 for 21.6 % of the pairs and 1.6 for 1.6 %
#: (benchmarks/reproduce_spread.py; seeds 0-1 give 1.315). The 20-seed targets are measured by
#: benchmarks/default_vs_oracle.py; 2 seeds can only catch a default gone wrong.
QUICK_DEFAULT_OVER_ORACLE = 1.6


def test_quick_reproduction_default_meets_the_oracle_and_paper_targets(quick_run):
    result = json.loads((quick_run[1] / "results.json").read_text())
    s = result["summary"]
    assert s["default_over_oracle"] < QUICK_DEFAULT_OVER_ORACLE
    assert s["default_over_oracle"] <= s["auto_over_oracle"]
    assert s["best_paper_elm_over_auto"] > 2.0


def test_reproduce_rejects_bad_seeds_without_output(tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["reproduce", "--seeds", "0", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("fricgen: error: --seeds")
    assert not out.exists()


SEEDS = range(3)


def test_standard_elm_is_badly_conditioned_and_enlarged_regularized_keeps_beta_small():
    for seed in SEEDS:
        d = synthesize_benchmark(preset("paper3"), seed=seed).dataset
        std = ELMRegressor(30, scheme="standard", solver="pinv", random_state=seed).fit(d.x, d.t)
        er = ELMRegressor(30, scheme="enlarged", solver="ridge", C=1e5, random_state=seed).fit(d.x, d.t)
        assert std.log10_cond_ > 15 and std.beta_norm_ > 1e5
        assert er.beta_norm_ < 100 and er.beta_norm_ < 1e-3 * std.beta_norm_


def test_anfis_overfits_as_membership_functions_grow():
    rows = {n: [] for n in (4, 12)}
    for seed in SEEDS:
        bench = synthesize_benchmark(preset("paper3"), seed=seed)
        d = bench.dataset
        for n in rows:
            e = bench.errors(AnfisRegressor(n, "bell", epochs=60).fit(d.x, d.t).predict)
            rows[n].append([e["e_train"], e["e_test"]])
    (tr4, te4), (tr12, te12) = np.mean(rows[4], axis=0), np.mean(rows[12], axis=0)
    assert tr12 < tr4 and te12 > te4
