"""No spurious dependence: joints of fricgen/sim/loaded_joint.py whose friction depends on neither
the load nor the temperature, logged while both vary (the warming duty: gravity with payloads
changing between runs, 25 to about 60 degC), trained with the load and temperature columns.

The harmonic joint with its load slopes 0 and a viscosity that does not change with the
temperature (``viscosity_ratio`` 1); the planetary joint with no gear loss (every efficiency
1) and an oil whose viscosity does not change (``oil_ratio`` 1). Prints per seed the form fricgen keeps and the share of
seeds where it keeps the one-input model (``report.model.inputs is None``); seeds 1000-1009 by
default (seeds that tuned nothing).

    python benchmarks/load_temperature_null.py [--seeds 1000-1009] [--workers 1]
"""
from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse                                         # noqa: E402
import multiprocessing                                  # noqa: E402
import sys                                              # noqa: E402
from dataclasses import replace                         # noqa: E402

import fricgen                                          # noqa: E402
from fricgen.sim.loaded_joint import random_harmonic_joint, random_planetary_joint  # noqa: E402

COLUMNS = ("t", "x", "force", "load", "temperature")


def null_joints(seed: int):
    """The seed's two joints with the friction's load and temperature dependence taken out."""
    harmonic = replace(random_harmonic_joint(seed), slope_driving=0.0, slope_back=0.0,
                       viscosity_ratio=1.0)
    planetary = replace(random_planetary_joint(seed), forward=1.0, forward_low=1.0, back=1.0,
                        back_low=1.0, oil_ratio=1.0)
    return {"harmonic": harmonic, "planetary": planetary}


def one(seed: int):
    rows = []
    for name, joint in null_joints(seed).items():
        log = joint.duty_log(seed)[0]
        report = fricgen.train({k: log[k] for k in COLUMNS}, rotary=True,
                               warn=lambda line: None)
        rows.append((seed, name, report.training["inputs"]["chosen"], report.model.inputs is None))
    return rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="1000-1009")
    parser.add_argument("--workers", type=int, default=1)
    args = parser.parse_args()
    lo, _, hi = args.seeds.partition("-")
    seeds = list(range(int(lo), int(hi or lo) + 1))
    with multiprocessing.Pool(args.workers) as pool:
        results = [row for rows in pool.imap(one, seeds) for row in rows]
    for seed, name, chosen, left_out in results:
        print(f"seed {seed} {name:9s} kept: {chosen}", flush=True)
    for name in ("harmonic", "planetary"):
        kept = [r[3] for r in results if r[1] == name]
        print(f"{name}: the one-input model on {sum(kept)}/{len(kept)} seeds (target >= 95 %)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
