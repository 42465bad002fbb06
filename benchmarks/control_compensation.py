"""Closed-loop friction compensation (section 6): the figures of the control issue.

1. Variant table per adaptation law (a, b, c): rms_e1, max_e1, rms_i with no compensation, the
   exact (true) friction, fricgen's default ELM and the fuzzy baseline; the ratios
   rms_e1(elm) / rms_e1(exact) (target <= 1.1) and rms_e1(elm) / rms_e1(none) (target <= 0.3).
2. Ts stability table: the largest sampling time at which the loop stays stable, for a standard
   ELM with huge output weights (20 neurons, pinv) and an enlarged + regularized one (10 neurons,
   C = 1e5), in float64 (Python controller) and float32 (the emitted C, through cffi).
3. C vs Python parity of the closed loop per law.

Run: python benchmarks/control_compensation.py [--quick]
"""
from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from fricgen.control.backstepping import AdaptiveBackstepping
from fricgen.control.c_controller import CController, build_controller, float32_twin
from fricgen.data import synthesize_benchmark
from fricgen.fit.elm import ELMRegressor
from fricgen.friction import preset
from fricgen.model import FrictionModel
from fricgen.control.loop import compensations, default_axis, simulate
from fricgen.codegen.twin import force_f32

#: A run is stable when it stays finite and max |e1| over its second half stays below this
#: (m): 3x the uncompensated error at Ts = 1 ms; a limit cycle reaches ~15 mm.
STABLE_MAX_E1 = 2e-3


def substeps_for(ts: float) -> int:
    """RK4 steps of at most 0.1 ms per sample."""
    return max(2, int(np.ceil(ts / 1e-4 - 1e-9)))


def variant_table(axis, variants, duration, friction_input):
    print(f"\n== variants, Ts = 1 ms, {duration:g} s, friction model evaluated at {friction_input} ==")
    print(f"{'law':3s} {'variant':7s} {'rms_e1 mm':>10s} {'max_e1 mm':>10s} {'rms_i A':>8s} "
          f"{'m_o_hat':>8s} {'k_hat':>7s}")
    for law in "abc":
        ctrls = [AdaptiveBackstepping(compensation=c, law=law, friction_input=friction_input)
                 for c in variants.values()]
        runs = dict(zip(variants, simulate(axis, ctrls, duration=duration)))
        m = {k: r.metrics() for k, r in runs.items()}
        for name, f in m.items():
            print(f"{law:3s} {name:7s} {1e3 * f['rms_e1']:10.4f} {1e3 * f['max_e1']:10.4f} "
                  f"{f['rms_i']:8.3f} {f['m_o_hat']:8.4f} {f['k_hat']:7.4f}")
        r_exact = m["elm"]["rms_e1"] / m["exact"]["rms_e1"]
        r_none = m["elm"]["rms_e1"] / m["none"]["rms_e1"]
        print(f"    elm/exact = {r_exact:.3f} ({'ok' if r_exact <= 1.1 else 'FAIL'}: <= 1.1), "
              f"elm/none = {r_none:.3f} ({'ok' if r_none <= 0.3 else 'FAIL'}: <= 0.3)")


def stable(run) -> bool:
    return run.finite and float(np.max(np.abs(run.e1[run.t.size // 2:]))) <= STABLE_MAX_E1


def ts_table(axis, models, ts_grid, duration):
    print(f"\n== largest stable Ts (law c; stable: finite, max|e1| <= {STABLE_MAX_E1 * 1e3:g} mm "
          f"over the second half of {duration:g} s) ==")
    v = np.linspace(-0.1, 0.1, 2001)
    for name, model in models.items():
        if model is not None:
            err32 = np.max(np.abs(force_f32(model, v) - model.force(v)))
            beta = np.linalg.norm(model.aim.output_weights)
            print(f"  {name:22s} ||beta|| = {beta:10.3g}, max |F_float32 - F_float64| = {err32:.3g} N")
    module = build_controller({f"m{k}": m for k, m in enumerate(models.values()) if m is not None})
    names = list(models)
    rows = {(n, b): [] for n in names for b in ("float64", "C float32")}
    for ts in ts_grid:
        py = [AdaptiveBackstepping(compensation=models[n] if models[n] is not None else axis.law.friction,
                                   ts=ts) for n in names]
        cc = [CController(module, p, f"m{k}_force" if models[n] is not None else None)
              for k, (n, p) in enumerate(zip(names, py))]
        runs = simulate(axis, py + cc, duration=duration, substeps=substeps_for(ts))
        for k, n in enumerate(names):
            rows[(n, "float64")].append(runs[k])
            rows[(n, "C float32")].append(runs[len(names) + k])
    print(f"  {'compensation':22s} {'arithmetic':10s} " +
          " ".join(f"{1e3 * ts:>6g}" for ts in ts_grid) + "   largest stable Ts (ms)   "
          "[rms_e1 mm / rms_i A at each Ts]")
    for (n, b), runs in rows.items():
        ok = [stable(r) for r in runs]
        largest = max((ts for ts, s in zip(ts_grid, ok) if s), default=None)
        marks = " ".join(f"{('ok' if s else 'x'):>6s}" for s in ok)
        rms = ", ".join(f"{1e3 * r.metrics()['rms_e1']:.3g}/{r.metrics()['rms_i']:.2g}" for r in runs)
        print(f"  {n:22s} {b:10s} {marks}   {'-' if largest is None else f'{1e3 * largest:g}':>8s}"
              f"   [{rms}]")


def parity_table(axis, model, duration):
    print(f"\n== C vs Python closed-loop parity ({duration:g} s, Ts = 1 ms, default ELM in C) ==")
    module = build_controller({"fm": model})
    for law in "abc":
        s = AdaptiveBackstepping(compensation=model, law=law)
        c, twin, py = simulate(axis, [CController(module, s, "fm_force"), float32_twin(s, model), s],
                               duration=duration)
        print(f"  law {law}: max|x_C - x_twin32| = {np.max(np.abs(c.x - twin.x)):.3g} m "
              f"({int(np.sum(c.i != twin.i))} of {c.i.size} currents not bit-equal), "
              f"max|x_C - x_py64| = {np.max(np.abs(c.x - py.x)):.3g} m, "
              f"rms_e1 C / py64 - 1 = {c.metrics()['rms_e1'] / py.metrics()['rms_e1'] - 1:.2g}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="shorter runs, fewer Ts values")
    args = ap.parse_args(argv)
    duration = 2.0 if args.quick else 4.0
    t0 = time.time()
    axis = default_axis()
    variants = compensations(axis)
    if "fuzzy" not in variants:
        print("fuzzy variant skipped: fricgen.fuzzy is not available", file=sys.stderr)
    print("axis: m = 2 kg, phi = 18 N/A (controller assumes 20), i_max = 10 A, Table 1 friction; "
          "reference: reversals every 0.25 s, peak speed 0.02 .. 0.2 m/s")
    for friction_input in ("v", "vd"):
        variant_table(axis, variants, duration, friction_input)

    bench = synthesize_benchmark(preset("paper3"), seed=0)
    models = {
        "exact (true friction)": None,
        "standard ELM 20, pinv": FrictionModel.fit(
            bench.dataset, ELMRegressor(n_hidden=20, scheme="standard", solver="pinv",
                                        random_state=0), name="std20"),
        "enlarged ELM 10, C=1e5": FrictionModel.fit(
            bench.dataset, ELMRegressor(n_hidden=10, scheme="enlarged", solver="ridge", C=1e5,
                                        random_state=0), name="reg10"),
        "fricgen default": variants["elm"],
    }
    grid = ([0.25e-3, 1e-3, 4e-3, 5e-3] if args.quick
            else [0.25e-3, 0.5e-3, 1e-3, 2e-3, 3e-3, 4e-3, 4.5e-3, 5e-3])
    ts_table(axis, models, grid, duration)
    parity_table(axis, variants["elm"], duration)
    print(f"\n({time.time() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
