"""Time and peak memory of train, eval and diagnose against the number of rows.

For each size it writes the input (a paper-benchmark sweep with uniform +-0.5 N noise; a
closed-loop log of `fricgen synth-log`, repeated end to end with continuous position), runs the
command in a fresh process and prints wall time, peak resident memory and the growth exponent
(log-log slope between the two largest sizes). It also prints the time of `fricgen --version`
and `--help`, and the accuracy of binning: the RMSE against the true curve on (0, v_sat] of a
model trained on the binned rows (the default) and on every row, side by side.

    python benchmarks/scale.py [--sizes 1e3,1e4,1e5,1e6,2e6] [--log-sizes 1e4,1e5,1e6,2e6]

Targets (reliability issue): train and diagnose on 2e6 rows in < 30 s and < 1 GB; eval memory
flat; --version and --help < 0.3 s.
"""
import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from fricgen.data import prepare, read_sweep_csv, training_set
from fricgen.fit import default_elm
from fricgen.friction import preset
from fricgen.model import FrictionModel
from fricgen.sim.logsynth import LogSpec, synthesize_log

def measure(argv, stdin=None):
    """(seconds, peak MiB, exit code) of ``argv`` run in a process of its own."""
    code = ("import resource, subprocess, sys, time\n"
            "stdin = open(sys.argv[1]) if sys.argv[1] != '-' else None\n"
            "start = time.perf_counter()\n"
            "rc = subprocess.run(sys.argv[2:], stdin=stdin, stdout=subprocess.DEVNULL).returncode\n"
            "print(time.perf_counter() - start, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, rc)")
    out = subprocess.run([sys.executable, "-c", code, stdin or "-", *argv], capture_output=True,
                         text=True, check=True).stdout.split()
    return float(out[0]), float(out[1]) / 1024.0, int(out[2])


def write_sweep(path, n, seed=0):
    """n rows: two thirds uniform in [0, 3 vs_max], one third in (3, 10] vs_max."""
    friction, rng = preset("paper3"), np.random.default_rng(seed)
    v = np.concatenate([rng.uniform(0, 0.06, n - n // 3), rng.uniform(0.06, 0.2, n // 3)])
    f = friction(v) + rng.uniform(-0.5, 0.5, v.size)
    with open(path, "w") as fh:
        fh.write("v,f\n")
        np.savetxt(fh, np.column_stack([v, f]), delimiter=",", fmt="%.17g")


def write_log(path, n, base):
    reps = -(-n // len(base))
    ts = base.sample_time
    shift = base.x[-1] - base.x[0] + base.v[-1] * ts
    cols = [np.arange(reps * len(base))[:n] * ts,
            np.concatenate([base.x + k * shift for k in range(reps)])[:n],
            np.tile(base.v, reps)[:n], np.tile(base.i, reps)[:n]]
    with open(path, "w") as fh:
        fh.write("t,x,v,i\n")
        np.savetxt(fh, np.column_stack(cols), delimiter=",", fmt="%.17g")


def slope(sizes, values):
    return float(np.log(values[-1] / values[-2]) / np.log(sizes[-1] / sizes[-2]))


def table(name, sizes, rows):
    print(f"\n== {name} ==")
    print(f"{'rows':>10s} {'seconds':>9s} {'peak MiB':>9s}")
    for n, (sec, mib, rc) in zip(sizes, rows):
        print(f"{n:10.0f} {sec:9.2f} {mib:9.0f}" + ("" if rc == 0 else f"   exit {rc}"))
    secs, mibs = [r[0] for r in rows], [r[1] for r in rows]
    print(f"growth exponent (last two sizes): time {slope(sizes, secs):.2f}, memory {slope(sizes, mibs):.2f}")


def binning_accuracy(folder, sizes):
    """RMSE (N) against the true curve on (0, v_sat] of the default model trained on the binned
    rows and on every row of the same sweep."""
    print("\n== binning: RMSE against the true curve on (0, v_sat], default model ==")
    print(f"{'rows':>10s} {'binned N':>10s} {'all rows N':>11s} {'ratio':>7s}")
    friction = preset("paper3")
    v = np.linspace(1e-4, 0.06, 2000)
    for n in sizes:
        path = folder / f"acc{n}.csv"
        write_sweep(path, int(n), seed=1)
        sweep = read_sweep_csv(path)
        errs = []
        for cap in (training_set.MAX_TRAINING_POINTS, 10 ** 9):
            saved = training_set.MAX_TRAINING_POINTS
            training_set.MAX_TRAINING_POINTS = cap
            try:
                model = FrictionModel.fit(prepare(sweep, vs_max=0.02), default_elm(0))
            finally:
                training_set.MAX_TRAINING_POINTS = saved
            errs.append(float(np.sqrt(np.mean((model.force(v) - friction(v)) ** 2))))
        print(f"{n:10.0f} {errs[0]:10.4f} {errs[1]:11.4f} {errs[0] / errs[1]:7.3f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="1e3,1e4,1e5,1e6,2e6")
    ap.add_argument("--log-sizes", default="1e4,1e5,1e6,2e6")
    ap.add_argument("--accuracy-sizes", default="1e4,3e4")
    args = ap.parse_args()
    sizes = [int(float(s)) for s in args.sizes.split(",")]
    log_sizes = [int(float(s)) for s in args.log_sizes.split(",")]
    fricgen = [sys.executable, "-m", "fricgen"]
    with tempfile.TemporaryDirectory(prefix="fricgen_scale_") as tmp:
        folder = Path(tmp)
        for flag in ("--version", "--help"):
            best = min(measure(fricgen + [flag])[0] for _ in range(3))
            print(f"fricgen {flag}: {best:.3f} s (best of 3)")
        write_sweep(folder / "model_sweep.csv", 300)
        model = folder / "model.json"
        subprocess.run(fricgen + ["train", str(folder / "model_sweep.csv"), "-o", str(model),
                                  "--vs-max", "0.02"], check=True, capture_output=True)
        train, evals = [], []
        for n in sizes:
            sweep = folder / f"sweep{n}.csv"
            write_sweep(sweep, n)
            train.append(measure(fricgen + ["train", str(sweep), "-o", str(folder / "m.json"),
                                            "--vs-max", "0.02", "--force"]))
            velocities = folder / f"v{n}.txt"
            np.savetxt(velocities, np.random.default_rng(n).uniform(-0.2, 0.2, n), fmt="%.17g")
            evals.append(measure(fricgen + ["eval", str(model)], stdin=str(velocities)))
            sweep.unlink()
            velocities.unlink()
        table("train (sweep rows)", sizes, train)
        table("eval (velocities on stdin)", sizes, evals)
        base = synthesize_log(LogSpec(duration=60.0, seed=1))
        diag = []
        for n in log_sizes:
            log = folder / f"log{n}.csv"
            write_log(log, n, base)
            diag.append(measure(fricgen + ["diagnose", str(log), "--model", str(model), "--mass", "4",
                                           "--force-constant", "20", "-o", str(folder / "d"),
                                           "--force"]))
            log.unlink()
        table("diagnose (log samples)", log_sizes, diag)
        binning_accuracy(folder, [int(float(s)) for s in args.accuracy_sizes.split(",")])
        print("\n" + json.dumps({"train": train, "eval": evals, "diagnose": diag}))


if __name__ == "__main__":
    main()
