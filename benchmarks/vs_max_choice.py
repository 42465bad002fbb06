"""vs_max chosen from the data (``choose_vs_max``) against vs_max given, on Table 1 sweeps.

The sweeps of ``default_vs_oracle.py`` (200 points in [0, 3 vs_max], 100 in (3, 10] vs_max,
vs_max = 0.02 m/s), with noise uniform in +-0.5 N or normal with the same standard deviation,
seeds from 1000 up (no constant was tuned on them). Errors are RMSE against the noise-free law,
on Table 1's range (0, 3 vs_max] ("low") and on the sweep's whole range (0, 10 vs_max] ("all").
Prints per shape and noise law, as medians over the seeds (and the largest):
  default / oracle (low): the default (``DefaultRegressor``) given the true vs_max, against the
      honest oracle ([F1] with the true shape and S = 3, with and without the point at v = 0,
      the better of the two: ``default_vs_oracle.oracle_error``) on the same training set;
  chosen / given: the default on the training set of the chosen vs_max (``prepare`` without
      vs_max) against the default given the true vs_max, on both ranges. The true vs_max puts
      v_sat at 3 vs_max, where the exponential and rational Stribeck tails are still 0.75 N
      and 3.75 N: beyond it the given training set's line is bent, which "low" does not see;
  chosen / hindsight (all): against the default given the vs_max of a grid that is best on the
      truth for that sweep (the strongest choice a rule could make);
  the chosen vs_max (median, range) and how often the data were judged to have no linear region;
  one line per sweep on stderr.
Then: refusals over 8 noise draws of one-direction sweeps to 10 vs_max, and the time of one
choice on a 300-row sweep.
Run: python benchmarks/vs_max_choice.py [--seeds 20] [--noise uniform gauss]
"""
import argparse
import sys
import time

import numpy as np

from default_vs_oracle import V_GRID, VS_MAX, oracle_error, sweep
from fricgen.data import DataError, choose_vs_max, prepare
from fricgen.fit import DefaultRegressor
from fricgen.friction import preset
from fricgen.model import FrictionModel

#: The sweep's whole range (0, 10 vs_max].
ALL = np.linspace(0.0, 10 * VS_MAX, 2001)[1:]
#: The fixed vs_max values of the hindsight choice (each leaves rows beyond v_sat = 3 vs_max).
HINDSIGHT = VS_MAX * np.array([1.0, 1.5, 2.0, 2.5])


def errors(law, data):
    """(low, all) RMSE of the default fitted to ``data``."""
    model = FrictionModel.fit(data, DefaultRegressor())
    return np.array([np.sqrt(np.mean((model.force(g) - law(g)) ** 2)) for g in (V_GRID, ALL)])


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first-seed", type=int, default=1000)
    parser.add_argument("--noise", nargs="+", default=["uniform", "gauss"])
    parser.add_argument("--shapes", nargs="+", default=["gauss", "exponential", "rational"])
    args = parser.parse_args()
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    print(f"{'shape':12s} {'noise':8s} {'default/oracle low':>18s} {'chosen/given low':>16s} "
          f"{'chosen/given all':>16s} {'chosen/hindsight all':>20s} {'vs_max chosen (m/s)':>22s} "
          f"{'no linear':>9s}", flush=True)
    cell = lambda r: f"{np.median(r):.2f} ({max(r):.2f})"          # noqa: E731
    for noise in args.noise:
        for shape in args.shapes:
            law = preset("paper3", shape)
            to_oracle, to_given, to_hindsight, chosen, joint = [], [], [], [], 0
            for seed in seeds:
                data = sweep(law, seed, noise=noise)
                grid = {vs: errors(law, prepare(data, vs_max=vs)) for vs in HINDSIGHT}
                e_given = grid[VS_MAX]
                to_oracle.append(e_given[0] / oracle_error(law, prepare(data, vs_max=VS_MAX), shape))
                free = prepare(data)
                e_free = errors(law, free)
                to_given.append(e_free / e_given)
                to_hindsight.append(e_free[1] / min(e[1] for e in grid.values()))
                chosen.append(free.stribeck_range.vs_max)
                joint += not free.stribeck_range.linear_region
                print(f"  {shape} {noise} seed {seed}: default/oracle {to_oracle[-1]:.2f}, chosen "
                      f"{chosen[-1]:.3f} m/s, chosen/given {to_given[-1][0]:.2f} (low) "
                      f"{to_given[-1][1]:.2f} (all), chosen/hindsight {to_hindsight[-1]:.2f}",
                      file=sys.stderr, flush=True)
            to_given = np.array(to_given)
            print(f"{shape:12s} {noise:8s} {cell(to_oracle):>18s} {cell(to_given[:, 0]):>16s} "
                  f"{cell(to_given[:, 1]):>16s} {cell(to_hindsight):>20s} "
                  f"{np.median(chosen):6.3f} ({min(chosen):.3f}-{max(chosen):.3f}) "
                  f"{joint:5d}/{len(seeds)}", flush=True)
    refused = 0
    law = preset("paper3")
    for seed in range(args.first_seed, args.first_seed + 8):
        try:
            prepare(sweep(law, seed).direction(1))
        except DataError:
            refused += 1
    folded = sweep(law, args.first_seed).folded()
    start = time.perf_counter()
    choose_vs_max(folded)
    print(f"\none-direction sweeps to 10 vs_max: {refused} of 8 refused; one choice on "
          f"{len(folded)} rows: {time.perf_counter() - start:.3f} s")


if __name__ == "__main__":
    main()
