"""``fricgen diagnose LOG --model M``: name what a friction model misses in a measured log."""
from __future__ import annotations

import json
from pathlib import Path

from .._io import check_folder
from ..data import read_log_csv
from ..diagnose.diagnoser import Diagnoser
from ..diagnose.report import format_value, render_files
from ..model import FrictionModel
from .common import (add_json, add_model, add_output, check_targets, number, out, say,
                     write_folder)


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("log", help="measured log CSV with columns t, x, v, i (uniformly sampled)")
    add_model(p)
    p.add_argument("--mass", required=True, type=number(0, 1e6, low_open=True, unit="kg"),
                   help="nominal moving mass m, kg")
    p.add_argument("--force-constant", required=True, type=number(0, 1e6, low_open=True, unit="N/A"),
                   help="nominal force constant phi, N/A")
    add_output(p, "folder for model.json, report.md and plots")
    add_json(p, "print the summary as one JSON object")
    p.set_defaults(run=run)


def run(args) -> int:
    inputs = [args.model, args.log]
    check_folder(args.output, [args.model], args.force)
    model = FrictionModel.load(args.model)
    log = read_log_csv(args.log)
    d = Diagnoser().fit(log, model, args.mass, args.force_constant)
    files = render_files(d, log, Path(args.log).name)
    check_targets(args, files, inputs, folder_of=[args.model])     # before any result is printed
    if args.json:
        out(json.dumps(d.summary()))
    else:
        lines = [f"effect     {d.effect_} (confidence {d.confidence_:.2f})"]
        if d.fitted_ is not None:
            lines.append("parameters " + ", ".join(f"{k} = {format_value(v)}"
                                                  for k, v in d.parameters().items()))
        lines.append(f"where      {d.where_}")
        lines.append(f"gap        {d.gap_before_:.4g} -> {d.gap_after_:.4g} m/s ({d.gap_metric_})")
        out("\n".join(lines))
    write_folder(args, files, inputs, folder_of=[args.model])
    if not any(name.endswith(".png") for name in files):
        say("fricgen: matplotlib not installed; no plots written")
    say(f"wrote {', '.join(sorted(files))} to {args.output}")
    return 0
