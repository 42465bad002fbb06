"""fricgen diagnose on a tight spot: the friction doubled over 2 % of the travel
(``oov:tight_spot`` of ``fricgen.sim.hidden_effects``), on logs it did not generate.

For every seed (from 7000 up: no constant was tuned on them) the log is diagnosed as
``diagnose_confusion.py`` does, and the truth's held-out gap computed beside it (the user's
model with the spot's exact force). The spot is **visible** where the truth shrinks the gap by
at least the held-out guard's least gain. Printed per log and in total:

- how often the gap is at least halved, on the visible logs;
- diagnose's gap over the truth's;
- what was named: a position table is the only right answer; any effect of the named
  vocabulary (all of them act along the whole travel or the whole log) counts as a global name.

A drawn log too short for diagnose (it refuses one with too few moving samples) is counted
apart.

    python benchmarks/tight_spot.py [--seeds 20] [--jobs 1]
"""
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from diagnose_confusion import halves, run_case, shows  # noqa: E402
from fricgen.errors import DataError  # noqa: E402

LOCAL = ("table_position", "table_position_friction")


def diagnosed(case):
    """``run_case``'s record, or None for a log too short to diagnose (diagnose refuses it)."""
    try:
        return run_case(case)
    except DataError as e:
        print(f"seed {case[2]}: not diagnosed: {e}", flush=True)
        return None


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=20)
    p.add_argument("--first-seed", type=int, default=7000)
    p.add_argument("--jobs", type=int, default=1)
    args = p.parse_args()
    cases = [(f"tight-{s}", "oov", s, ("oov:tight_spot",), {})
             for s in range(args.first_seed, args.first_seed + args.seeds)]
    with ProcessPoolExecutor(args.jobs) as pool:
        records = []
        for r in pool.map(diagnosed, cases):
            if r is None:
                continue
            records.append(r)
            print(f"seed {r['seed']}: {r['duration_s']:.0f} s at {r['rate_hz']:.0f} Hz; "
                  f"{'visible' if shows(r) else 'invisible'}; named {r['effects'] or ['none']}; "
                  f"gap {r['gap_before']:.3g} -> {r['gap_after']:.3g} "
                  f"(x{r['gap_after'] / r['gap_before']:.2f}), truth {r['gap_truth']:.3g} "
                  f"(x{r['gap_truth'] / r['gap_before']:.2f}); {r['seconds_diagnose']:.0f} s", flush=True)
    seen = [r for r in records if shows(r)]
    halved = [r for r in seen if halves(r, "gap_after")]
    truth_halved = [r for r in seen if halves(r, "gap_truth")]
    global_names = [r for r in records if any(e not in LOCAL for e in r["effects"])]
    ratio = [r["gap_after"] / r["gap_truth"] for r in seen]
    print(f"diagnosed {len(records)} of {len(cases)} logs; visible {len(seen)}")
    print(f"gap at least halved: {len(halved)} of {len(seen)} visible "
          f"({len(halved) / max(len(seen), 1):.0%}); the truth halves it on {len(truth_halved)}")
    if ratio:
        print(f"diagnose's gap over the truth's (visible): median {np.median(ratio):.2f}, "
              f"largest {np.max(ratio):.2f}; within 1.1x on {sum(x <= 1.1 for x in ratio)} of {len(ratio)}")
    print(f"a global name on {len(global_names)} of {len(records)} logs"
          + (": " + ", ".join(f"{r['seed']} {r['effects']}" for r in global_names) if global_names else ""))


if __name__ == "__main__":
    main()
