"""A log joined from runs, each with its own constant force: what fricgen makes of it.

Each seed simulates an axis (mass 4 kg; friction of a law of this script's own: an asymmetric
Stribeck drop of power 1.5 plus viscous and a v |v| drag, none of them fricgen's candidates)
in three runs of 8 s at 1 kHz, each from rest, swinging through reversals at its own
frequency and amplitude, with its own constant force (drawn from N(0, 0.5 N): a torque sensor
zeroed again, a cable that pulls otherwise), velocity noise 2 mm/s and force noise 0.2 N. The
runs are joined end to end, t restarting at 0 in each, and trained by ``fricgen.train``:
  - runs:      the file as it is (each run's constant force identified and taken out);
  - one run:   the first run alone (what a user could train before the runs were read);
  - one clock: the same rows on one continuous clock (no run boundaries: one constant force).
Printed per seed: the friction's RMS error against the truth over 0.01-0.4 m/s (the model plus
its offset, against the truth plus the first run's force), each run's identified force less the
first's against the truth in standard errors; then the medians and the ratios to "runs".
Seeds from 1000 (they tuned nothing).

Run: python benchmarks/log_runs.py [--seeds 10]
"""
import argparse

import numpy as np

import fricgen

TS, MASS, SECONDS = 1e-3, 4.0, 8.0


def friction(v):
    s = np.abs(v)
    drop = np.exp(-(s / 0.03) ** 1.5)
    return np.where(v > 0, 2.0 + 1.0 * drop + 10.0 * s + 8.0 * s * s,
                    -(1.7 + 0.8 * drop + 11.0 * s + 8.0 * s * s))


def one_run(rng, offset):
    t = np.arange(0.0, SECONDS, TS)
    ramp = np.minimum(t / 0.4, 1.0)
    v = ramp * (rng.uniform(0.15, 0.35) * np.sin(2 * np.pi * rng.uniform(0.2, 0.5) * t)
                + 0.05 * np.sin(2 * np.pi * rng.uniform(1.0, 2.0) * t + rng.uniform(0, 6)))
    force = MASS * np.gradient(v, TS) + friction(v) + offset
    return {"t": t, "v": v + rng.normal(0.0, 2e-3, t.size), "force": force + rng.normal(0.0, 0.2, t.size)}


def error(report, first_offset):
    v = np.concatenate([-np.geomspace(0.01, 0.4, 40), np.geomspace(0.01, 0.4, 40)])
    offset = report.training["axis"]["offset"] or 0.0
    return float(np.sqrt(np.mean((report.model.force(v) + offset - friction(v) - first_offset) ** 2)))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=10)
    args = p.parse_args()
    quiet = dict(warn=lambda line: None)
    rows = []
    print(f"{'seed':>5s} {'runs':>7s} {'one run':>8s} {'one clock':>9s}  run offsets (truth, found +- se)")
    for seed in range(1000, 1000 + args.seeds):
        rng = np.random.default_rng(seed)
        offsets = rng.normal(0.0, 0.5, 3)
        runs = [one_run(rng, o) for o in offsets]
        joined = {k: np.concatenate([r[k] for r in runs]) for k in runs[0]}
        clock = {**joined, "t": np.arange(joined["t"].size) * TS}
        found = fricgen.train(joined, **quiet)
        body = found.identification.body
        errs = (error(found, offsets[0]), error(fricgen.train(runs[0], **quiet), offsets[0]),
                error(fricgen.train(clock, **quiet), offsets[0]))
        sigmas = [abs(f - (offsets[r] - offsets[0])) / se for r, f, se in body.run_offsets or ()]
        rows.append((*errs, max(sigmas) if sigmas else np.inf))
        detail = ", ".join(f"{offsets[r] - offsets[0]:+.3f} {f:+.3f} +- {se:.3f}"
                           for r, f, se in body.run_offsets or ())
        print(f"{seed:5d} {errs[0]:7.4f} {errs[1]:8.4f} {errs[2]:9.4f}  {detail or 'none identified'}")
    rows = np.array(rows)
    med = np.median(rows[:, :3], axis=0)
    print(f"\nmedian friction error (N): runs {med[0]:.4f}, one run {med[1]:.4f} ({med[1] / med[0]:.2f}x), "
          f"one clock {med[2]:.4f} ({med[2] / med[0]:.2f}x)")
    print(f"run offsets within 3 standard errors of the truth on {int(np.sum(rows[:, 3] <= 3))} of "
          f"{len(rows)} seeds (both later runs)")


if __name__ == "__main__":
    main()
