"""Logs with the position in encoder counts: the mass and the friction identified from them.

A simulator of its own (not fricgen's): a 3 kg axis under a PI velocity loop at the log's rate,
integrated by semi-implicit Euler at 20 steps per sample, its friction a tanh-smoothed Coulomb
level with a Lorentzian Stribeck peak and viscous friction (no shape of fricgen's vocabulary),
the drive force logged with 0.2 N of noise, the position logged in encoder steps (1 um and 10 um)
and no velocity column (fricgen differentiates the position). Per seed (1000 up: none tuned
anything here) and rate (1 and 4 kHz): ``fricgen.train`` on the quantized log and on the same
log with the exact position. Counted: the mass within 2 % of the truth and within 3 of its
standard errors; the friction's RMS error over 0.005-0.2 m/s against the truth, quantized over
exact.

    python benchmarks/encoder_counts.py [--seeds 10] [--duration 16]
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import fricgen  # noqa: E402

MASS = 3.0
STEPS = (1e-6, 1e-5)
RATES = (1000.0, 4000.0)


def friction(v):
    """The simulator's law: tanh-smoothed Coulomb 6 N, a Lorentzian Stribeck peak of 4 N at
    0.015 m/s, viscous 25 N s/m."""
    v = np.asarray(v, dtype=float)
    return np.tanh(v / 2e-4) * (6.0 + 4.0 / (1.0 + (v / 0.015) ** 2)) + 25.0 * v


def simulate(seed: int, rate: float, duration: float) -> dict:
    """t, the exact x and the noisy drive force of one log."""
    rng = np.random.default_rng(seed)
    n, sub = int(duration * rate), 20
    ts, h = 1.0 / rate, 1.0 / (rate * sub)
    period = 4.0 + rng.uniform(0, 2)
    t = np.arange(n) * ts
    s = 2 * np.abs(((t / period) + 0.25) % 1.0 - 0.5) * 2 - 1           # triangle in [-1, 1]
    v_ref = 0.2 * s * np.abs(s)
    x = v = integral = 0.0
    xs, force = np.empty(n), np.empty(n)
    kp, ki = MASS * 2 * np.pi * 60, MASS * (2 * np.pi * 60) ** 2 / 4
    for k in range(n):
        error = v_ref[k] - v
        integral += error * ts
        f = kp * error + ki * integral
        xs[k], force[k] = x, f
        for _ in range(sub):
            v += h * (f - friction(v)) / MASS
            x += h * v
    return {"t": t, "x": xs, "force": force + 0.2 * rng.standard_normal(n)}


def identify(columns: dict) -> tuple:
    """(mass, its standard error, the model) of fricgen.train on the columns."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        report = fricgen.train(columns)
    body = report.identification.body
    return body.mass, body.mass_se, report.model


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--duration", type=float, default=16.0)
    args = ap.parse_args(argv)
    speeds = np.concatenate([-np.geomspace(0.2, 0.005, 30), np.geomspace(0.005, 0.2, 30)])
    print(f"mass {MASS} kg; seeds 1000-{999 + args.seeds}; {args.duration:g} s logs")
    good = {(step, rate): 0 for step in STEPS for rate in RATES}
    ratios = {(step, rate): [] for step in STEPS for rate in RATES}
    for seed in range(1000, 1000 + args.seeds):
        for rate in RATES:
            t0 = time.perf_counter()
            log = simulate(seed, rate, args.duration)
            _, _, exact_model = identify(log)
            exact_rms = float(np.sqrt(np.mean((exact_model.force(speeds) - friction(speeds)) ** 2)))
            for step in STEPS:
                quantized = {**log, "x": np.round(log["x"] / step) * step}
                mass, se, model = identify(quantized)
                rms = float(np.sqrt(np.mean((model.force(speeds) - friction(speeds)) ** 2)))
                ok = abs(mass - MASS) <= 0.02 * MASS and abs(mass - MASS) <= 3 * se
                good[step, rate] += ok
                ratios[step, rate].append(rms / exact_rms)
                print(f"  seed {seed} {rate / 1e3:.0f} kHz {step * 1e6:4.0f} um: mass {mass:.4f} +- "
                      f"{se:.2g} kg ({'ok' if ok else 'MISS'}), friction RMS {rms:.3f} N against "
                      f"{exact_rms:.3f} N exact ({rms / exact_rms:.2f}x)", flush=True)
            print(f"  ({time.perf_counter() - t0:.0f} s)", flush=True)
    for (step, rate), count in good.items():
        r = np.array(ratios[step, rate])
        print(f"{step * 1e6:4.0f} um, {rate / 1e3:.0f} kHz: mass ok on {count}/{args.seeds} seeds; "
              f"friction RMS quantized / exact median {np.median(r):.2f}x, worst {r.max():.2f}x")


if __name__ == "__main__":
    main()
