"""``fricgen reproduce -o DIR [--quick] [--seeds N] [--jobs J]``: the paper end to end.

Writes ``DIR/results.json``, ``DIR/report.md`` and the PNG figures of ``fricgen.paper.figures``
(skipped, with a message, when matplotlib is missing). Progress goes to stderr.
"""
from __future__ import annotations

import json

from .._plot import pyplot
from ..paper import reported as paper
from ..paper.experiments import fitted_seed0, reproduce
from ..paper.figures import FIGURES, render_figures
from ..paper.report import render
from .common import add_output, check_targets, number, out, say, write_folder


def run(args) -> int:
    # every file the run will write, checked before the experiments (minutes) begin
    check_targets(args, ["results.json", "report.md", *(FIGURES if pyplot() is not None else ())])
    seeds = args.seeds if args.seeds is not None else (3 if args.quick else paper.SEEDS)
    say(f"reproducing the paper on {seeds} seeds with {args.jobs} job(s)"
         f"{' (quick)' if args.quick else ''}")
    result = reproduce(seeds, quick=args.quick, jobs=args.jobs, progress=say)
    files, figures, note = {}, [], ""
    if pyplot() is None:
        note = "Figures skipped: matplotlib is not installed (pip install 'fricgen[plot]')."
        say(note)
    else:
        say("drawing figures ...")
        files.update(render_figures(result, fitted_seed0()))
        figures = list(FIGURES.items())
    result["figures"] = [name for name, _ in figures]
    files["results.json"] = json.dumps(result, indent=1) + "\n"
    files["report.md"] = render(result, figures, note)
    check_targets(args, files)                                     # before any result is printed
    s = result["summary"]
    out(f"median E_Ttest: default/oracle = {s['default_over_oracle']:.2f}, "
        f"auto/oracle = {s['auto_over_oracle']:.2f}, "
        f"best paper ELM ({s['best_paper_elm']})/auto = {s['best_paper_elm_over_auto']:.2f}, "
        f"best paper model ({s['best_paper_model']})/auto = {s['best_paper_over_auto']:.2f}")
    write_folder(args, files)
    say(f"wrote results.json, report.md and {len(figures)} figures to {args.output} "
        f"({result['benchmark']['seconds']:.1f} s of experiments)")
    return 0


def register(p) -> None:
    """The arguments of this command."""
    add_output(p, "output folder")
    p.add_argument("--quick", action="store_true", help="coarse grids, 3 seeds: a smoke run")
    p.add_argument("--seeds", type=number(1, 1000, integer=True),
                   help=f"seeds to average (default {paper.SEEDS}; 3 with --quick)")
    p.add_argument("--jobs", type=number(1, 256, integer=True), default=1,
                   help="worker processes (default 1)")
    p.set_defaults(run=run)
