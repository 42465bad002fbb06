"""Logs with the position in encoder counts: the mass and the friction identified from them.

A simulator of its own (not fricgen's, ``tests/independent_axis.counts_log``): a 3 kg axis under
a PI velocity loop at the log's rate, integrated by semi-implicit Euler at 20 steps per sample,
its friction a tanh-smoothed Coulomb level with a Lorentzian Stribeck peak and viscous friction
(no shape of fricgen's vocabulary), the drive force logged with 0.2 N of noise, the position logged in encoder steps (1 um and 10 um)
and no velocity column (fricgen differentiates the position). Per seed (1000 up: none tuned
anything here) and rate (1 and 4 kHz): ``fricgen.train`` on the quantized log and on the same
log with the exact position. Counted: the mass within 2 % of the truth and within 3 of its
standard errors; the friction's RMS error over 0.005-0.2 m/s against the truth, quantized over
exact; and how many logs a warning doubted the mass of (``RigidBody.doubts``: none has
memory). The simulator logs its loop's force as it is sent, held over the next sample (a set-point), so
both are trained with force_held (``train --force-held``); ``--as-logged`` trains without it.

    python benchmarks/encoder_counts.py [--seeds 10] [--duration 16] [--as-logged]
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import fricgen  # noqa: E402
from independent_axis import COUNTS_MASS as MASS  # noqa: E402
from independent_axis import counts_friction as friction  # noqa: E402
from independent_axis import counts_log  # noqa: E402

STEPS = (1e-6, 1e-5)
RATES = (1000.0, 4000.0)


def identify(columns: dict, held: bool) -> tuple:
    """(mass, its standard error, the model, whether a warning doubted the mass) of
    fricgen.train on the columns."""
    lines = []
    report = fricgen.train(columns, force_held=held, warn=lines.append)
    body = report.identification.body
    return body.mass, body.mass_se, report.model, any("the identified mass" in line for line in lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--duration", type=float, default=16.0)
    ap.add_argument("--as-logged", action="store_true",
                    help="train without force_held (the force taken at the row it is logged at)")
    args = ap.parse_args(argv)
    held = not args.as_logged
    speeds = np.concatenate([-np.geomspace(0.2, 0.005, 30), np.geomspace(0.005, 0.2, 30)])
    print(f"mass {MASS} kg; seeds 1000-{999 + args.seeds}; {args.duration:g} s logs; force "
          + ("held over each sample (force_held)" if held else "as logged"))
    good = {(step, rate): 0 for step in STEPS for rate in RATES}
    ratios = {(step, rate): [] for step in STEPS for rate in RATES}
    doubts = 0
    for seed in range(1000, 1000 + args.seeds):
        for rate in RATES:
            t0 = time.perf_counter()
            log = counts_log(seed, rate, args.duration)
            _, _, exact_model, doubted = identify(log, held)
            doubts += doubted
            exact_rms = float(np.sqrt(np.mean((exact_model.force(speeds) - friction(speeds)) ** 2)))
            for step in STEPS:
                quantized = {**log, "x": np.round(log["x"] / step) * step}
                mass, se, model, doubted = identify(quantized, held)
                doubts += doubted
                rms = float(np.sqrt(np.mean((model.force(speeds) - friction(speeds)) ** 2)))
                ok = abs(mass - MASS) <= 0.02 * MASS and abs(mass - MASS) <= 3 * se
                good[step, rate] += ok
                ratios[step, rate].append(rms / exact_rms)
                print(f"  seed {seed} {rate / 1e3:.0f} kHz {step * 1e6:4.0f} um: mass {mass:.4f} +- "
                      f"{se:.2g} kg ({'ok' if ok else 'MISS'}), friction RMS {rms:.3f} N against "
                      f"{exact_rms:.3f} N exact ({rms / exact_rms:.2f}x)", flush=True)
            print(f"  ({time.perf_counter() - t0:.0f} s)", flush=True)
    for (step, rate), count in good.items():
        r = np.array(ratios[step, rate])
        print(f"{step * 1e6:4.0f} um, {rate / 1e3:.0f} kHz: mass ok on {count}/{args.seeds} seeds; "
              f"friction RMS quantized / exact median {np.median(r):.2f}x, worst {r.max():.2f}x, "
              f"within 1.2x on {int(np.sum(r <= 1.2))}/{r.size}")
    print(f"a warning doubted the mass (friction with memory?) on {doubts} of "
          f"{args.seeds * len(RATES) * (1 + len(STEPS))} logs, none of which has memory")


if __name__ == "__main__":
    main()
