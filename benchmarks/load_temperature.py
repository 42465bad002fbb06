"""Friction that depends on the load and the temperature: fricgen's model with inputs against the
velocity-only one and against the plant's own law, on held-out logs.

Joints of fricgen/sim/loaded_joint.py, each from a law of its own (neither is fricgen's form): a
harmonic-drive joint under gravity (Coulomb and Stribeck levels plus a load term of another slope
driving than back-driving, a Vogel viscosity that lowers the viscous term and, more weakly, the
levels) and a planetary-geared palletizer joint (the mesh's loss from speed-dependent forward and
backward efficiencies, a Walther oil viscosity, a two-node thermal model). One joint of each per
seed, ``--seeds`` 1000-1009 by default (seeds that tuned nothing). Per joint and seed:

- train: the warming duty, 20 min at 200 Hz from 25 to about 60 degC, payloads none and full
  alternating by 2-min run;
- held-out: 5 min after a 3-min rest, half the payload, another trajectory family, about
  43-58 degC (``loaded_joint``'s docstring says how it differs);
- constant: 5 min, no gravity (load 0), a constant temperature within the sensor's noise.

The models, each trained on the training log:

(i)   inputs: ``fricgen.train({t, x, force, load, temperature}, rotary=True)``, the default;
(ii)  velocity only: ``fricgen.train({t, x, force: force - load}, rotary=True)``: the gravity known
      and taken out, the best a velocity-only model can do;
(iii) true form: the plant's own law fitted by ``scipy.optimize.least_squares`` (soft L1, f_scale
      three times the force noise, ORACLE_STARTS starts: the class defaults and random draws
      within the law's bounds) to friction samples force - J a - load - o of the training log
      (J and o known, v and a from a Savitzky-Golay filter of the encoder, |v| > ORACLE_SPEED,
      the temperature as logged): the ceiling of what a model of the right form gets from the log.

Score: the RMS of (model friction - true friction) over the held-out rows where |v| > MOVING, the
model evaluated at the true v, the logged load and the logged temperature. Printed per seed and as
medians over seeds: err(inputs) / err(velocity only) (target <= 0.25) and err(true form) /
err(velocity only); on the constant-conditions logs, the share of seeds where the model with
inputs left both inputs out (``report.model.inputs is None``, target >= 95 %).

Real data (``../shared/data/ur10e``, read in place, skipped when absent): UR10e joints 2 and 3
under gravity, trained on jointJ_train.csv with force = tau_meas, load = tau_grav, x = q (no
temperature), and velocity only on force = tau_meas - tau_grav; scored on jointJ_test.csv against
tau_meas - tau_grav - J a over |v| > the folder's VMIN, v and a from the folder's own filter of dq
(its baseline.py), J the velocity-only fit's identified inertia for both, each model plus its own
identified offset.

    python benchmarks/load_temperature.py [--seeds 1000-1009] [--quick] [--workers 1]
"""
from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse                                         # noqa: E402
import importlib.util                                   # noqa: E402
import multiprocessing                                  # noqa: E402
import sys                                              # noqa: E402
import time                                             # noqa: E402
from dataclasses import replace                         # noqa: E402
from pathlib import Path                                # noqa: E402

import numpy as np                                      # noqa: E402
from scipy.optimize import least_squares                # noqa: E402
from scipy.signal import savgol_filter                  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import fricgen                                          # noqa: E402
from fricgen.data.table import read_table_csv           # noqa: E402
from fricgen.sim.loaded_joint import (logs, random_harmonic_joint,  # noqa: E402
                                      random_planetary_joint)

JOINTS = {"harmonic": random_harmonic_joint, "planetary": random_planetary_joint}
COLUMNS = ("t", "x", "force", "load", "temperature")
#: rad/s: the held-out rows scored (the joint moves).
MOVING = 0.02
#: The oracle: its Savitzky-Golay filter (samples, order), the least speed of its samples (rad/s),
#: about how many samples it fits, its starts.
SG_WINDOW, SG_ORDER = 21, 3
ORACLE_SPEED, ORACLE_ROWS, ORACLE_STARTS = 0.01, 40000, 4
#: Targets: err(inputs) / err(velocity only) at most; the share of constant-conditions logs
#: whose model leaves both inputs out, at least.
RATIO_TARGET, LEFT_OUT_TARGET = 0.25, 0.95
DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "ur10e"
UR10E_JOINTS = (2, 3)


def rms(e) -> float:
    return float(np.sqrt(np.mean(np.square(e))))


def train(columns):
    return fricgen.train(columns, rotary=True, warn=lambda line: None)


def train_with_inputs(columns):
    """(report, None), or (None, why) where ``fricgen.train`` refuses the load and temperature."""
    try:
        return train(columns), None
    except (fricgen.FricgenError, TypeError, ValueError) as exc:
        return None, f"fricgen.train refused the log with load and temperature: {exc}"


def inputs_of(report) -> str:
    """What the model with inputs depends on beside v."""
    inputs = report.model.inputs
    if inputs is None:
        return "v only"
    return " + ".join(k for k in ("load", "temperature") if getattr(inputs, k) is not None)


def oracle(joint, log):
    """The joint with its law's parameters (``joint.LAW``) fitted to the training log."""
    dt = float(log["t"][1] - log["t"][0])
    v = savgol_filter(log["x"], SG_WINDOW, SG_ORDER, deriv=1, delta=dt)
    a = savgol_filter(log["x"], SG_WINDOW, SG_ORDER, deriv=2, delta=dt)
    rows = np.flatnonzero(np.abs(v) > ORACLE_SPEED)
    rows = rows[::max(rows.size // ORACLE_ROWS, 1)]
    v, load, temperature = v[rows], log["load"][rows], log["temperature"][rows]
    f = (log["force"] - joint.inertia * a - log["load"] - joint.offset)[rows]
    names = list(joint.LAW)
    lo, hi = np.array([joint.LAW[k] for k in names]).T

    def residual(theta):
        return replace(joint, **dict(zip(names, theta))).true_friction(v, load, temperature) - f

    rng = np.random.default_rng(0)
    defaults = np.clip([getattr(type(joint), k) for k in names], lo, hi)
    starts = [defaults] + [rng.uniform(lo, hi) for _ in range(ORACLE_STARTS - 1)]
    fits = [least_squares(residual, x0, bounds=(lo, hi), loss="soft_l1", x_scale="jac",
                          f_scale=3.0 * joint.force_noise) for x0 in starts]
    best = min(fits, key=lambda r: r.cost)
    return replace(joint, **dict(zip(names, best.x)))


def one(job) -> dict:
    """Every figure of one joint and seed."""
    kind, seed = job
    start = time.perf_counter()
    joint = JOINTS[kind](seed)
    runs = logs(joint, seed)
    tr, ho = runs["train"], runs["heldout"]
    moving = np.abs(ho["true_v"]) > MOVING
    v, load, temperature = ho["true_v"][moving], ho["load"][moving], ho["temperature"][moving]
    truth = ho["true_friction"][moving]
    with_inputs, refused = train_with_inputs({k: tr[k] for k in COLUMNS})
    velocity = train({"t": tr["t"], "x": tr["x"], "force": tr["force"] - tr["load"]})
    err = {"velocity": rms(velocity.model.force(v) - truth),
           "true form": rms(oracle(joint, tr).true_friction(v, load, temperature) - truth),
           "inputs": None if with_inputs is None else
           rms(with_inputs.model.force(v, load=load, temperature=temperature) - truth)}
    constant, _ = train_with_inputs({k: runs["constant"][k] for k in COLUMNS})
    return {"kind": kind, "seed": seed, "peak": joint.peak_gravity, "err": err,
            "chose": refused or inputs_of(with_inputs),
            "constant": None if constant is None else constant.model.inputs is None,
            "train T": (tr["temperature"].min(), tr["temperature"].max()),
            "held T": (ho["temperature"].min(), ho["temperature"].max()),
            "seconds": time.perf_counter() - start}


def ratio(r, name):
    e = r["err"]
    return None if e[name] is None else e[name] / e["velocity"]


def report(results: list) -> None:
    print(f"\n{'joint':9s} {'seed':>5s} {'peak L':>7s} {'T train':>11s} {'T held':>11s} "
          f"{'inputs':>7s} {'v only':>7s} {'form':>7s} {'in/v':>6s} {'form/v':>6s} "
          f"{'const':>7s} {'s':>4s}  inputs chosen")
    for r in sorted(results, key=lambda r: (r["kind"], r["seed"])):
        e, fi = r["err"], ratio(r, "inputs")
        cells = f"{'-':>7s} " if fi is None else f"{e['inputs']:7.3f} "
        const = {None: "-", True: "none", False: "INPUTS"}[r["constant"]]
        temperatures = " ".join(f"{r[k][0]:5.1f}-{r[k][1]:<5.1f}" for k in ("train T", "held T"))
        print(f"{r['kind']:9s} {r['seed']:5d} {r['peak']:7.1f} {temperatures} {cells}{e['velocity']:7.3f} "
              f"{e['true form']:7.3f} {'-' if fi is None else f'{fi:6.3f}':>6s} "
              f"{ratio(r, 'true form'):6.3f} {const:>7s} {r['seconds']:4.0f}  {r['chose']}")
    print("\nmedians over seeds (RMS friction error on the held-out rows, Nm; ratios per seed)")
    groups = [(kind, [r for r in results if r["kind"] == kind]) for kind in JOINTS]
    for kind, rs in groups + [("all", results)]:
        fi = [ratio(r, "inputs") for r in rs if ratio(r, "inputs") is not None]
        ft = [ratio(r, "true form") for r in rs]
        const = [r["constant"] for r in rs if r["constant"] is not None]
        inputs = f"{np.median(fi):.3f} ({sum(f <= RATIO_TARGET for f in fi)}/{len(rs)} seeds <= " \
                 f"{RATIO_TARGET})" if fi else "- (refused)"
        left_out = f"{np.mean(const):.0%} of {len(const)}" if const else "- (refused)"
        print(f"  {kind:9s} err(inputs)/err(v only) {inputs}; err(true form)/err(v only) "
              f"{np.median(ft):.3f}; constant conditions, inputs left out: {left_out} "
              f"(target >= {LEFT_OUT_TARGET:.0%})")


def load_baseline(folder: Path):
    """The folder's baseline.py as a module (its filter ``va`` and VMIN)."""
    spec = importlib.util.spec_from_file_location("ur10e_baseline", folder / "baseline.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def ur10e(folder: Path) -> None:
    print(f"\nUR10e ({folder}): RMS of predicted - (tau_meas - tau_grav - J a) on "
          "jointJ_test.csv, Nm")
    if not folder.is_dir():
        print(f"  skipped: no folder {folder}")
        return
    base = load_baseline(folder)
    for j in UR10E_JOINTS:
        tr, te = (read_table_csv(folder / f"joint{j}_{part}.csv", (), keep_extra=True)
                  for part in ("train", "test"))
        velocity = train({"t": tr["t"], "x": tr["q"], "force": tr["tau_meas"] - tr["tau_grav"]})
        with_inputs, refused = train_with_inputs({"t": tr["t"], "x": tr["q"],
                                                  "force": tr["tau_meas"], "load": tr["tau_grav"]})
        inertia = velocity.identification.body.mass
        v, a = base.va(te["t"], te["dq"])
        m = np.abs(v) > base.VMIN
        y = (te["tau_meas"] - te["tau_grav"] - inertia * a)[m]
        e_v = rms(velocity.model.force(v[m]) + velocity.identification.body.offset - y)
        line = f"  joint {j}: J {inertia:.3f} kg m^2; velocity only {e_v:.3f}"
        if with_inputs is None:
            print(f"{line}; {refused}")
            continue
        e_i = rms(with_inputs.model.force(v[m], load=te["tau_grav"][m])
                  + with_inputs.identification.body.offset - y)
        print(f"{line}; inputs {e_i:.3f} ({inputs_of(with_inputs)}); ratio {e_i / e_v:.3f}")


def seeds_of(texts) -> list:
    """'1000-1009' and '1003' -> the seeds."""
    out = []
    for text in texts:
        lo, _, hi = text.partition("-")
        out += list(range(int(lo), int(hi or lo) + 1))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", nargs="+", default=["1000-1009"], help="seeds or ranges a-b")
    ap.add_argument("--quick", action="store_true", help="the first 2 seeds")
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--data", type=Path, default=DATA, help="the UR10e folder")
    args = ap.parse_args(argv)
    seeds = seeds_of(args.seeds)[:2 if args.quick else None]
    jobs = [(kind, seed) for seed in seeds for kind in JOINTS]
    start = time.perf_counter()
    results = []
    with multiprocessing.Pool(args.workers) as pool:
        for k, r in enumerate(pool.imap_unordered(one, jobs), 1):
            results.append(r)
            print(f"  {k}/{len(jobs)} ({r['kind']} {r['seed']}: {r['seconds']:.0f} s), "
                  f"{time.perf_counter() - start:.0f} s", file=sys.stderr, flush=True)
    print(f"seeds {', '.join(map(str, seeds))}; held-out rows with |v| > {MOVING} rad/s")
    report(results)
    ur10e(args.data)
    print(f"\n{time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
