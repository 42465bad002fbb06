"""A rack-and-pinion rig's identification run, exported as its two instruments would.

The axis (4 kg, 20 N/A) of fricgen's simulator sweeps its speeds in both directions under a
velocity loop (``fricgen.sim.identification``). Its friction differs between the directions:
Table 1 of the paper for v > 0, and for v < 0 larger Coulomb and Stribeck forces with other
Stribeck velocities. Two files come out, each with a preamble:

- ``drive.csv``: the drive at 1.5 kHz, time in s, position in mm, motor speed in rpm (one
  revolution moves the rack 20 mm, so 1 rpm = 1/3000 m/s), speed noise 1 rpm, 0.1 rpm steps;
- ``loadcell.csv``: a load cell on the carriage at 2 kHz, time in s on its own clock, 4 ms
  behind the drive's, and the drive force in N with 0.3 N noise.

``truth.json`` holds the friction of each direction. Run ``python make_export.py -o rig/``, then
the ``fricgen train`` command of the README.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from fricgen.friction import multisource, preset
from fricgen.sim.identification import DirectionalFriction, SweepRun, simulate_sweep_run

#: The rig's friction: Table 1 for v > 0, a rougher curve for v < 0.
FRICTION = DirectionalFriction(
    positive=preset("paper3"),
    negative=multisource(fc=(5.0, 7.5, 6.0), fs=(9.0, 19.0, 24.0), vs=(0.012, 0.006, 0.025),
                         B=(2.5, 45.0, 5.0)))
#: m/s per rpm: one pinion revolution moves the rack 20 mm.
METERS_PER_S_PER_RPM = 0.02 / 60.0
#: The load cell's clock lags the drive's by this much (s).
LOADCELL_LAG = 0.004
#: Samples of the simulation (6 kHz) per drive sample (1.5 kHz) and per load-cell sample (2 kHz).
DRIVE_STEP, LOADCELL_STEP = 4, 3
#: Sensor noise (standard deviations) and the drive's speed resolution.
SPEED_NOISE_RPM, SPEED_STEP_RPM, FORCE_NOISE = 1.0, 0.1, 0.3

DRIVE_PREAMBLE = ["# ServoDrive X2 trace export", "# axis: X1 (rack and pinion, 20 mm/rev)",
                  "# trigger: manual", "# sample rate: 1500 Hz", "# channels: 3"]
LOADCELL_PREAMBLE = ["LoadCell DAQ v4.1", "channel 0: carriage force, 2000 S/s", "units: s, N"]


def _rows(columns) -> str:
    return "\n".join(",".join(f"{c:.9g}" for c in row) for row in zip(*columns)) + "\n"


def export(signals, seed: int = 0):
    """The two files' text, (drive.csv, loadcell.csv), of the true ``signals`` of a run."""
    rng = np.random.default_rng(seed)
    d = slice(None, None, DRIVE_STEP)
    rpm = signals["v"][d] / METERS_PER_S_PER_RPM + SPEED_NOISE_RPM * rng.standard_normal(signals["t"][d].size)
    rpm = np.round(rpm / SPEED_STEP_RPM) * SPEED_STEP_RPM
    drive = "\n".join(DRIVE_PREAMBLE) + "\nTime [s],Position [mm],Speed [rpm]\n" + _rows(
        [signals["t"][d], 1e3 * signals["x"][d], rpm])
    c = slice(None, None, LOADCELL_STEP)
    force = signals["force"][c] + FORCE_NOISE * rng.standard_normal(signals["t"][c].size)
    loadcell = "\n".join(LOADCELL_PREAMBLE) + "\nTimestamp [s],Load [N]\n" + _rows(
        [signals["t"][c] - LOADCELL_LAG, force])
    return drive, loadcell


def truth() -> dict:
    return {"positive": FRICTION.positive.to_dict(), "negative": FRICTION.negative.to_dict(),
            "mass": SweepRun().mass}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-o", "--output", default="rig", help="folder to write (default rig/)")
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args(argv)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    drive, loadcell = export(simulate_sweep_run(FRICTION), args.seed)
    (out / "drive.csv").write_text(drive)
    (out / "loadcell.csv").write_text(loadcell)
    (out / "truth.json").write_text(json.dumps(truth(), indent=1) + "\n")
    print(f"wrote {out / 'drive.csv'}, {out / 'loadcell.csv'} and {out / 'truth.json'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
