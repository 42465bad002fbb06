"""Anticogging in the loop: fricgen's cogging map against ODrive's integrator-sampling map.

DRAFT
"""
from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse                                         # noqa: E402
import math                                             # noqa: E402
import multiprocessing                                  # noqa: E402
import sys                                              # noqa: E402
import time                                             # noqa: E402
from pathlib import Path                                # noqa: E402

import numpy as np                                      # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fricgen.fit.cogging import identify_cogging        # noqa: E402
from fricgen.sim.servo_axis import TWO_PI, Drive, calibration_move, random_axis, run  # noqa: E402

CASES = (("rotary 12 bit", 12, False), ("rotary 14 bit", 14, False), ("linear 12 bit", 12, True))
COMPENSATIONS = ("none", "fricgen", "integrator", "exact")
#: fricgen's calibration: turns each way at this speed (rad/s of theta), logged every period.
CALIBRATION_TURNS, CALIBRATION_SPEED = 2.0, 1.0
#: The integrator map: turns each way at a creep (rad/s), ODrive's bins per revolution, and the
#: time after each start that is left out (the loop settling).
CREEP_TURNS, CREEP_SPEED = 5, 0.1
MAP_BINS = 3600
SETTLE = 0.5
#: Velocity ripple: speeds (rad/s), one revolution each way after SETTLE.
SPEEDS = (0.5, 1.0, 2.0)
#: Position error at rest: steps to TARGETS targets (each a uniform step of at most STEP rad from
#: the last), held HOLD s, measured after SKIP s.
TARGETS, STEP, HOLD, SKIP = 20, 0.1, 0.6, 0.2


def count_lookup(table, counts: int):
    """A feedforward (A) of the measured theta from a table of one value per encoder count."""
    table = [float(v) for v in table]
    quantum = TWO_PI / counts
    return lambda theta: table[int(round(theta / quantum)) % counts]


def map_bins(counts: int) -> int:
    return min(MAP_BINS, counts)


def integrator_map(axis) -> np.ndarray:
    """ODrive's map (A per bin): the velocity integrator while the drive creeps CREEP_TURNS
    each way at CREEP_SPEED, averaged per bin of the measured theta in each direction, the two
    directions' averages averaged (their friction cancels); empty bins interpolated."""
    bins, counts, rate = map_bins(axis.counts), axis.counts, axis.rate
    quantum = TWO_PI / counts
    drive = Drive(axis)
    span = CREEP_TURNS * TWO_PI
    steps = int(span / CREEP_SPEED * rate)
    skip = int(SETTLE * rate)
    means = []
    for direction in (1, -1):
        total, visits = [0.0] * bins, [0] * bins
        start = 0.0 if direction > 0 else span
        for k in range(steps):
            theta_ref = start + direction * CREEP_SPEED * k / rate
            drive.step(theta_ref, direction * CREEP_SPEED, True)
            if k >= skip:
                b = (int(round(drive.measured() / quantum)) % counts) * bins // counts
                total[b] += drive.integrator
                visits[b] += 1
        for k in range(int(SETTLE * rate)):                 # rest before the way back
            drive.step(start + direction * span, 0.0, True)
        total, visits = np.array(total), np.array(visits)
        seen = visits > 0
        centres = np.arange(bins)
        means.append(np.interp(centres, centres[seen], total[seen] / visits[seen], period=bins))
    return (means[0] + means[1]) / 2


def feedforwards(axis, cogging_map, imap) -> dict:
    """The compensation of each name as a function of the measured theta (A)."""
    counts = axis.counts
    theta = np.arange(counts) * TWO_PI / counts
    bins = map_bins(counts)
    out = {"none": None,
           "exact": count_lookup(axis.cogging_torque(theta) / axis.kt, counts),
           "integrator": count_lookup(imap[np.arange(counts) * bins // counts], counts)}
    if cogging_map is not None:
        out["fricgen"] = count_lookup(cogging_map.force(theta * axis.pitch / TWO_PI) / axis.kt, counts)
    else:
        out["fricgen"] = None
    return out


def ripple(axis, feedforward, speed: float) -> float:
    """RMS of the true omega - speed over one revolution each way, each after SETTLE s."""
    rate = axis.rate
    settle, turn = int(SETTLE * rate), int(TWO_PI / speed * rate)
    t = np.arange(settle + turn) / rate
    theta = np.concatenate([speed * t, speed * t[-1] - speed * t])
    omega = np.concatenate([np.full(t.size, speed), np.full(t.size, -speed)])
    log = run(Drive(axis, feedforward), theta, omega, position_loop=True, every=1)
    error = log["omega"] - omega
    window = np.r_[error[settle:t.size], error[t.size + settle:]]
    return float(np.sqrt(np.mean(window ** 2)))


def hold_error(axis, feedforward, targets) -> np.ndarray:
    """Per target: the mean |theta - target| over the hold after SKIP s."""
    rate = axis.rate
    hold, skip = int(HOLD * rate), int(SKIP * rate)
    theta = np.repeat(targets, hold)
    log = run(Drive(axis, feedforward), theta, np.zeros(theta.size), position_loop=True, every=1)
    error = np.abs(log["theta"] - theta).reshape(len(targets), hold)
    return error[:, skip:].mean(axis=1)


def relative_error(axis, cogging_map) -> float:
    """RMS over theta of map - truth over the RMS of the truth minus its mean."""
    theta = np.arange(1 << 16) * TWO_PI / (1 << 16)
    truth = axis.cogging_torque(theta)
    est = cogging_map.force(theta * axis.pitch / TWO_PI) if cogging_map is not None else 0.0
    return float(np.sqrt(np.mean((est - truth) ** 2)) / np.std(truth))
