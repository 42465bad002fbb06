"""``fricgen demo``: the paper benchmark, the default model, its C and the measured parity."""
from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np

from ..codegen import check_overwrite, emit, parity, render
from .._io import check_folder
from ..codegen.cbuild import build_model
from ..data import synthesize_benchmark
from ..fit import DEFAULT_ELM, ELMRegressor, default_elm
from ..friction import preset
from ..model import FrictionModel
from ..paper import reported as paper
from .common import FORCE_C, add_output, number, out, say


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("--seeds", type=number(1, 1000, integer=True), default=paper.SEEDS,
                   help="runs to average (default 20)")
    add_output(p, "keep the emitted C in this folder (default: a temporary one)", required=False,
               force_also=FORCE_C)
    p.set_defaults(run=run)


def _mean_errors(make, seeds):
    rows = []
    for seed in seeds:
        bench = synthesize_benchmark(preset("paper3"), seed=seed)
        est = make(seed).fit(bench.dataset.x, bench.dataset.t)
        e = bench.errors(est.predict)
        rows.append([e["e_train"], e["e_test"], e["e_ttest"], e["e_ttest_newton"],
                     est.beta_norm_, est.log10_cond_])
    return np.mean(rows, axis=0), float(np.median(np.array(rows)[:, 3]))


def run(args) -> int:
    if args.output:
        check_folder(args.output, (), args.force)
    bench = synthesize_benchmark(preset("paper3"), seed=0)
    model = FrictionModel.fit(bench.dataset, default_elm(0), name="fm")
    if args.output:                     # before the benchmark runs, as emit checks it at the end
        check_overwrite([Path(args.output) / f for f in render(model, "fm")], args.force)
    seeds = range(args.seeds)
    say(f"paper benchmark (Table 1, 3 sources), {args.seeds} seeds")
    makers = {label: (lambda s, cfg=cfg: ELMRegressor(random_state=s, **cfg))
              for label, cfg in paper.HEADLINE_ELMS.items()}
    makers["elm_loo (M=40, C by LOO)"] = lambda s: ELMRegressor(random_state=s, **DEFAULT_ELM)
    makers["fricgen elm_auto"] = default_elm
    out(f"{'model':28s} {'E_train':>8s} {'E_test':>8s} {'E_Ttest':>8s} {'E_Ttest N':>10s} "
        f"{'median N':>9s} {'||beta||':>10s} {'log10cond':>9s}   paper [E_train, E_test, E_Ttest]")
    for label, make in makers.items():
        means, median_n = _mean_errors(make, seeds)
        reported = paper.REPORTED.get(label)
        ref = f"[{', '.join(f'{r:.4f}' for r in reported)}]" if reported else "-"
        out(f"{label:28s} {means[0]:8.4f} {means[1]:8.4f} {means[2]:8.4f} {means[3]:10.4f} "
            f"{median_n:9.4f} {means[4]:10.3g} {means[5]:9.2f}   {ref}")
    out("(normalized errors depend on the unspecified K_out; compare ratios and newtons)")

    work = Path(tempfile.mkdtemp(prefix="fricgen_demo_"))
    try:            # emitted and compiled aside: -o gets the C only, and only once it compiles
        emit(model, work / "c", "fm")
        say("emitted the C; compiling with cffi ...")
        lib = build_model(work / "c", "fm", build_dir=work / "build")
        p = parity.measure(model, lib, "fm")
        if args.output:
            emit(model, args.output, "fm", force=args.force)
            say(f"wrote the emitted C to {args.output}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    out(f"C parity over {p['n_velocities']} velocities: max |C - float32 twin| = "
        f"{p['max_abs_c_vs_twin']:.3g} N ({p['n_not_bit_equal']} not bit-equal), "
        f"max |C - float64 model| / max|F| = {p['max_rel_c_vs_model']:.3g}")
    return 0
