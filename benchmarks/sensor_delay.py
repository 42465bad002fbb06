"""fricgen diagnose on scenario logs (fricgen.sim.scenarios, its own plant, controller and
trajectory) hiding a sensor delay (``oov:sensor_delay``: x and v logged, and fed back, whole
samples late), and on logs hiding a frictional lag: for each seed, the effects named and the
fitted delay against the truth's. Prints the share of delay logs on which exactly
{sensor_delay} is named, the median |tau_fit / tau_true - 1| where it is named (against the
hidden delay, and against it plus the half sample by which the logged current, the command held
over each sample, acts late), and on how many lag logs sensor_delay is named.

    python benchmarks/sensor_delay.py [--seeds 20] [--first 600] [--lag-seeds 10]
                                      [--duration 20] [--jobs 1]
"""
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse                                         # noqa: E402
from concurrent.futures import ProcessPoolExecutor      # noqa: E402

import numpy as np                                      # noqa: E402

from fricgen.diagnose.diagnoser import diagnose         # noqa: E402
from fricgen.sim.scenarios import make_scenario         # noqa: E402


def one(seed: int, hidden: str, duration: float) -> dict:
    sc = make_scenario(seed, (hidden,), duration_s=duration)
    d = diagnose(sc.log, sc.model, sc.mass, sc.force_constant)
    delay = [e for e in d.added_ if e.name == "sensor_delay"]
    truth = sc.conditions["magnitudes"][hidden].get("delay_s", float("nan"))
    return {"seed": seed, "hidden": hidden, "rate": sc.conditions.get("rate_hz"),
            "hold": 0.5 * sc.log.sample_time,
            "named": [e.name for e in d.added_], "truth": truth,
            "tau": delay[0].tau if delay else float("nan"), "gap": d.gap_after_ / d.gap_before_}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first", type=int, default=600)
    parser.add_argument("--lag-seeds", type=int, default=10)
    parser.add_argument("--duration", type=float, default=20.0)
    parser.add_argument("--jobs", type=int, default=1)
    args = parser.parse_args()
    seeds = list(range(args.first, args.first + args.seeds))
    lag_seeds = list(range(args.first, args.first + args.lag_seeds))
    cases = [(s, "oov:sensor_delay") for s in seeds] + [(s, "frictional_lag") for s in lag_seeds]
    with ProcessPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(one, *zip(*cases), [args.duration] * len(cases)))
    print(f"{'seed':>5s} {'hidden':>16s} {'rate':>6s} {'delay':>8s} {'fitted':>8s} {'gap a/b':>8s}  named")
    for r in rows:
        print(f"{r['seed']:5d} {r['hidden']:>16s} {r['rate']:6.0f} {r['truth'] * 1e3:6.2f}ms "
              f"{r['tau'] * 1e3:6.2f}ms {r['gap']:8.3f}  {', '.join(r['named']) or 'none'}")
    delays = [r for r in rows if r["hidden"] == "oov:sensor_delay"]
    exact = [r for r in delays if r["named"] == ["sensor_delay"]]
    errors = [abs(r["tau"] / r["truth"] - 1) for r in delays if np.isfinite(r["tau"])]
    held = [abs(r["tau"] / (r["truth"] + r["hold"]) - 1) for r in delays if np.isfinite(r["tau"])]
    lags = [r for r in rows if r["hidden"] == "frictional_lag"]
    wrong = [r for r in lags if "sensor_delay" in r["named"]]
    print(f"\nhiding a sensor delay: exactly {{sensor_delay}} on {len(exact)}/{len(delays)} "
          f"({len(exact) / max(len(delays), 1):.0%}); median |tau_fit / tau_true - 1| where named: "
          f"{np.median(errors) if errors else float('nan'):.1%} (of {len(errors)}); against the delay "
          f"plus half a sample: {np.median(held) if held else float('nan'):.1%}")
    print(f"hiding a frictional lag: sensor_delay named on {len(wrong)}/{len(lags)}")


if __name__ == "__main__":
    main()
