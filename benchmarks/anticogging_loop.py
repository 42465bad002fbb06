"""Anticogging in the loop: fricgen's cogging map against ODrive's integrator map and the truth.

Axes of fricgen/sim/servo_axis.py (a PMSM with slot/pole cogging, an unbalance, a torque ripple
proportional to the current, friction that varies along the turn, a quantized encoder and a
cascaded P/PI loop at 8 kHz), one per seed from 1000 up (none tuned anything here), rotary
with 12- and 14-bit encoders and a linear motor (12 bits per pole pitch), and the rotary 12-bit
axes again with the measured loop at ODrive's default gains (``ODRIVE_DEFAULTS``; calibrated at
the axis's own). ``--case PREFIX`` runs only the cases whose name starts with it. Per axis:

1. fricgen's map: ``identify_cogging`` on calibrations of 2 turns each way in all at 1 rad/s
   logged at the drive's rate (force = kt i): by default two of one turn each way, the second
   with the first one's map fed forward (``anticogging_map.two_pass_fit``; ``--passes 1``: one
   of two turns).
2. The integrator map, as ODrive's anticogging calibration builds it: the drive creeps 5 turns
   each way under position control and the velocity integrator (A) is averaged in each of 3600
   bins of the measured theta (the encoder's counts if fewer), per direction, the two
   directions then averaged (their friction cancels); bins never visited are interpolated.
   The creep is min(0.5, 7.5 / L) rad/s, L the cogging's periods per turn (the motor's slots
   and poles, which its user knows): averaged over both directions the integrator holds the
   share 1 / (1 + (w kv / ki)^2) of a harmonic at w rad/s (ki / kv = 94 rad/s), 0.994 at the
   fundamental's 7.5 rad/s. On seed 1001 at 14 bits (L = 144) a creep of 0.5 rad/s leaves
   the map's error at 0.39 (share 0.63), 0.1 rad/s at 0.04 and its ripple at 2 rad/s 16 %
   above 0.05 rad/s's; on the axes of small L a slower creep than 7.5 / L gains nothing.
3. The loop with four compensations added to the current command at the measured theta: none,
   fricgen's map / kt, the integrator map (by bin), the exact position torque / kt averaged
   over each count (``ServoAxis.cogging_per_count``: the best a table of the counts can hold;
   not quite the best compensation, for the torque ripple scales the current that cancels the
   cogging, and fricgen's map, measured in current, holds that).

   a. Velocity ripple: position ramps at 0.5, 1 and 2 rad/s, one turn forward and one back,
      each after 0.5 s of settling; the RMS of the true omega minus the ramp's speed, and the
      RMS of its part at the position torque's orders (the unbalance's 1 and the cogging's
      multiples of L; least squares on their cos and sin of the true theta, per direction).
      The first holds the encoder's floor: the count edges through the PLL's velocity estimate
      drive a ripple that no map removes. The second is the ripple the position torque drives,
      which a map is for.
   b. Position error at rest: steps to 20 targets (each within 0.1 rad of the last), held
      0.6 s; |theta - target| averaged over the hold after 0.2 s, in encoder counts; the mean
      and the largest over the targets.

Printed per case: medians over seeds, then per seed the map's relative error (RMS over the
encoder's counts of map - the truth averaged over each count, ``ServoAxis.map_error``, over the
RMS of the truth minus its mean: the drive reads whole counts, and the map is a function of
them, so the truth at the count's lower edge would count half a count of phase as error, 9 %
on a 12-bit axis of 120 periods per turn; the integrator map's over its bins, against the truth
averaged over each bin), the ripple ratios at each speed, and the share of
seeds meeting each target, for each measure of the ripple. Speeds are rad/s of theta (the pole
pair's phase for the linear motor). ripple(none) / ripple(exact) is printed as the ceiling of
the first ratio: no map reduces the ripple that the encoder's counts cause. Beside the ratios at
the orders, exact/floor: the exact map's ripple there over the same fit at orders 2 above (where
no position torque acts); near 1, a ratio of two compensations at the orders is one of noise.

    python benchmarks/anticogging_loop.py [--seeds 10] [--quick]

Targets: ripple(none) / ripple(fricgen) >= 4; ripple(fricgen) / ripple(exact) <= 1.2;
ripple(fricgen) / ripple(integrator map) <= 1.0.
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
from dataclasses import replace                         # noqa: E402
from pathlib import Path                                # noqa: E402

import numpy as np                                      # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fricgen.errors import DataError                    # noqa: E402
from anticogging_map import two_pass_fit                 # noqa: E402
from fricgen.fit.cogging import identify_cogging        # noqa: E402
from fricgen.sim.servo_axis import (TWO_PI, Drive, calibration_move, count_lookup, map_feedforward,  # noqa: E402
                                     random_axis, run)

#: ODrive's default tuning (firmware 0.5: pos_gain 20 (turn/s)/turn, vel_gain 1/6 Nm/(turn/s),
#: vel_integrator_gain 1/3 Nm/turn, encoder bandwidth 1000 rad/s) in the axis's units
#: (A through kt). The calibrations run on the axis's own stiffer tuning, as ODrive's guide
#: raises the gains to calibrate; only the loop that is measured runs on these.
ODRIVE_DEFAULTS = {"kp": 20.0, "kv": 1.0 / 6.0 / TWO_PI, "ki": 1.0 / 3.0 / TWO_PI,
                   "pll_bandwidth": 1000.0}
#: (case, encoder bits, linear motor, the measured loop's tuning: None for the axis's own).
CASES = (("rotary 12 bit", 12, False, None), ("rotary 14 bit", 14, False, None),
         ("linear 12 bit", 12, True, None),
         ("rotary 12 bit, ODrive's default gains", 12, False, ODRIVE_DEFAULTS))
COMPENSATIONS = ("none", "fricgen", "integrator", "exact")
#: fricgen's calibration: turns each way at this speed (rad/s of theta).
CALIBRATION_TURNS, CALIBRATION_SPEED = 2.0, 1.0
#: The integrator map: turns each way, creeping at the speed (rad/s, at most MAX_CREEP) that
#: puts the cogging's fundamental at CREEP_WAVE rad/s; ODrive's bins per turn.
CREEP_TURNS, CREEP_WAVE, MAX_CREEP = 5, 7.5, 0.5
MAP_BINS = 3600
#: Time (s) after each start left out of a measurement (the loop settling).
SETTLE = 0.5
#: Velocity ripple: ramp speeds (rad/s), one turn each way.
SPEEDS = (0.5, 1.0, 2.0)
#: Position error at rest: TARGETS steps of at most STEP rad, held HOLD s, measured after SKIP s.
TARGETS, STEP, HOLD, SKIP = 20, 0.1, 0.6, 0.2
#: Targets: ripple(none) / ripple(fricgen), ripple(fricgen) / ripple(exact) and
#: ripple(fricgen) / ripple(integrator) against these (the first at least, the others at most).
BETTER_THAN_NONE, NEAR_EXACT, BETTER_THAN_INTEGRATOR = 4.0, 1.2, 1.0


def map_bins(counts: int) -> int:
    """The integrator map's bins per turn: ODrive's 3600, or the encoder's counts if fewer."""
    return min(MAP_BINS, counts)


def creep_speed(axis) -> float:
    """The integrator map's creep (rad/s): the cogging's fundamental at CREEP_WAVE rad/s."""
    return min(MAX_CREEP, CREEP_WAVE / axis.period_count)


def integrator_map(axis) -> np.ndarray:
    """The integrator map (A per bin, see the module docstring)."""
    counts, rate = axis.counts, axis.rate
    bins, quantum = map_bins(counts), TWO_PI / counts
    span, speed = CREEP_TURNS * TWO_PI, creep_speed(axis)
    steps, settle = int(span / speed * rate), int(SETTLE * rate)
    drive = Drive(axis)
    directions = []
    for sign, start in ((1, 0.0), (-1, span)):
        total, visits = [0.0] * bins, [0] * bins
        for k in range(steps):
            drive.step(start + sign * speed * k / rate, sign * speed, True)
            if k >= settle:
                b = math.floor(drive.theta / quantum) % counts * bins // counts
                total[b] += drive.integrator
                visits[b] += 1
        for _ in range(settle):                               # at rest before turning back
            drive.step(start + sign * span, 0.0, True)
        total, visits = np.array(total), np.array(visits)
        seen, centre = visits > 0, np.arange(bins)
        directions.append(np.interp(centre, centre[seen], total[seen] / visits[seen], period=bins))
    return (directions[0] + directions[1]) / 2


def fricgen_map(axis, passes: int = 2):
    """fricgen's map from CALIBRATION_TURNS each way: one calibration, or two of half as many
    turns, the second with the first map fed forward (``anticogging_map.two_pass_fit``); None
    when it finds none or refuses the log."""
    try:
        if passes == 2:
            return two_pass_fit(axis, CALIBRATION_TURNS, CALIBRATION_SPEED, axis.pitch).map
        log = calibration_move(axis, CALIBRATION_TURNS, CALIBRATION_SPEED, every=1)
        return identify_cogging(log["t"], log["x"], axis.kt * log["i"], axis.pitch).map
    except DataError:
        return None


def feedforwards(axis, cogging_map, integrator) -> dict:
    """Each compensation as a function of the measured theta (A), None for none."""
    counts = axis.counts
    return {"exact": count_lookup(axis.cogging_per_count() / axis.kt, counts),
            "integrator": count_lookup(integrator[np.arange(counts) * map_bins(counts) // counts], counts),
            "none": None, "fricgen": map_feedforward(axis, cogging_map)}


def orders(axis) -> list:
    """The orders per turn of the position torque a map compensates: the unbalance's (1) and the
    cogging's multiples of L."""
    return sorted({1, *((j + 1) * axis.period_count for j in range(len(axis.cogging)))})


def order_part(error: np.ndarray, theta: np.ndarray, ks: list) -> np.ndarray:
    """The part of ``error`` at the orders ``ks`` of theta (least squares on their cos and sin):
    the ripple the position torque drives, without the encoder's count-by-count noise."""
    basis = np.column_stack([f(k * theta) for k in ks for f in (np.cos, np.sin)])
    coef, *_ = np.linalg.lstsq(basis, error, rcond=None)
    return basis @ coef


def ripple(axis, feedforward, speed: float) -> tuple:
    """Over one turn forward and one back, each after SETTLE: the RMS of the true omega - speed,
    the RMS of its part at the position torque's orders (``order_part``, per direction), and
    the floor of the second: the RMS of its part at as many orders 2 above them (orthogonal to
    them over a turn), where no position torque acts: what the encoder's broadband ripple alone
    leaves in such a fit."""
    settle, turn = int(SETTLE * axis.rate), int(TWO_PI / speed * axis.rate)
    t = np.arange(settle + turn) / axis.rate
    theta = np.concatenate([speed * t, speed * (t[-1] - t)])
    omega = np.concatenate([np.full(t.size, speed), np.full(t.size, -speed)])
    log = run(Drive(axis, feedforward), theta, omega, every=1)
    error = log["omega"] - omega
    passes = (slice(settle, t.size), slice(t.size + settle, None))
    total = np.concatenate([error[p] for p in passes])
    synchronous = np.concatenate([order_part(error[p], log["theta"][p], orders(axis)) for p in passes])
    off = [k + 2 for k in orders(axis)]
    floor = np.concatenate([order_part(error[p], log["theta"][p], off) for p in passes])
    return tuple(float(np.sqrt(np.mean(e ** 2))) for e in (total, synchronous, floor))


def hold_error(axis, feedforward, targets: np.ndarray) -> np.ndarray:
    """Per target, the mean |theta - target| (counts) over the hold after SKIP."""
    hold, skip = int(HOLD * axis.rate), int(SKIP * axis.rate)
    theta = np.repeat(targets, hold)
    log = run(Drive(axis, feedforward), theta, np.zeros(theta.size), every=1)
    error = np.abs(log["theta"] - theta).reshape(targets.size, hold) / (TWO_PI / axis.counts)
    return error[:, skip:].mean(axis=1)


def integrator_error(axis, integrator: np.ndarray) -> float:
    """RMS over the bins of kt times the integrator map - the truth averaged over the bin, over
    the RMS of the truth minus its mean."""
    bins = integrator.size
    theta = (np.arange(bins)[:, None] + (np.arange(16)[None, :] + 0.5) / 16) * TWO_PI / bins
    truth = axis.cogging_torque(theta)
    return float(np.sqrt(np.mean((axis.kt * integrator - truth.mean(axis=1)) ** 2)) / np.std(truth))


def one(job) -> dict:
    """The measurements of one (case, bits, linear, seed)."""
    case, bits, linear, tuning, seed, passes = job
    start = time.perf_counter()
    axis = random_axis(seed, bits=bits, linear=linear)
    cogging_map = fricgen_map(axis, passes)
    integrator = integrator_map(axis)
    lookup = feedforwards(axis, cogging_map, integrator)
    if tuning is not None:
        axis = replace(axis, **{k: (v / axis.kt if k in ("kv", "ki") else v) for k, v in tuning.items()})
    targets = np.cumsum(np.random.default_rng(seed).uniform(-STEP, STEP, TARGETS))
    return {"case": case, "seed": seed, "periods": axis.period_count,
            "harmonics": () if cogging_map is None else cogging_map.harmonics,
            "map error": axis.map_error(cogging_map),
            "integrator error": integrator_error(axis, integrator),
            "ripple": {(c, s): ripple(axis, lookup[c], s) for c in COMPENSATIONS for s in SPEEDS},
            "hold": {c: hold_error(axis, lookup[c], targets) for c in COMPENSATIONS},
            "seconds": time.perf_counter() - start}


#: The two measures of ``ripple``: the whole ripple, and its part at the position torque's orders.
MEASURES = ("ripple", "ripple at the cogging's orders")


def ratios(r: dict, speed: float, measure: int = 0) -> tuple:
    """none / fricgen, fricgen / exact, fricgen / integrator, none / exact at ``speed``."""
    rip = {c: r["ripple"][c, speed][measure] for c in COMPENSATIONS}
    return (rip["none"] / rip["fricgen"], rip["fricgen"] / rip["exact"],
            rip["fricgen"] / rip["integrator"], rip["none"] / rip["exact"])


def floor_ratio(r: dict, speed: float) -> float:
    """The exact compensation's ripple at the orders over its floor (``ripple``) at ``speed``:
    near 1, what is left at the orders is the encoder's broadband ripple, and a ratio of two
    compensations there is a ratio of noise."""
    _, at_orders, floor = r["ripple"]["exact", speed]
    return at_orders / floor


def report(case: str, rows: list) -> None:
    """The case's table of medians, the per-seed ratios and the share meeting each target, for
    each measure of the ripple."""
    print(f"\n{case}: medians over {len(rows)} seeds")
    print(f"  {'':42s}" + "".join(f"{c:>11s}" for c in COMPENSATIONS))
    for m, measure in enumerate(MEASURES):
        for s in SPEEDS:
            cells = [np.median([r["ripple"][c, s][m] for r in rows]) for c in COMPENSATIONS]
            label = f"{'ripple' if m == 0 else 'at the orders'} at {s:g} rad/s (rad/s RMS)"
            print(f"  {label:42s}" + "".join(f"{v:11.4f}" for v in cells))
    for label, stat in (("mean", np.mean), ("max", np.max)):
        cells = [np.median([stat(r["hold"][c]) for r in rows]) for c in COMPENSATIONS]
        print(f"  {f'error at rest, {label} (counts)':42s}" + "".join(f"{v:11.3f}" for v in cells))
    speeds = " ".join(f"{s:g}" for s in SPEEDS)
    for m, measure in enumerate(MEASURES):
        print(f"  {measure}, per seed (ratios at {speeds} rad/s; ceiling = none / exact):")
        print(f"  {'seed':>5s} {'L':>4s} {'map err':>8s} {'intgr err':>9s}  {'none/fricgen':>18s}  "
              f"{'fricgen/exact':>18s}  {'fricgen/intgr':>18s}  {'ceiling':>18s}  "
              + (f"{'exact/floor':>18s}  " if m else "") + "harmonics")
        for r in sorted(rows, key=lambda r: r["seed"]):
            cols = list(zip(*(ratios(r, s, m) for s in SPEEDS)))
            print(f"  {r['seed']:5d} {r['periods']:4d} {r['map error']:8.3f} {r['integrator error']:9.3f}  "
                  + "  ".join(" ".join(f"{v:5.2f}" for v in col).rjust(18) for col in cols)
                  + ("  " + " ".join(f"{floor_ratio(r, s):5.2f}" for s in SPEEDS).rjust(18) if m else "")
                  + f"  {','.join(map(str, r['harmonics'])) or 'no map'}")
        for label, k, met in (("none/fricgen >= 4", 0, lambda v: v >= BETTER_THAN_NONE),
                              ("fricgen/exact <= 1.2", 1, lambda v: v <= NEAR_EXACT),
                              ("fricgen/integrator <= 1.0", 2, lambda v: v <= BETTER_THAN_INTEGRATOR),
                              ("(ceiling none/exact >= 4)", 3, lambda v: v >= BETTER_THAN_NONE)):
            shares = [sum(met(ratios(r, s, m)[k]) for r in rows) for s in SPEEDS]
            every = sum(all(met(ratios(r, s, m)[k]) for s in SPEEDS) for r in rows)
            print(f"  {label:26s} met at " + ", ".join(f"{s:g} rad/s {n}/{len(rows)}"
                                                        for s, n in zip(SPEEDS, shares))
                  + f"; at every speed {every}/{len(rows)}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--quick", action="store_true", help="3 seeds")
    ap.add_argument("--case", help="only the cases whose name starts with this")
    ap.add_argument("--passes", type=int, choices=(1, 2), default=2,
                    help="fricgen's calibration: one of 2 turns each way, or two of one (default)")
    args = ap.parse_args(argv)
    seeds = range(1000, 1000 + (3 if args.quick else args.seeds))
    cases = [c for c in CASES if args.case is None or c[0].startswith(args.case)]
    jobs = [(*case, seed, args.passes) for seed in seeds for case in cases]
    start = time.perf_counter()
    results = []
    with multiprocessing.Pool(2) as pool:
        for k, r in enumerate(pool.imap_unordered(one, jobs), 1):
            results.append(r)
            print(f"  {k}/{len(jobs)} axes ({r['case']}, seed {r['seed']}: {r['seconds']:.0f} s), "
                  f"{time.perf_counter() - start:.0f} s", file=sys.stderr, flush=True)
    print(f"seeds {seeds.start}-{seeds.stop - 1}; fricgen's map: {CALIBRATION_TURNS:g} turns each "
          f"way at {CALIBRATION_SPEED:g} rad/s in {args.passes} calibration(s); integrator map: {CREEP_TURNS} turns each way at "
          f"min({MAX_CREEP:g}, {CREEP_WAVE:g} / L) rad/s, {MAP_BINS} bins (the counts if fewer); "
          f"ripple over one turn each way; error at rest over the last {HOLD - SKIP:g} s of "
          f"{TARGETS} holds")
    for case, *_ in cases:
        report(case, [r for r in results if r["case"] == case])
    print(f"\n{time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
