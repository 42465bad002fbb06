"""``fricgen synth``: a measured-style friction sweep (CSV v,f) of a preset."""
from __future__ import annotations

import numpy as np

from ..data import Sweep, synthesize_benchmark, sweep_csv_text
from ..friction import PRESETS, SHAPES, preset
from .common import add_output, add_seed, number, say, write_file


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("--preset", choices=sorted(PRESETS), default="paper3",
                   help="friction parameters: paper3 is Table 1's three sources (default paper3)")
    p.add_argument("--shape", choices=sorted(SHAPES), default="gauss",
                   help="the Stribeck shape g of [F1] (default gauss)")
    p.add_argument("--noise", type=number(0, 1e6, unit="N"), default=0.5,
                   help="uniform noise half-width, N (default 0.5)")
    add_seed(p)
    p.add_argument("--both-signs", action="store_true", help="mirror a random half to v < 0")
    add_output(p, "the CSV to write")
    p.set_defaults(run=run)


def run(args) -> int:
    """Write the paper benchmark's training data of a preset."""
    bench = synthesize_benchmark(preset(args.preset, args.shape), seed=args.seed, noise=args.noise)
    sweep = bench.train
    if args.both_signs:
        flip = np.random.default_rng(args.seed + 1).uniform(size=len(sweep)) < 0.5
        sweep = Sweep(np.where(flip, -sweep.v, sweep.v), np.where(flip, -sweep.f, sweep.f))
    write_file(args, sweep_csv_text(sweep))
    say(f"wrote {len(sweep)} rows ({args.preset}, {args.shape} shape, noise +-{args.noise} N) "
        f"to {args.output}")
    return 0
