"""The spread of default / oracle on the paper's benchmark (section 2), on seeds that tuned
nothing: what ``fricgen reproduce --quick --seeds 2`` (seeds 0-1) can tell, and so the bound
tests/test_experiments.py puts on it.

For each seed: Table 1 friction (``preset("paper3")``, gauss), ``synthesize_benchmark``, and the
default and the honest oracle made as ``fricgen reproduce`` makes them (``HEADLINE``) and fitted
to its [F9] set. Prints each seed's ratio of E_Ttest (N), their median and range, and, over every
pair of seeds, the share whose ratio exceeds each bound, the ratio taken as the quick run's
summary takes it: of the medians over the two seeds.

    python benchmarks/reproduce_spread.py [--seeds 20] [--first-seed 1000] [--shape gauss]
"""
import argparse
import itertools

import numpy as np

from fricgen.data import synthesize_benchmark
from fricgen.friction import preset
from fricgen.paper.experiments import HEADLINE

BOUNDS = (1.3, 1.6)


def errors(seed: int, shape: str) -> tuple:
    """E_Ttest (N) of the default and of the oracle on one seed's benchmark."""
    bench = synthesize_benchmark(preset("paper3", shape), seed=seed)
    d = bench.dataset
    return tuple(bench.errors(HEADLINE[name](seed, shape).fit(d.x, d.t).predict)["e_ttest_newton"]
                 for name in ("default", "oracle"))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first-seed", type=int, default=1000)
    parser.add_argument("--shape", default="gauss")
    args = parser.parse_args()
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    rows = []
    for seed in seeds:
        rows.append(errors(seed, args.shape))
        print(f"seed {seed}: default / oracle {rows[-1][0] / rows[-1][1]:.3f}", flush=True)
    ratios = [default / oracle for default, oracle in rows]
    pairs = np.array([np.median([a[0], b[0]]) / np.median([a[1], b[1]])
                      for a, b in itertools.combinations(rows, 2)])
    print(f"\n{args.shape}, seeds {seeds[0]}-{seeds[-1]}: median {np.median(ratios):.3f}, "
          f"range {min(ratios):.2f}-{max(ratios):.2f}")
    for bound in BOUNDS:
        print(f"pairs of seeds whose ratio of medians exceeds {bound}: "
              f"{np.mean(pairs > bound):.1%} of {pairs.size}")

if __name__ == "__main__":
    main()
