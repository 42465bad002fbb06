"""Where fricgen diagnose succeeds and where it fails, on logs with one hidden effect (or none).

Prints
1. the confusion matrix (true effect x named effect) at the reference magnitude;
2. the same at a small magnitude, where confusable pairs show;
3. the smallest magnitude of each effect that is still named correctly for every seed;
4. the held-out gap before and after, per effect (median over seeds, reference magnitude).

    python benchmarks/diagnose_confusion.py [--seeds 4] [--noise 1.0] [--small 0.1]

Every log is 12 s at 1 kHz from the truth axis of fricgen.logsynth; magnitudes scale the
reference sizes listed there (ripple 3 N, asymmetry 20 %, load 5 N, mass +30 %, phi -15 %,
extra source fc 2 N / fs 6 N / B 15 N s/m, lag 20 ms, drift 2 %/s).
"""
import argparse
import time

import numpy as np

from fricgen.diagnose.diagnoser import diagnose
from fricgen.sim.logsynth import HIDDEN_EFFECTS, LogSpec, nominal_model, synthesize_logs

SHORT = {"none": "none", "position_ripple": "ripple", "direction_asymmetry": "asym",
         "constant_load": "load", "inertia_mismatch": "mass", "force_constant_mismatch": "phi",
         "extra_friction_source": "extra", "frictional_lag": "lag", "thermal_drift": "drift"}
MAGNITUDES = (0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0)


def run(specs, model):
    logs = synthesize_logs(specs, model)
    return [diagnose(log, model, s.mass, s.force_constant) for s, log in zip(specs, logs)]


def confusion(specs, results, title):
    names = list(HIDDEN_EFFECTS)
    m = np.zeros((len(names), len(names)), dtype=int)
    for s, d in zip(specs, results):
        m[names.index(s.effect), names.index(d.effect_)] += 1
    print(f"\n{title}\n(rows: hidden effect, columns: named effect)")
    print(f"{'':>8s} " + " ".join(f"{SHORT[n]:>6s}" for n in names))
    for k, n in enumerate(names):
        print(f"{SHORT[n]:>8s} " + " ".join(f"{c:6d}" for c in m[k]))
    print(f"accuracy {np.trace(m) / m.sum():.3f} ({np.trace(m)}/{m.sum()})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--noise", type=float, default=1.0)
    ap.add_argument("--small", type=float, default=0.1, help="magnitude of the second confusion matrix")
    args = ap.parse_args()
    seeds = range(args.seeds)
    model = nominal_model()
    start = time.time()

    specs = [LogSpec(effect=e, seed=s, noise=args.noise) for s in seeds for e in HIDDEN_EFFECTS]
    ref = run(specs, model)
    confusion(specs, ref, f"magnitude 1, noise {args.noise:g}, {args.seeds} seeds")

    small = [LogSpec(effect=e, seed=s, magnitude=args.small, noise=args.noise)
             for s in seeds for e in HIDDEN_EFFECTS]
    confusion(small, run(small, model), f"magnitude {args.small:g}, noise {args.noise:g}, {args.seeds} seeds")

    effects = [e for e in HIDDEN_EFFECTS if e != "none"]
    sweep = [LogSpec(effect=e, seed=100 + s, magnitude=m, noise=args.noise)
             for e in effects for m in MAGNITUDES for s in seeds]
    res = run(sweep, model)
    print(f"\nsmallest magnitude named correctly for all {args.seeds} seeds (of {MAGNITUDES}), noise {args.noise:g}")
    print(f"{'effect':>24s} {'magnitude':>9s}  named at each magnitude (correct/seeds)")
    for e in effects:
        ok = {m: sum(d.effect_ == e for s, d in zip(sweep, res) if s.effect == e and s.magnitude == m)
              for m in MAGNITUDES}
        passing = [m for m in MAGNITUDES if all(ok[k] == args.seeds for k in MAGNITUDES if k >= m)]
        smallest = f"{min(passing):g}" if passing else "> 1"
        wrong = {m: sorted({SHORT[d.effect_] for s, d in zip(sweep, res)
                            if s.effect == e and s.magnitude == m and d.effect_ != e}) for m in MAGNITUDES}
        print(f"{e:>24s} {smallest:>9s}  " + " ".join(
            f"{m:g}:{ok[m]}" + (f"({','.join(wrong[m])})" if wrong[m] else "") for m in MAGNITUDES))

    print(f"\nheld-out gap (rms velocity error of 20 ms restarted simulations, m/s), magnitude 1, "
          f"median of {args.seeds} seeds")
    print(f"{'effect':>24s} {'before':>10s} {'after':>10s} {'after/before':>12s}")
    for e in HIDDEN_EFFECTS:
        before = np.median([d.gap_before_ for s, d in zip(specs, ref) if s.effect == e])
        after = np.median([d.gap_after_ for s, d in zip(specs, ref) if s.effect == e])
        print(f"{e:>24s} {before:10.3e} {after:10.3e} {after / before:12.3f}")
    print(f"\n({len(specs) + len(small) + len(sweep)} logs in {time.time() - start:.0f} s)")


if __name__ == "__main__":
    main()
