"""Time and peak memory of train, eval and diagnose against the number of rows.

For each size it writes the input (a paper-benchmark sweep with uniform +-0.5 N noise; a
closed-loop log of `fricgen synth-log`, repeated end to end with continuous position), runs the
command in a fresh process and prints wall time, peak resident memory and the growth exponent
(log-log slope between the two largest sizes). It also prints the time of `fricgen --version`
and `--help`, and the accuracy of binning: the RMSE against the true curve on (0, v_sat] of a
model trained on the binned rows (the default) and on every row, side by side.

    python benchmarks/scale.py [--sizes 1e3,1e4,1e5,1e6,2e6] [--log-sizes 1e4,1e5,1e6,2e6]
    python benchmarks/scale.py --sections models,elm,load     # the model-size figures only

Sections (``--sections``, default all): ``time`` (the above), ``models`` (rows 1e3..1e6 ->
default neurons, RMSE against the true curve, host ns per call of the emitted C measured by a
C harness, Cortex-M4F instructions from ``fricgen.codegen.cost``; medians over seeds),
``elm`` (``--method elm`` at 1e4 and 1e6 rows: RMSE against the true curve, C, the float32
twin's error against the float64 model on the parity velocities, on the solver's probes and on
10^6 inputs), ``load`` (``fricgen
train`` on 1e6 rows alone, beside one busy process, beside a second training and beside one
busy process per core, on one BLAS thread and on one per core; wall and CPU seconds).

Targets (reliability issue): train and diagnose on 2e6 rows in < 30 s and < 1 GB; eval memory
flat; --version and --help < 0.3 s. Model size: default neurons at 1e6 rows <= 1.2x those at
1e4 with the error still falling; ``--method elm`` error at 1e6 <= 0.5x at 1e4 within parity;
loaded train time <= 1.2x unloaded, loaded meaning one other CPU-bound process on the 2-core
machine (one core busy: with every core busy a single-threaded job gets 2/3 of a core, and 1.5x
is the CPU share alone).
"""
import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

for _key in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_key, "1")   # as the fricgen command does, before numpy loads

import numpy as np  # noqa: E402

from fricgen import codegen
from fricgen.codegen.cost import cortex_m4f_instructions
from fricgen.codegen.cbuild import build_model
from fricgen.codegen.parity import measure as measure_parity, parity_velocities
from fricgen.codegen.twin import force_f32
from fricgen.data import prepare, read_sweep_csv, training_set
from fricgen.fit import DEFAULT_ELM, ELMRegressor, default_elm
from fricgen.fit.elm import PARITY, TWIN_MARGIN, float32_twin_error, parity_limit, probe_inputs
from fricgen.friction import preset
from fricgen.model import FrictionModel
from fricgen.sim.logsynth import LogSpec, synthesize_log

#: A C program timing NAME_force (best of 5 runs of 4e5 calls over [-0.12, 0.12] m/s).
HOST_HARNESS = r"""
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <time.h>
#include "fm.h"
int main(void)
{
    volatile float sink = 0.0f;
    double best = 1e30;
    for (int rep = 0; rep < 5; rep++) {
        struct timespec a, b;
        const int n = 400000;
        clock_gettime(CLOCK_MONOTONIC, &a);
        for (int i = 0; i < n; i++)
            sink += fm_force(-0.12f + 0.24f * (float)(i % 4096) / 4096.0f);
        clock_gettime(CLOCK_MONOTONIC, &b);
        double ns = ((double)(b.tv_sec - a.tv_sec) * 1e9 + (double)(b.tv_nsec - a.tv_nsec)) / n;
        if (ns < best) best = ns;
    }
    printf("%.3f\n", best);
    return 0;
}
"""

def measure(argv, stdin=None):
    """(seconds, peak MiB, exit code, CPU seconds) of ``argv`` run in a process of its own."""
    code = ("import resource, subprocess, sys, time\n"
            "stdin = open(sys.argv[1]) if sys.argv[1] != '-' else None\n"
            "start = time.perf_counter()\n"
            "rc = subprocess.run(sys.argv[2:], stdin=stdin, stdout=subprocess.DEVNULL).returncode\n"
            "use = resource.getrusage(resource.RUSAGE_CHILDREN)\n"
            "print(time.perf_counter() - start, use.ru_maxrss, rc, use.ru_utime + use.ru_stime)")
    out = subprocess.run([sys.executable, "-c", code, stdin or "-", *argv], capture_output=True,
                         text=True, check=True).stdout.split()
    return float(out[0]), float(out[1]) / 1024.0, int(out[2]), float(out[3])


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
    for n, (sec, mib, rc, _) in zip(sizes, rows):
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


def host_ns(model, folder):
    """Nanoseconds per NAME_force call of the emitted C on this host (gcc -O2, glibc expf)."""
    folder.mkdir(parents=True, exist_ok=True)
    codegen.emit(model, folder, "fm")
    (folder / "bench_main.c").write_text(HOST_HARNESS)
    exe = folder / "bench"
    subprocess.run(["cc", "-O2", "-std=c99", "-ffp-contract=off", "-o", str(exe),
                    *map(str, sorted(folder.glob("*.c"))), "-lm"], check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    shutil.rmtree(folder)
    return float(out)


def true_rmse(model, friction):
    """RMSE (N) of the model against the true curve on (0, v_sat]."""
    v = np.linspace(1e-4, model.v_sat, 2000)
    return float(np.sqrt(np.mean((model.force(v) - friction(v)) ** 2)))


def sweep_dataset(folder, n, seed):
    path = folder / f"model_size_{n}_{seed}.csv"
    write_sweep(path, n, seed=seed)
    dataset = prepare(read_sweep_csv(path), vs_max=0.02)
    path.unlink()
    return dataset


def model_sizes(folder, sizes, seeds):
    """Default model per size and seed: neurons, RMSE against the true curve, host ns per call."""
    print("\n== default model (elm_auto) against rows: medians over seeds "
          + ",".join(map(str, seeds)) + " ==")
    print(f"{'rows':>10s} {'neurons':>8s} {'RMSE N':>8s} {'host ns':>8s} {'M4F instr':>10s}   "
          "per seed (neurons, RMSE N)")
    friction, rows = preset("paper3"), {}
    for n in sizes:
        per_seed = []
        for seed in seeds:
            model = FrictionModel.fit(sweep_dataset(folder, n, seed), default_elm(0), name="fm")
            per_seed.append((model.aim.n_hidden, true_rmse(model, friction), host_ns(model, folder / "host")))
        m, e, ns = (float(np.median([p[i] for p in per_seed])) for i in range(3))
        rows[n] = (m, e, ns)
        print(f"{n:10.0f} {m:8.0f} {e:8.4f} {ns:8.0f} {cortex_m4f_instructions(m):10.0f}   "
              + "  ".join(f"({p[0]}, {p[1]:.4f})" for p in per_seed), flush=True)
    if 10 ** 4 in rows and 10 ** 6 in rows:
        print(f"neurons at 1e6 / at 1e4: {rows[10 ** 6][0] / rows[10 ** 4][0]:.2f} (target <= 1.2); "
              f"RMSE falling with rows: {all(np.diff([r[1] for r in rows.values()]) < 0)}")
    return rows


def elm_improvement(folder, seed=1):
    """--method elm (40 enlarged sigmoids, C by leave-one-out within the parity bound) at 1e4 and
    1e6 rows: RMSE against the true curve; the float32 twin against the float64 model on the
    parity velocities, on the solver's probes and on a grid of 10^6 inputs."""
    print("\n== --method elm: RMSE against the true curve, float32 parity ==")
    print("twin: float32 twin on the parity velocities, / max|F|; probes: float32 network on the solver's "
          f"probes times the margin {TWIN_MARGIN}, / parity limit; dense: on 10^6 inputs in [0, 1], / limit; "
          "C: the emitted C (cffi) on 4e5 velocities in [-v_sat, v_sat], / max|F|")
    print(f"{'rows':>10s} {'C':>9s} {'RMSE N':>8s} {'||b||_1':>8s} {'twin':>9s} {'probes':>7s} "
          f"{'dense':>6s} {'dense/probes':>13s} {'C':>9s}")
    friction, errs = preset("paper3"), {}
    dense = np.linspace(0.0, 1.0, 10 ** 6 + 1).astype(np.float32)
    for n in (10 ** 4, 10 ** 6):
        dataset = sweep_dataset(folder, n, seed)
        est = ELMRegressor(**{**DEFAULT_ELM, "random_state": 0})
        model = FrictionModel.fit(dataset, est, name="fm")
        v = parity_velocities(model.v_sat)
        v = v[np.abs(v) <= 2 * model.v_sat]
        exact = model.force(v.astype(float))
        twin = float(np.max(np.abs(force_f32(model, v) - exact))) / np.max(np.abs(exact))
        limit = parity_limit(dataset.t)
        probes = float32_twin_error(est.network_, probe_inputs(dataset.x)) / limit
        on_dense = float32_twin_error(est.network_, dense) / limit
        errs[n] = true_rmse(model, friction)
        emitted = folder / f"parity{n}"
        codegen.emit(model, emitted, "fm")
        lib = build_model(emitted, "fm", build_dir=emitted / "build")
        v = np.linspace(-model.v_sat, model.v_sat, 400_001).astype(np.float32)
        c_rel = measure_parity(model, lib, "fm", v)["max_rel_c_vs_model"]
        print(f"{n:10.0f} {est.C_:9.3g} {errs[n]:8.4f} {np.abs(est.beta_).sum():8.1f} {twin:9.2e} "
              f"{TWIN_MARGIN * probes:7.2f} {on_dense:6.2f} {on_dense / probes:13.2f} {c_rel:9.2e}", flush=True)
    print(f"--method elm RMSE at 1e6 / at 1e4: {errs[10 ** 6] / errs[10 ** 4]:.2f} (target <= 0.5; "
          f"parity: twin and C <= {PARITY:g}, probes <= 1)")
    return errs


def background(kind, argv, cores):
    """Processes of my own that load the machine while train is measured: ``train`` runs the same
    training in a loop beside it, ``busy`` one ``yes > /dev/null``, ``busy/core`` one per core."""
    if kind == "train":
        loop = "while true; do " + " ".join(f"'{a}'" for a in argv) + " > /dev/null 2>&1; done"
        return [subprocess.Popen(["sh", "-c", loop], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                 start_new_session=True)]
    count = {"busy": 1, "busy/core": cores}.get(kind, 0)
    return [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                             start_new_session=True) for _ in range(count)]


def stop(procs):
    for proc in procs:
        os.killpg(proc.pid, 15)   # the group this benchmark started for it
        proc.wait()


#: The loads of ``loaded_train``, by column: nothing, one other CPU-bound process (``yes``), a
#: second training (CPU-bound and using caches and memory as train does), one busy process per core.
LOADS = ("none", "busy", "train", "busy/core")


def loaded_train(folder, n=10 ** 6, repeats=3, blas_threads=None):
    """fricgen train on n rows alone and beside each load of ``LOADS``, on one BLAS thread (the
    default) and on one per core (FRICGEN_BLAS_THREADS); wall and CPU seconds, best of
    ``repeats``, the loads interleaved repeat by repeat so that a change of the machine's other
    load reaches every column alike."""
    cores = os.cpu_count() or 1
    sweep = folder / "load_sweep.csv"
    write_sweep(sweep, n)
    train = [sys.executable, "-m", "fricgen", "train", str(sweep), "--vs-max", "0.02", "--force", "-o"]
    print(f"\n== fricgen train on {n:.0e} rows: seconds, best of {repeats}, {cores} cores ==")
    print(f"load average before: {' '.join(f'{a:.2f}' for a in os.getloadavg())}")
    print(f"{'BLAS threads':>12s} " + " ".join(f"{'+ ' + k if k != 'none' else 'alone':>11s}" for k in LOADS)
          + "   wall loaded/alone; CPU seconds loaded/alone")
    results = {}
    for threads in blas_threads or ("1", str(cores)):
        os.environ["FRICGEN_BLAS_THREADS"] = threads
        runs = {load: [] for load in LOADS}
        for _ in range(repeats):
            for load in LOADS:
                procs = background(load, train + [str(folder / "other.json")], cores)
                try:
                    runs[load].append(measure(train + [str(folder / "load.json")]))
                finally:
                    stop(procs)
        del os.environ["FRICGEN_BLAS_THREADS"]
        for load in LOADS:
            results[(threads, load)] = (min(r[0] for r in runs[load]), min(r[3] for r in runs[load]))
        wall, cpu = results[(threads, "none")]
        print(f"{threads:>12s} " + " ".join(f"{results[(threads, k)][0]:11.2f}" for k in LOADS) + "   "
              + ", ".join(f"{results[(threads, k)][0] / wall:.2f}" for k in LOADS[1:]) + "; "
              + ", ".join(f"{results[(threads, k)][1] / cpu:.2f}" for k in LOADS[1:]), flush=True)
    print(f"load average after: {' '.join(f'{a:.2f}' for a in os.getloadavg())}")
    alone = results[("1", "none")][0]
    print(f"loaded = one other CPU-bound process on the {cores} cores, so a single-threaded train still "
          "has a core of its own and what slows it is the neighbour's use of caches and memory; "
          f"one BLAS thread: beside one busy process {results[('1', 'busy')][0] / alone:.2f} x alone, "
          f"beside a second training {results[('1', 'train')][0] / alone:.2f} x (target <= 1.2). "
          f"Beside {cores} busy processes a single-threaded job gets {cores}/{cores + 1} of a core: "
          f"{1 + 1 / cores:.2f} x is the CPU share alone, not the load's effect on train.")
    sweep.unlink()
    return results


def main():
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))   # stop the load processes on the way out
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="1e3,1e4,1e5,1e6,2e6")
    ap.add_argument("--log-sizes", default="1e4,1e5,1e6,2e6")
    ap.add_argument("--accuracy-sizes", default="1e4,3e4")
    ap.add_argument("--model-sizes", default="1e3,1e4,1e5,1e6")
    ap.add_argument("--seeds", default="0,1,2", help="seeds of the model-size sweeps")
    ap.add_argument("--sections", default="time,models,elm,load")
    ap.add_argument("--load-repeats", type=int, default=3, help="runs per column of the load section")
    ap.add_argument("--load-rows", default="1e6", help="rows of the load section's sweep")
    ap.add_argument("--load-blas", default=None,
                    help="BLAS thread counts of the load section, e.g. 1 (default: 1 and one per core)")
    args = ap.parse_args()
    sizes = [int(float(s)) for s in args.sizes.split(",")]
    log_sizes = [int(float(s)) for s in args.log_sizes.split(",")]
    sections = args.sections.split(",")
    fricgen = [sys.executable, "-m", "fricgen"]
    with tempfile.TemporaryDirectory(prefix="fricgen_scale_") as tmp:
        folder = Path(tmp)
        if "models" in sections:
            model_sizes(folder, [int(float(s)) for s in args.model_sizes.split(",")],
                        [int(s) for s in args.seeds.split(",")])
        if "elm" in sections:
            elm_improvement(folder)
        if "load" in sections:
            loaded_train(folder, int(float(args.load_rows)), args.load_repeats,
                         args.load_blas.split(",") if args.load_blas else None)
        if "time" not in sections:
            return
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
