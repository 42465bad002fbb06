"""vs_max chosen from the data (``choose_vs_max``) against vs_max given, on Table 1 sweeps.

The sweeps of ``default_vs_oracle.py`` (200 points in [0, 3 vs_max], 100 in (3, 10] vs_max,
vs_max = 0.02 m/s), with noise uniform in +-0.5 N or normal with the same standard deviation,
seeds from 1000 up (no constant was tuned on them). Error: RMSE against the noise-free law on
(0, 3 vs_max]. Prints per shape and noise law, as medians over the seeds:
  default / oracle: the default (``DefaultRegressor``) given the true vs_max, against the honest
      oracle (eq. (1) with the true shape and S = 3) on the same training set; and the largest;
  chosen / given: the default on the training set of the chosen vs_max (``prepare`` without
      vs_max) against the default given the true vs_max; and the largest;
  the chosen vs_max (median, range) and how often the data were judged to have no linear region.
Then: refusals over 8 noise draws of one-direction sweeps to 10 vs_max, and the time of one
choice on a 300-row sweep.
Run: python benchmarks/vs_max_choice.py [--seeds 20] [--noise uniform gauss]
"""
import argparse
import time

import numpy as np

from default_vs_oracle import VS_MAX, error, sweep
from fricgen.data import DataError, choose_vs_max, prepare
from fricgen.fit import DefaultRegressor, OracleRegressor
from fricgen.friction import preset


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first-seed", type=int, default=1000)
    parser.add_argument("--noise", nargs="+", default=["uniform", "gauss"])
    parser.add_argument("--shapes", nargs="+", default=["gauss", "exponential", "rational"])
    args = parser.parse_args()
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    print(f"{'shape':12s} {'noise':8s} {'default/oracle':>14s} {'max':>5s} {'chosen/given':>12s} "
          f"{'max':>5s} {'vs_max chosen (m/s)':>26s} {'no linear':>9s}", flush=True)
    for noise in args.noise:
        for shape in args.shapes:
            law = preset("paper3", shape)
            to_oracle, to_given, chosen, joint = [], [], [], 0
            for seed in seeds:
                data = sweep(law, seed, noise=noise)
                given = prepare(data, vs_max=VS_MAX)
                e_given = error(law, given, DefaultRegressor())
                to_oracle.append(e_given / error(law, given, OracleRegressor(shape)))
                free = prepare(data)
                to_given.append(error(law, free, DefaultRegressor()) / e_given)
                chosen.append(free.stribeck_range.vs_max)
                joint += not free.stribeck_range.linear_region
            print(f"{shape:12s} {noise:8s} {np.median(to_oracle):14.2f} {max(to_oracle):5.2f} "
                  f"{np.median(to_given):12.2f} {max(to_given):5.2f} "
                  f"{np.median(chosen):8.3f} ({min(chosen):.3f}-{max(chosen):.3f}) "
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
