"""Reproduction of the paper's experiments (sections 3-5) on its benchmark (section 2, Table 1).

Every experiment is averaged over seeds: seed s synthesizes the benchmark data and seeds the
random hidden layers. Per seed, ``run_seed`` fits the headline models and runs the sweeps
(neurons 1..50, activations, regularization, enlarged variability, conditioning by PSO,
cond(1/C I + H^T H) over neurons x C, ANFIS 2..12 MFs); ``reproduce`` maps it over the seeds
in parallel (``concurrent.futures``) and aggregates means (and medians of E_Ttest in newtons).
"""
from __future__ import annotations

import contextlib
import multiprocessing
import os
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Callable, Dict, List, Optional

import numpy as np

from .._validate import integer
from ..data import Benchmark, synthesize_benchmark
from ..fit import (AnfisRegressor, AutoELMRegressor, ConditionedELMRegressor, DefaultRegressor,
                   OracleRegressor)
from ..fit.elm import SVD, ELMRegressor, StandardScheme, log10_cond
from ..friction import preset
from ..networks.elm import hidden_matrix
from . import reported as paper

METRICS = ("e_train", "e_test", "e_ttest", "e_train_newton", "e_test_newton", "e_ttest_newton")

#: The headline models, in Table 2 order, by method name: seed -> unfitted estimator.
HEADLINE: Dict[str, Callable] = {
    "fuzzy_bell4": lambda s, shape: AnfisRegressor(paper.FUZZY_MFS, "bell"),
    "fuzzy_gauss4": lambda s, shape: AnfisRegressor(paper.FUZZY_MFS, "gauss"),
    **{name: (lambda s, shape, cfg=cfg: ELMRegressor(random_state=s, **cfg))
       for name, cfg in paper.HEADLINE_ELMS.items()},
    "elm_conditioned": lambda s, shape: ConditionedELMRegressor(10, random_state=s),
    "elm_auto": lambda s, shape: AutoELMRegressor(random_state=s),
    "default": lambda s, shape: DefaultRegressor(random_state=s),
    "oracle": lambda s, shape: OracleRegressor(shape=shape),
}

#: Sweeps over the number of neurons: variant -> (M, seed) -> unfitted estimator (figs. 9-22).
NEURON_SWEEPS: Dict[str, Callable] = {
    "standard_sigmoid": lambda m, s: ELMRegressor(m, "sigmoid", "standard", "pinv", random_state=s),
    "standard_sine": lambda m, s: ELMRegressor(m, "sine", "standard", "pinv", random_state=s),
    "standard_rbf": lambda m, s: ELMRegressor(m, "rbf", "standard", "pinv", random_state=s),
    "regularized": lambda m, s: ELMRegressor(m, "sigmoid", "standard", "ridge", C=1e5, random_state=s),
    "enlarged": lambda m, s: ELMRegressor(m, "sigmoid", "enlarged", "pinv", random_state=s),
    "enlarged_regularized": lambda m, s: ELMRegressor(m, "sigmoid", "enlarged", "ridge", C=1e5,
                                                      random_state=s),
}


class Plan:
    """Grids of one reproduction: full (the paper's) or quick (a smoke run)."""

    def __init__(self, quick: bool = False):
        self.quick = quick
        self.neurons = [1, 2, 4, 6, 10, 20, 35, 50] if quick else list(range(1, 51))
        self.conditioned = [2, 6, 10, 20] if quick else [2, 4, 6, 8, 10, 14, 20, 30, 40, 50]
        self.cond_neurons = [1, 5, 10, 20, 50] if quick else [1, 2, 5, 10, 15, 20, 30, 40, 50]
        self.cond_C = [10.0 ** k for k in range(0, 15, 2)] if quick else [10.0 ** k for k in range(0, 15)]
        self.anfis = [2, 4, 8, 12] if quick else list(range(2, 13))
        self.anfis_epochs = 30 if quick else 100
        self.pso_iterations = 15 if quick else 40


def _fit(estimator, bench: Benchmark) -> dict:
    """Fit on the benchmark's training data; errors of [F4]-[F6] and model figures."""
    d = bench.dataset
    start = time.perf_counter()
    estimator.fit(d.x, d.t)
    seconds = time.perf_counter() - start
    row = bench.errors(estimator.predict)
    row["fit_seconds"] = seconds
    row["beta_norm"] = getattr(estimator, "beta_norm_", None)
    row["log10_cond"] = getattr(estimator, "log10_cond_", None)
    C = getattr(estimator, "C_", None)
    row["C"] = None if C is None or not np.isfinite(C) else float(C)
    s = getattr(estimator, "singular_values_", None)
    row["log10_cond_regularized"] = (None if s is None or row["C"] is None else
                                     log10_cond(s, row["C"], n_hidden=int(estimator.n_hidden)))
    n = getattr(estimator, "n_hidden", None)
    row["n_hidden"] = getattr(estimator, "n_mfs", n)
    return row


def _cond_grid(bench: Benchmark, plan: Plan, seed: int) -> np.ndarray:
    """log10 cond(1/C I + H^T H) of a standard sigmoid ELM, neurons x C (fig. 14)."""
    rng = np.random.default_rng(seed)
    out = np.empty((len(plan.cond_neurons), len(plan.cond_C)))
    for i, m in enumerate(plan.cond_neurons):
        w, b = StandardScheme().draw(m, rng)
        s = SVD.of(hidden_matrix("sigmoid", bench.dataset.x, w, b)).s
        out[i] = [log10_cond(s, C, n_hidden=m) for C in plan.cond_C]
    return out


def run_seed(seed: int, quick: bool = False, shape: str = "gauss") -> dict:
    """Everything one seed contributes: headline rows and every sweep."""
    plan = Plan(quick)
    bench = synthesize_benchmark(preset("paper3", shape), seed=seed)
    out = {"seed": seed, "headline": {}, "neurons": {}, "conditioned": [], "anfis": {}}
    for name, make in HEADLINE.items():
        est = make(seed, shape)
        if isinstance(est, AnfisRegressor):
            est.epochs = plan.anfis_epochs
        if isinstance(est, ConditionedELMRegressor):
            est.iterations = plan.pso_iterations
        row = _fit(est, bench)
        if isinstance(est, ConditionedELMRegressor):
            row["pso_evaluations"] = est.n_evaluations_
            row["log10_cond_start"] = est.log10_cond_start_
        out["headline"][name] = row
    for variant, make in NEURON_SWEEPS.items():
        out["neurons"][variant] = [_fit(make(m, seed), bench) for m in plan.neurons]
    for m in plan.conditioned:
        est = ConditionedELMRegressor(m, iterations=plan.pso_iterations, random_state=seed)
        row = _fit(est, bench)
        row["pso_evaluations"] = est.n_evaluations_
        out["conditioned"].append(row)
    for mf in ("bell", "gauss"):
        out["anfis"][mf] = [_fit(AnfisRegressor(n, mf, epochs=plan.anfis_epochs), bench)
                            for n in plan.anfis]
    out["cond_grid"] = _cond_grid(bench, plan, seed).tolist()
    return out


def _mean(rows: List[dict], key: str) -> Optional[float]:
    values = [r[key] for r in rows if r.get(key) is not None]
    return float(np.mean(values)) if values else None


def _aggregate_curve(per_seed: List[List[dict]]) -> dict:
    """Mean over seeds of each metric along a sweep grid (+ median of E_Ttest in newtons)."""
    n = len(per_seed[0])
    keys = METRICS + ("beta_norm", "log10_cond", "log10_cond_regularized", "fit_seconds")
    curve = {k: [_mean([s[i] for s in per_seed], k) for i in range(n)] for k in keys}
    curve["e_ttest_newton_median"] = [float(np.median([s[i]["e_ttest_newton"] for s in per_seed]))
                                      for i in range(n)]
    return curve


def aggregate(seeds_out: List[dict], plan: Plan) -> dict:
    """Headline model rows and sweep curves from the per-seed results."""
    seeds_out = sorted(seeds_out, key=lambda r: r["seed"])
    models = []
    for name in HEADLINE:
        rows = [s["headline"][name] for s in seeds_out]
        row = {"method": name}
        n = [r["n_hidden"] for r in rows if r["n_hidden"] is not None]
        row["n_hidden"] = float(np.mean(n)) if n else None
        Cs = [r["C"] for r in rows if r["C"] is not None]
        row["C"] = float(np.median(Cs)) if Cs else None
        for k in METRICS + ("beta_norm", "log10_cond", "log10_cond_regularized", "fit_seconds"):
            row[k] = _mean(rows, k)
        row["e_ttest_newton_median"] = float(np.median([r["e_ttest_newton"] for r in rows]))
        if name == "elm_conditioned":
            row["pso_evaluations"] = _mean(rows, "pso_evaluations")
            row["log10_cond_start"] = _mean(rows, "log10_cond_start")
        row["paper"] = list(paper.REPORTED[name]) if name in paper.REPORTED else None
        models.append(row)
    sweeps = {
        "neurons": {"grid": plan.neurons, "variants": {
            v: _aggregate_curve([s["neurons"][v] for s in seeds_out]) for v in NEURON_SWEEPS}},
        "conditioned": {"grid": plan.conditioned,
                        **_aggregate_curve([s["conditioned"] for s in seeds_out]),
                        "pso_evaluations": [_mean([s["conditioned"][i] for s in seeds_out],
                                                  "pso_evaluations")
                                            for i in range(len(plan.conditioned))]},
        "cond_grid": {"neurons": plan.cond_neurons, "C": plan.cond_C,
                      "log10_cond": np.mean([s["cond_grid"] for s in seeds_out], axis=0).tolist()},
        "anfis": {"grid": plan.anfis, "epochs": plan.anfis_epochs, "variants": {
            mf: _aggregate_curve([s["anfis"][mf] for s in seeds_out]) for mf in ("bell", "gauss")}},
    }
    return {"models": models, "sweeps": sweeps}


def _ratio(a: Optional[float], b: Optional[float]) -> Optional[float]:
    return None if a is None or b is None or b == 0 else float(a / b)


def findings(result: dict) -> dict:
    """The paper's qualitative claims (``paper.CLAIMS``) checked against the measured numbers."""
    rows = {m["method"]: m for m in result["models"]}
    sw = result["sweeps"]
    grid = sw["neurons"]["grid"]
    var = sw["neurons"]["variants"]
    anfis = sw["anfis"]["variants"]["bell"]
    big = len(grid) - 1                                   # the largest M of the sweep
    out = {}

    def claim(key, holds, measured):
        out[key] = {"claim": paper.CLAIMS[key], "holds": bool(holds), "measured": measured}

    claim("anfis_overfits",
          anfis["e_train"][-1] < anfis["e_train"][0] and anfis["e_test"][-1] > min(anfis["e_test"]),
          f"bell MFs {sw['anfis']['grid'][0]}..{sw['anfis']['grid'][-1]}: E_train "
          f"{anfis['e_train'][0]:.4f} -> {anfis['e_train'][-1]:.4f}, E_test min "
          f"{min(anfis['e_test']):.4f} -> {anfis['e_test'][-1]:.4f}")
    std = var["standard_sigmoid"]
    claim("standard_ill_conditioned", std["log10_cond"][big] > 12,
          f"M = {grid[big]}: log10 cond = {std['log10_cond'][big]:.1f}, ||beta|| = {std['beta_norm'][big]:.3g}")
    act = [var[v]["e_test"][big] for v in ("standard_sigmoid", "standard_sine", "standard_rbf")]
    claim("activation_irrelevant", max(act) < 1.25 * min(act),
          f"E_test at M = {grid[big]}: sigmoid {act[0]:.4f}, sine {act[1]:.4f}, rbf {act[2]:.4f}")
    reg = var["regularized"]
    best_std, best_reg = min(std["e_ttest"]), min(reg["e_ttest"])
    claim("regularization_spoils_accuracy", best_reg > 1.1 * best_std,
          f"best E_Ttest over M: standard {best_std:.4f}, C = 1e5 {best_reg:.4f}")
    enl = var["enlarged"]
    i10 = grid.index(10) if 10 in grid else big
    claim("enlarged_well_conditioned",
          enl["log10_cond"][i10] < std["log10_cond"][i10] and enl["beta_norm"][i10] < std["beta_norm"][i10],
          f"M = 10: log10 cond {std['log10_cond'][i10]:.1f} -> {enl['log10_cond'][i10]:.1f}, "
          f"||beta|| {std['beta_norm'][i10]:.3g} -> {enl['beta_norm'][i10]:.3g}")
    er = var["enlarged_regularized"]
    claim("enlarged_regularized_small_beta",
          max(er["beta_norm"]) < paper.REPORTED_BETA_BOUND["elm_enlarged_regularized"]
          and er["e_test"][big] < 1.1 * min(er["e_test"]),
          f"max mean ||beta|| over M = {max(er['beta_norm']):.3g}; E_test at M = {grid[big]} "
          f"{er['e_test'][big]:.4f} vs best {min(er['e_test']):.4f}")
    cond = sw["conditioned"]
    claim("conditioned_beta_below_17",
          max(cond["beta_norm"]) < paper.REPORTED_BETA_BOUND["elm_conditioned"],
          f"max mean ||beta|| over M in {cond['grid']} = {max(cond['beta_norm']):.3g}")
    elms = [rows[k]["e_ttest"] for k in paper.HEADLINE_ELMS] + [rows["elm_conditioned"]["e_ttest"]]
    fz = rows["fuzzy_bell4"]["e_ttest"]
    claim("elm_matches_fuzzy", min(elms) < 1.25 * fz,
          f"E_Ttest: fuzzy_bell4 {fz:.4f}, best paper ELM {min(elms):.4f}")
    return out


def summary(result: dict) -> dict:
    """Headline ratios of medians of E_Ttest in newtons over seeds."""
    rows = {m["method"]: m for m in result["models"]}
    med = {k: r["e_ttest_newton_median"] for k, r in rows.items()}
    paper_models = [k for k in rows if k not in ("elm_auto", "default", "oracle")]
    paper_elms = [k for k in paper_models if k.startswith("elm_")]
    best_all = min(paper_models, key=med.get)
    best_elm = min(paper_elms, key=med.get)
    return {"auto_over_oracle": _ratio(med["elm_auto"], med["oracle"]),
            "default_over_oracle": _ratio(med["default"], med["oracle"]),
            "best_paper_model": best_all,
            "best_paper_over_auto": _ratio(med[best_all], med["elm_auto"]),
            "best_paper_elm": best_elm,
            "best_paper_elm_over_auto": _ratio(med[best_elm], med["elm_auto"])}


@contextlib.contextmanager
def _single_threaded_blas():
    """Workers spawned inside inherit one BLAS thread each: the matrices are small (202 x M),
    and BLAS threads of parallel workers on a shared machine slow each SVD down 2-20x."""
    keys = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
    saved = {k: os.environ.get(k) for k in keys}
    os.environ.update({k: "1" for k in keys})
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def reproduce(seeds: int = paper.SEEDS, quick: bool = False, jobs: int = 1,
              progress: Callable[[str], None] = lambda msg: None, shape: str = "gauss") -> dict:
    """Run every experiment of sections 3-5 over ``seeds`` seeds in ``jobs`` worker processes.

    Per seed (``run_seed``) the benchmark of section 2 (Table 1) is synthesized, the headline
    models (``HEADLINE``) fitted and scored by the errors of [F4]-[F6], and the sweeps run.

    Parameters
    ----------
    seeds : int
        Seeds to average over (the paper: ``SEEDS`` = 20).
    quick : bool
        Coarse grids and fewer epochs (a smoke run, ``Plan``).
    jobs : int
        Worker processes.
    progress : callable
        Called with a line of text after each seed.
    shape : str
        The Stribeck shape of [F2] of the benchmark's friction.

    Returns
    -------
    dict
        The results.json object: ``benchmark``, ``models`` (Table 2 rows), ``sweeps``,
        ``summary`` and ``findings`` (the paper's claims checked).

    Examples
    --------
    A quick run of two seeds takes minutes, so only the check of the arguments runs here:

    >>> from fricgen.paper import reproduce
    >>> result = reproduce(seeds=2, quick=True)           # doctest: +SKIP
    >>> reproduce(seeds=0)
    Traceback (most recent call last):
    ValueError: seeds must be a positive integer, got 0
    """
    integer("seeds", seeds)
    integer("jobs", jobs)
    plan = Plan(quick)
    start = time.perf_counter()
    outs = []
    with _single_threaded_blas(), ProcessPoolExecutor(
            max_workers=int(jobs), mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = [pool.submit(run_seed, s, quick, shape) for s in range(seeds)]
        for n, fut in enumerate(as_completed(futures), start=1):
            outs.append(fut.result())
            progress(f"{n}/{seeds} seeds done ({time.perf_counter() - start:.1f} s)")
    result = {"benchmark": {"preset": "paper3", "shape": shape, "seeds": int(seeds), "quick": bool(quick),
                            "n_train": 200, "n_test": 200, "n_theory": 500, "noise": 0.5,
                            "anfis_epochs": plan.anfis_epochs, "pso_iterations": plan.pso_iterations,
                            "pso_particles": ConditionedELMRegressor().n_particles}}
    result.update(aggregate(outs, plan))
    result["summary"] = summary(result)
    result["findings"] = findings(result)
    result["benchmark"]["seconds"] = time.perf_counter() - start
    return result


def fitted_seed0(shape: str = "gauss") -> dict:
    """The headline models (``HEADLINE``) fitted on seed 0 of the benchmark (for the curve
    figures of ``render_figures``).

    Parameters
    ----------
    shape : str
        The Stribeck shape of [F2] of the benchmark's friction.

    Returns
    -------
    dict
        Method name -> fitted estimator.

    Examples
    --------
    The fits take about half a minute; the example shows the names and the shape check:

    >>> from fricgen.paper import HEADLINE, fitted_seed0
    >>> list(HEADLINE)[:3]
    ['fuzzy_bell4', 'fuzzy_gauss4', 'elm_standard']
    >>> fitted = fitted_seed0()                           # doctest: +SKIP
    >>> fitted_seed0("sawtooth")
    Traceback (most recent call last):
    ValueError: shape must be one of ['exponential', 'gauss', 'rational'], got 'sawtooth'
    """
    bench = synthesize_benchmark(preset("paper3", shape), seed=0)
    return {name: make(0, shape).fit(bench.dataset.x, bench.dataset.t) for name, make in HEADLINE.items()}
