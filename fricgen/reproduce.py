"""``fricgen reproduce --out DIR [--quick] [--seeds N] [--jobs J]``: the paper end to end.

Writes ``DIR/results.json``, ``DIR/report.md`` and the PNG figures of ``fricgen.figures``
(skipped, with a message, when matplotlib is missing). Progress goes to stderr.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

from . import paper
from .data import synthesize_benchmark
from .experiments import HEADLINE, reproduce
from .files import write_atomic
from .friction import preset


def _say(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def fitted_seed0(shape: str = "gauss") -> dict:
    """The headline models fitted on seed 0 (for the curve figures)."""
    bench = synthesize_benchmark(preset("paper3", shape), seed=0)
    return {name: make(0, shape).fit(bench.dataset.x, bench.dataset.t) for name, make in HEADLINE.items()}


def cmd_reproduce(args) -> int:
    from .cli import UsageError
    from .figures import FIGURES
    from .report import render

    if args.seeds is not None and args.seeds < 1:
        raise UsageError(f"--seeds must be >= 1, got {args.seeds}")
    if args.jobs < 1:
        raise UsageError(f"--jobs must be >= 1, got {args.jobs}")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError(f"--out {out} exists and is not a folder")
    seeds = args.seeds if args.seeds is not None else (3 if args.quick else paper.SEEDS)
    _say(f"reproducing the paper on {seeds} seeds with {args.jobs} job(s)"
         f"{' (quick)' if args.quick else ''}")
    result = reproduce(seeds, quick=args.quick, jobs=args.jobs, progress=_say)
    out.mkdir(parents=True, exist_ok=True)
    figures, note = [], ""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        note = "Figures skipped: matplotlib is not installed (pip install 'fricgen[plot]')."
        _say(note)
    else:
        from .figures import write_figures

        _say("drawing figures ...")
        write_figures(result, out, fitted_seed0())
        figures = list(FIGURES.items())
    result["figures"] = [name for name, _ in figures]
    write_atomic(out / "results.json", json.dumps(result, indent=1) + "\n")
    write_atomic(out / "report.md", render(result, figures, note))
    s = result["summary"]
    _say(f"wrote results.json, report.md and {len(figures)} figures to {out} "
         f"({result['benchmark']['seconds']:.1f} s of experiments)")
    print(f"median E_Ttest: auto/oracle = {s['auto_over_oracle']:.2f}, "
          f"best paper ELM ({s['best_paper_elm']})/auto = {s['best_paper_elm_over_auto']:.2f}, "
          f"best paper model ({s['best_paper_model']})/auto = {s['best_paper_over_auto']:.2f}")
    return 0


def register(sub) -> None:
    """Add the ``reproduce`` subcommand to the ``fricgen`` parser's subparsers."""
    p = sub.add_parser("reproduce", help="run every experiment of the paper; write results.json, "
                       "report.md and figures")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--quick", action="store_true", help="coarse grids, 3 seeds: a smoke run")
    p.add_argument("--seeds", type=int, help=f"seeds to average (default {paper.SEEDS}; 3 with --quick)")
    p.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    p.set_defaults(run=cmd_reproduce)
