"""fricgen diagnose on scenario logs (fricgen.sim.scenarios, its own plant, controller and
trajectory) hiding a sensor delay (``oov:sensor_delay``: x and v logged, and fed back, whole
samples late), and on logs hiding a frictional lag: for each seed, the effects named and the
fitted delay against the truth's. A log's effect is visible when the truth (the hidden force
undone, ``Scenario.truth_log``) shrinks the held-out gap by ``VISIBLE_GAIN``. Prints the share
of delay logs (all, visible, visible of 1-3 samples) on which exactly {sensor_delay} is named,
what is named on the invisible ones, the median |tau_fit / tau_true - 1| where it is named, and
on how many lag logs sensor_delay is named.

    python benchmarks/sensor_delay.py [--seeds 20] [--first 1000] [--lag-seeds 10]
                                      [--duration 20] [--jobs 1]
"""
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse                                         # noqa: E402
from concurrent.futures import ProcessPoolExecutor      # noqa: E402

import numpy as np                                      # noqa: E402

from fricgen.diagnose.diagnoser import Diagnoser, candidates_with, diagnose     # noqa: E402
from fricgen.sim.scenarios import make_scenario         # noqa: E402


#: An effect is visible when the truth shrinks the held-out gap by at least this (issue 29's
#: definition, the diagnosis' own least gain).
VISIBLE_GAIN = 0.1


def one(seed: int, hidden: str, duration: float) -> dict:
    sc = make_scenario(seed, (hidden,), duration_s=duration)
    d = diagnose(sc.log, sc.model, sc.mass, sc.force_constant, candidates=candidates_with("sensor_delay"))   # --sensor-delay
    delay = [e for e in d.added_ if e.name == "sensor_delay"]
    truth = sc.conditions["magnitudes"][hidden].get("delay_s", float("nan"))
    gap_truth = Diagnoser().held_out_gap(sc.truth_log(), sc.model, sc.truth_mass(), sc.force_constant)
    return {"seed": seed, "hidden": hidden, "rate": sc.conditions.get("rate_hz"),
            "named": [e.name for e in d.added_], "truth": truth,
            "samples": sc.conditions["magnitudes"][hidden].get("samples", 0),
            "visible": gap_truth <= (1.0 - VISIBLE_GAIN) * d.gap_before_,
            "tau": delay[0].tau if delay else float("nan"), "gap": d.gap_after_ / d.gap_before_}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first", type=int, default=1000)
    parser.add_argument("--lag-seeds", type=int, default=10)
    parser.add_argument("--duration", type=float, default=20.0)
    parser.add_argument("--jobs", type=int, default=1)
    args = parser.parse_args()
    seeds = list(range(args.first, args.first + args.seeds))
    lag_seeds = list(range(args.first, args.first + args.lag_seeds))
    cases = [(s, "oov:sensor_delay") for s in seeds] + [(s, "frictional_lag") for s in lag_seeds]
    with ProcessPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(one, *zip(*cases), [args.duration] * len(cases)))
    print(f"{'seed':>5s} {'hidden':>16s} {'rate':>6s} {'delay':>8s} {'samples':>7s} {'visible':>7s} "
          f"{'fitted':>8s} {'gap a/b':>8s}  named")
    for r in rows:
        print(f"{r['seed']:5d} {r['hidden']:>16s} {r['rate']:6.0f} {r['truth'] * 1e3:6.2f}ms "
              f"{r['samples']:7d} {'yes' if r['visible'] else 'no':>7s} "
              f"{r['tau'] * 1e3:6.2f}ms {r['gap']:8.3f}  {', '.join(r['named']) or 'none'}")
    delays = [r for r in rows if r["hidden"] == "oov:sensor_delay"]
    exact = [r for r in delays if r["named"] == ["sensor_delay"]]
    seen = [r for r in delays if r["visible"]]
    seen13 = [r for r in seen if 1 <= r["samples"] <= 3]
    hidden_wrong = [r for r in delays if not r["visible"] and r["named"]]
    errors = [abs(r["tau"] / r["truth"] - 1) for r in delays if np.isfinite(r["tau"])]
    lags = [r for r in rows if r["hidden"] == "frictional_lag"]
    wrong = [r for r in lags if "sensor_delay" in r["named"]]
    print(f"\nhiding a sensor delay: exactly {{sensor_delay}} on {len(exact)}/{len(delays)} "
          f"({len(exact) / max(len(delays), 1):.0%}); median |tau_fit / tau_true - 1| where named: "
          f"{np.median(errors) if errors else float('nan'):.1%} (of {len(errors)})")
    for label, group in (("visible", seen), ("visible, 1-3 samples", seen13)):
        hits = sum(r["named"] == ["sensor_delay"] for r in group)
        print(f"  {label}: exactly {{sensor_delay}} on {hits}/{len(group)} ({hits / max(len(group), 1):.0%})")
    print(f"  invisible: something named on {len(hidden_wrong)}/{len(delays) - len(seen)}")
    print(f"hiding a frictional lag: sensor_delay named on {len(wrong)}/{len(lags)}")


if __name__ == "__main__":
    main()
