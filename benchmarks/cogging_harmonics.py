"""fricgen diagnose on scenario logs (fricgen.sim.scenarios, its own plant, controller and
trajectory) hiding cogging with its 2nd and 3rd harmonics (``oov:ripple_harmonics``: 0.12,
0.10, 0.08 F_c): for each seed, the effects named, the harmonics H and the period found
against the truth's. The cogging is **visible** in a log where the truth (the user's model
with the cogging's exact force, ``diagnose_confusion.py``'s ``shows``) shrinks the held-out gap
by at least the guard's 10 %. Prints the share of logs, and of visible logs, on which exactly
{position_ripple} is named with H = 3, and with the period within 1 %. Seeds from 1000 up
tuned nothing.

    python benchmarks/cogging_harmonics.py [--seeds 20] [--first 1000] [--duration 20] [--jobs 2]
"""
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse                                         # noqa: E402
import sys                                              # noqa: E402
from concurrent.futures import ProcessPoolExecutor      # noqa: E402
from pathlib import Path                                # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))

from diagnose_confusion import shows                    # noqa: E402
from fricgen.diagnose.diagnoser import Diagnoser, diagnose  # noqa: E402
from fricgen.sim.scenarios import make_scenario         # noqa: E402


def one(seed: int, duration: float) -> dict:
    sc = make_scenario(seed, ("oov:ripple_harmonics",), duration_s=duration)
    d = diagnose(sc.log, sc.model, sc.mass, sc.force_constant)
    truth = sc.conditions["magnitudes"]["oov:ripple_harmonics"]
    ripple = [e for e in d.added_ if e.name == "position_ripple"]
    return {"seed": seed, "rate": sc.conditions.get("rate_hz"), "named": [e.name for e in d.added_],
            "H": ripple[0].harmonics if ripple else 0,
            "period": ripple[0].period / truth["period"] - 1 if ripple else float("nan"),
            "gap": d.gap_after_ / d.gap_before_, "gap_before": d.gap_before_,
            "gap_truth": Diagnoser().held_out_gap(sc.truth_log(), sc.model, sc.truth_mass(),
                                                  sc.force_constant)}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first", type=int, default=1000)
    parser.add_argument("--duration", type=float, default=20.0)
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    seeds = range(args.first, args.first + args.seeds)
    with ProcessPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(one, seeds, [args.duration] * len(seeds)))
    print(f"{'seed':>5s} {'H':>2s} {'period err':>10s} {'gap after/before':>16s} "
          f"{'truth/before':>12s}  named")
    for r in rows:
        print(f"{r['seed']:5d} {r['H']:2d} {r['period']:10.2%} {r['gap']:16.3f} "
              f"{r['gap_truth'] / r['gap_before']:12.3f}  {', '.join(r['named']) or 'none'}"
              + ("" if shows(r) else "  (invisible)"))
    for label, group in (("all", rows), ("visible", [r for r in rows if shows(r)])):
        exact = [r for r in group if r["named"] == ["position_ripple"] and r["H"] == 3]
        close = [r for r in exact if abs(r["period"]) < 0.01]
        print(f"{label:8s} exactly {{position_ripple}} with H = 3: {len(exact)}/{len(group)} "
              f"({len(exact) / max(len(group), 1):.0%}); of those, period within 1 %: {len(close)}")


if __name__ == "__main__":
    main()
