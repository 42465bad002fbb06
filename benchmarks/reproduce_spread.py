"""The spread of default / oracle on the paper's benchmark (section 2), on seeds that tuned
nothing: what ``fricgen reproduce --quick --seeds 2`` (seeds 0-1) can tell, and so the bound
tests/test_experiments.py puts on it.

For each seed: Table 1 friction (``preset("paper3")``, gauss), ``synthesize_benchmark``, the
default and the honest oracle (``OracleRegressor``, as in ``fricgen reproduce``) fitted to its
[F9] set, and the ratio of their E_Ttest. Prints each ratio, their median and largest, and, over
every pair of seeds, the share whose mean ratio exceeds each bound (the quick run's summary is
the ratio of 2-seed medians, the mean of the two).

    python benchmarks/reproduce_spread.py [--seeds 20] [--first-seed 1000] [--shape gauss]
"""
import argparse
import itertools

import numpy as np

from fricgen.data import synthesize_benchmark
from fricgen.fit import DefaultRegressor, OracleRegressor
from fricgen.friction import preset

BOUNDS = (1.3, 1.6)


def ratio(seed: int, shape: str) -> float:
    """E_Ttest of the default over the oracle's on one seed's benchmark."""
    bench = synthesize_benchmark(preset("paper3", shape=shape), seed=seed)
    d = bench.dataset
    errors = [bench.errors(est.fit(d.x, d.t).predict)["e_ttest"]
              for est in (DefaultRegressor(), OracleRegressor(shape=shape))]
    return errors[0] / errors[1]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first-seed", type=int, default=1000)
    parser.add_argument("--shape", default="gauss")
    args = parser.parse_args()
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    ratios = []
    for seed in seeds:
        ratios.append(ratio(seed, args.shape))
        print(f"seed {seed}: default / oracle {ratios[-1]:.3f}", flush=True)
    pairs = np.array([(a + b) / 2 for a, b in itertools.combinations(ratios, 2)])
    print(f"\n{args.shape}, seeds {seeds[0]}-{seeds[-1]}: median {np.median(ratios):.3f}, "
          f"range {min(ratios):.2f}-{max(ratios):.2f}")
    for bound in BOUNDS:
        print(f"pairs of seeds whose mean exceeds {bound}: {np.mean(pairs > bound):.1%} "
              f"of {pairs.size}")


if __name__ == "__main__":
    main()
