"""``fricgen fleet`` on a synthetic fleet: drift recall, false flags, throughput and memory.

Every axis is drawn apart from fricgen (tests/independent_axis.py: a squared-rational Stribeck
drop and quadratic drag, not [F1]) and logged twice, a baseline and a newest log of the same
motion program with new sensor noise. A share of the axes (default 5 %) have their Coulomb
level and static friction grown by a known factor between the two logs (wear); the rest are
unchanged. The fleet runs on a real Dask LocalCluster. Printed:

- recall of the drifted axes, overall and where the true change of the Coulomb level is at
  least 3 of the identification's standard errors (the baseline's SE of that level), and the
  false-flag rate among the unchanged axes, at the default thresholds, then by the
  standard-error test alone (``--min-change 0``: a growth below the default's 10 % counts);
- throughput (logs per minute, cluster start-up excluded) with 1 and 2 worker processes on the
  same logs, and their ratio; peak resident memory of each worker (ru_maxrss).

With ``--cogging SHARE`` every axis also has a cogging (a position ripple at its pole pitch; the
logs hold no position), and on SHARE of the axes that do not drift it alone changes between the
logs: printed, the false flags among those.

    python benchmarks/fleet.py [--axes 1000] [--duration 60] [--throughput-logs 24]
                               [--cogging 0.05] [--skip-throughput]
"""
from __future__ import annotations

import argparse
import csv
import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from independent_axis import fleet_axis, fleet_log, write_fleet_log  # noqa: E402

from fricgen.cli import blas_env  # noqa: E402
from fricgen.cli.train import train_argv  # noqa: E402
from fricgen.fleet import Entry, run_fleet  # noqa: E402
from fricgen.fleet.drift import drift_table, latest  # noqa: E402

DRIFT_RANGE = (0.03, 0.30)      # the drifted axes' growth of Coulomb and static friction
#: With ``--cogging``: every axis's cogging (N, at the pole pitch, m), and the growth of the
#: cogging-changed axes' amplitude between the logs (a magnet shifted or weakened), with a new phase.
COGGING_RANGE, PITCH_RANGE, COGGING_GROWTH = (0.3, 1.5), (0.016, 0.064), (1.5, 3.0)


def make_fleet(folder: Path, axes: int, duration: float, share: float, seed: int,
               cogging_share: float = 0.0):
    """The logs and manifest entries; the drift factor of each axis (0 for unchanged), and the
    axes whose cogging alone changes (``cogging_share`` of those that do not drift; every axis
    has a cogging when it is > 0)."""
    rng = np.random.default_rng(seed)
    drifted = set(rng.choice(axes, size=max(1, round(share * axes)), replace=False).tolist())
    others = [a for a in range(axes) if a not in drifted]
    cogged = set(rng.choice(others, size=round(cogging_share * axes), replace=False).tolist()) \
        if cogging_share > 0 else set()
    drift, entries = {}, []
    for a in range(axes):
        axis = fleet_axis(seed * 100000 + a)
        if cogging_share > 0:
            axis.update(cogging=float(rng.uniform(*COGGING_RANGE)), pitch=float(rng.uniform(*PITCH_RANGE)))
        drift[f"ax{a:04d}"] = float(rng.uniform(*DRIFT_RANGE)) if a in drifted else 0.0
        for n, stamp in enumerate(("2024-01-01T00:00", "2024-02-01T00:00")):
            now = dict(axis)
            if n == 1:
                now["coulomb"] *= 1 + drift[f"ax{a:04d}"]
                now["static"] *= 1 + drift[f"ax{a:04d}"]
                if a in cogged:
                    now["cogging"] *= float(rng.uniform(*COGGING_GROWTH))
                    now["phase"] = float(rng.uniform(0, 2 * np.pi))
            path = folder / f"ax{a:04d}_{n}.csv"
            write_fleet_log(path, fleet_log(now, seed * 100000 + 2 * a + n, duration))
            entries.append(Entry(f"ax{a:04d}", str(path), stamp))
    return (entries, drift, {f"ax{a:04d}": fleet_axis(seed * 100000 + a) for a in range(axes)},
            {f"ax{a:04d}" for a in cogged})


def timed_run(entries, out: Path, workers: int):
    """(seconds, FleetRun, peak RSS MB per worker) of the fleet on a fresh LocalCluster."""
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           dashboard_address=None, env=blas_env())
    client = Client(cluster)
    try:
        start = time.perf_counter()
        run = run_fleet(entries, out, train_argv, scheduler=cluster.scheduler_address, progress=print_err)
        seconds = time.perf_counter() - start
        peaks = client.run(lambda: resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
    finally:
        client.close()
        cluster.close()
    return seconds, run, sorted(peaks.values())


def print_err(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--axes", type=int, default=1000)
    p.add_argument("--duration", type=float, default=60.0, help="seconds per log (1 kHz)")
    p.add_argument("--drifted", type=float, default=0.05, help="share of drifted axes")
    p.add_argument("--throughput-logs", type=int, default=24,
                   help="logs timed with 1 and with 2 workers (the same logs)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--cogging", type=float, default=0.0,
                   help="give every axis a cogging, and change it alone on this share of the axes")
    p.add_argument("--skip-throughput", action="store_true", help="the detection run only")
    p.add_argument("--folder", help="where the logs and OUT go (default: a temporary folder)")
    args = p.parse_args()
    folder = Path(args.folder or tempfile.mkdtemp(prefix="fleet-bench-"))
    folder.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    entries, drift, truth, cogged = make_fleet(folder, args.axes, args.duration, args.drifted, args.seed,
                                              args.cogging)
    print(f"{args.axes} axes, {len(entries)} logs of {args.duration:g} s in {folder} "
          f"({time.perf_counter() - t0:.0f} s to write)", flush=True)

    # throughput: the same logs on 1 and on 2 workers, each into a fresh OUT
    subset = entries[:args.throughput_logs]
    rates = {}
    for workers in (() if args.skip_throughput else (1, 2)):
        seconds, run, peaks = timed_run(subset, folder / f"out_throughput_{workers}", workers)
        rates[workers] = 60 * run.computed / seconds
        print(f"throughput {workers} worker(s): {run.computed} logs in {seconds:.1f} s = "
              f"{rates[workers]:.2f} logs/min; peak RSS per worker "
              + ", ".join(f"{m:.0f} MB" for m in peaks), flush=True)
    if rates:
        print(f"ratio 2 / 1 workers: {rates[2] / rates[1]:.2f}", flush=True)

    # detection: every log on 2 workers (the throughput run's results are not reused)
    seconds, run, peaks = timed_run(entries, folder / "out", 2)
    print(f"all {len(entries)} logs on 2 workers: {seconds:.0f} s "
          f"({60 * run.computed / seconds:.2f} logs/min), {run.failed} failed; peak RSS per worker "
          + ", ".join(f"{m:.0f} MB" for m in peaks), flush=True)
    rows = {r["axis"]: r for r in latest(run.rows)}
    first = {r["axis"]: r for r in run.rows if r["timestamp"].startswith("2024-01")}
    drifted = [a for a, d in drift.items() if d > 0]
    steady = [a for a, d in drift.items() if d == 0]
    ratio = {}
    for a in drifted:           # the true change of the Coulomb level in the baseline's SEs
        se = max(first[a]["coulomb_pos_se"], first[a]["coulomb_neg_se"])
        ratio[a] = drift[a] * truth[a]["coulomb"] / se
    big = [a for a in drifted if ratio[a] >= 3]
    hit = [a for a in drifted if rows[a]["flagged"]]
    false = [a for a in steady if rows[a]["flagged"]]
    print(f"drifted axes: {len(drifted)} (growth {DRIFT_RANGE[0]:.0%}-{DRIFT_RANGE[1]:.0%}); "
          f"flagged {len(hit)} = recall {len(hit) / len(drifted):.1%}")
    print(f"  of them with change >= 3 SE: {len(big)}, flagged "
          f"{sum(rows[a]['flagged'] for a in big)} = recall "
          f"{sum(rows[a]['flagged'] for a in big) / max(len(big), 1):.1%}")
    for a in drifted:
        print(f"    {a}: growth {drift[a]:.1%}, {ratio[a]:.0f} SE, flagged {rows[a]['flagged']} "
              f"({rows[a]['drifted'] or '-'})")
    print(f"unchanged axes: {len(steady)}; falsely flagged {len(false)} = {len(false) / len(steady):.2%}")
    if cogged:
        flagged = [a for a in cogged if rows[a]["flagged"]]
        print(f"  of them with a changed cogging alone: {len(cogged)}; falsely flagged {len(flagged)} = "
              f"{len(flagged) / len(cogged):.2%}" + "".join(f"\n    {a}: {rows[a]['drifted']}" for a in flagged))
    by = {}
    for a in false:
        for name in rows[a]["drifted"].split():
            by[name] = by.get(name, 0) + 1
    if by:
        print("  false flags by parameter: " + ", ".join(f"{k} {v}" for k, v in sorted(by.items())))
    alone = {r["axis"]: r for r in latest(drift_table(run.rows, min_change=0.0))}
    print(f"the standard-error test alone (--min-change 0): recall {sum(alone[a]['flagged'] for a in big)}"
          f"/{len(big)} at >= 3 SE, {sum(alone[a]['flagged'] for a in drifted)}/{len(drifted)} in all; "
          f"falsely flagged {sum(alone[a]['flagged'] for a in steady)}/{len(steady)}")
    with open(folder / "benchmark_axes.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["axis", "drift", "flagged", "drifted"])
        for a in sorted(drift):
            w.writerow([a, drift[a], rows[a]["flagged"], rows[a]["drifted"]])


if __name__ == "__main__":
    main()
