"""The friction model a cogging calibration at one speed each way writes, against the axis's true
friction at speeds other than the move's.

Axes of fricgen/sim/servo_axis.py, one per seed from 1000 up (none tuned anything here): a
calibration of 2 turns each way at 1 and at 3 rad/s, logged at 2 kHz, trained as
``fricgen train LOG --cogging --rotary --force-constant KT``. Per case: the model's force over the
true steady friction (Coulomb, a Gaussian Stribeck drop, viscous) at 0.3, 1, 3 and 6 rad/s, the
median and the worst over seeds of |ratio - 1|, and how many models say they hold the move's
level alone (``training.method`` "level_at_one_speed").

    python benchmarks/calibration_friction.py [--first 1000] [--seeds 10]
"""
from __future__ import annotations

import argparse
import contextlib
import io
import multiprocessing
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fricgen.cli import main as fricgen_main  # noqa: E402
from fricgen.model import FrictionModel  # noqa: E402
from fricgen.sim.servo_axis import calibration_move, random_axis  # noqa: E402

SPEEDS = np.array([0.3, 1.0, 3.0, 6.0])


def one(job):
    """(move speed, seed, |model / truth - 1| at SPEEDS, the training method)."""
    speed, seed = job
    axis = random_axis(seed)
    log = calibration_move(axis, turns=2.0, speed=speed, every=4)
    truth = (axis.coulomb + (axis.static - axis.coulomb) * np.exp(-(SPEEDS / axis.stribeck) ** 2)
             + axis.viscous * SPEEDS)
    with tempfile.TemporaryDirectory() as tmp:
        path, out = Path(tmp) / "cal.csv", Path(tmp) / "m.json"
        np.savetxt(path, np.column_stack([log["t"], log["x"], log["i"]]), delimiter=",",
                   header="t,x,i", comments="", fmt="%.9g")
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            code = fricgen_main(["train", str(path), "--cogging", "--rotary", "--force-constant",
                                 str(axis.kt), "-o", str(out)])
        if code:
            return speed, seed, None, "refused"
        model = FrictionModel.load(out)
    errors = np.maximum(np.abs(model.force(SPEEDS) / truth - 1), np.abs(-model.force(-SPEEDS) / truth - 1))
    return speed, seed, errors, model.training.get("method")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--first", type=int, default=1000)
    ap.add_argument("--seeds", type=int, default=10)
    args = ap.parse_args(argv)
    jobs = [(s, seed) for s in (1.0, 3.0) for seed in range(args.first, args.first + args.seeds)]
    with multiprocessing.Pool(2) as pool:
        results = pool.map(one, jobs)
    print(f"seeds {args.first}-{args.first + args.seeds - 1}; |model / true friction - 1| at "
          f"{', '.join(f'{s:g}' for s in SPEEDS)} rad/s: median / worst over seeds\n")
    print(f"{'move':>10s} " + " ".join(f"{f'{s:g} rad/s':>15s}" for s in SPEEDS) + "  level only  refused")
    for speed in (1.0, 3.0):
        rows = [r for r in results if r[0] == speed]
        kept = np.array([r[2] for r in rows if r[2] is not None])
        cells = " ".join(f"{np.median(kept[:, k]):7.3f}/{kept[:, k].max():<7.3f}" for k in range(SPEEDS.size))
        level = sum(r[3] == "level_at_one_speed" for r in rows)
        refused = sum(r[3] == "refused" for r in rows)
        print(f"{speed:6g} rad/s {cells}  {level:5d}/{len(rows):<5d} {refused:3d}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
