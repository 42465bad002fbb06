"""``fricgen fleet``: identify every axis of a manifest on Dask and flag drifting friction."""
from __future__ import annotations

from ..errors import UsageError
from ..fleet import MIN_CHANGE, SIGMAS, read_manifest, run_fleet
from ..fleet.drift import BASELINES
from .common import add_seed, number, positive_float, say
from .inputs import add_export_options
from . import INTERRUPTED, blas_env
from .train import train_argv


def train_options(args) -> list:
    """The ``fricgen train`` options every log of the fleet is trained with."""
    if args.merge:
        raise UsageError("--merge applies to one log; a fleet's manifest lists one file per log")
    options = ["--seed", str(args.seed), "--skip", str(args.skip)]
    for flag, values in (("--columns", args.columns), ("--scale", args.scale)):
        for value in values:
            options += [flag, value]
    if args.vs_max is not None:
        options += ["--vs-max", repr(args.vs_max)]
    if args.accept_unusual:
        options.append("--accept-unusual")
    return options


def run(args) -> int:
    options = train_options(args)
    entries = read_manifest(args.manifest)
    try:
        result = run_fleet(entries, args.output, train_argv, options, env=blas_env(), scheduler=args.scheduler,
                           workers=args.workers, sigmas=args.sigmas, min_change=args.min_change,
                           baseline=args.baseline, progress=say)
    except KeyboardInterrupt:
        say(f"fricgen: interrupted; the finished results are kept in {args.output}/results "
            "(a rerun skips them)")
        return INTERRUPTED
    say(f"fleet: {result.computed} logs identified, {result.skipped} done before, "
        f"{result.failed} failed, {result.flagged} axes flagged; wrote {args.output}/fleet.parquet, "
        "fleet.csv, report.md")
    return 0


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("manifest", help="CSV with columns axis, log (CSV or .mat, relative to the "
                   "manifest), timestamp (ISO 8601), and optionally mass (kg) and force_constant (N/A)")
    p.add_argument("-o", "--output", "--out", dest="output", required=True,
                   help="folder of the results (kept between runs), the table, report.md and plots")
    p.add_argument("--workers", type=number(1, 1024, integer=True), default=2,
                   help="worker processes of the embedded LocalCluster (default 2), one thread each")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on the Dask cluster at ADDRESS (e.g. tcp://host:8786) instead")
    p.add_argument("--sigmas", type=positive_float, default=SIGMAS,
                   help=f"a drift exceeds this many combined standard errors (default {SIGMAS:g})")
    p.add_argument("--min-change", type=number(0, 10), default=MIN_CHANGE,
                   help="... and this fraction of the earlier value, the practical threshold "
                   f"(default {MIN_CHANGE:g})")
    p.add_argument("--baseline", choices=BASELINES, default="previous",
                   help="compare each result with the axis's previous result (default) or its first")
    p.add_argument("--vs-max", type=positive_float, help="train's --vs-max for every log")
    add_seed(p)
    add_export_options(p)
    p.set_defaults(run=run)
