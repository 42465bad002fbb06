"""What `fricgen readback` exports after a long run of constant friction, against the truth.

The built-in axis (Table 1's friction, no drift) under the adaptive backstepping loop with the
adapted model (the C runtime through cffi, 1 kHz, the reversing trajectory of 0.02-0.2 m/s).
The controller's k_hat scales the compensation and trades against theta: only their product
k_hat F is determined. Its forces are the firmware's, phi_N times the current: the plant's
friction times phi_N / phi (the built-in axis has phi = 18 N/A against the controller's nominal
phi_N = 20 N/A, which k_hat absorbs as well). Every ``--every`` seconds this prints the friction
read back from the dump (k_hat F, ``fricgen.control.readback``) against the plant's friction in
those units, and theta's F alone (what a dump without the scale gave) against it in newtons and
in those units: relative RMS error over 0.02-0.2 m/s and the error at 0.05 m/s, with k_hat.

    python benchmarks/adaptation_readback.py [--duration 1800] [--every 300] [--rule lyapunov]
                                             [--leak L]
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fricgen.control.adaptation import adapted  # noqa: E402
from fricgen.control.c_adapted import CAdaptedController, build_adapted  # noqa: E402
from fricgen.control.loop import default_axis, default_model, simulate  # noqa: E402
from fricgen.control.readback import scaled  # noqa: E402
from fricgen.control.regressor import with_parameters  # noqa: E402
from fricgen.friction import preset  # noqa: E402
from fricgen.sim.trajectory import reversing  # noqa: E402

SPEEDS = np.linspace(0.02, 0.2, 37)
AT = 0.05


def errors(force, truth):
    """(relative RMS error over SPEEDS, relative error at AT) of ``force`` against ``truth``."""
    rel = np.sqrt(np.mean((force(SPEEDS) - truth(SPEEDS)) ** 2) / np.mean(truth(SPEEDS) ** 2))
    return float(rel), float(force(np.array([AT]))[0] / truth(np.array([AT]))[0] - 1)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=1800.0)
    ap.add_argument("--every", type=float, default=300.0)
    ap.add_argument("--rule", choices=("lyapunov", "rls"), default="lyapunov")
    ap.add_argument("--leak", type=float, help="the leakage per sample (default: the rule's)")
    args = ap.parse_args(argv)
    model = default_model("fm")
    friction = preset("paper3")
    truth = lambda v: friction.stribeck(v) * np.sign(v) + friction.viscous * v  # noqa: E731
    twin = adapted(model, args.rule, dtype="float32",
                   **({} if args.leak is None else {"leak": args.leak}))
    units = twin.controller.phi_n / default_axis().law.force_constant      # phi_N / phi
    firmware = lambda v: units * truth(v)                                  # noqa: E731
    ctrl = CAdaptedController(build_adapted(model, "fm"), twin)
    print(f"{args.rule}, {args.duration:g} s at 1 kHz, constant friction; relative error of the "
          f"friction read back over {SPEEDS[0]:g}-{SPEEDS[-1]:g} m/s (RMS) and at {AT:g} m/s")
    print(f"phi_N / phi = {units:.4f}; columns: k_hat F against the truth in phi_N A; F against "
          "the truth in N; F against the truth in phi_N A")
    print(f"{'t s':>7s} {'k_hat':>7s} {'k_hat F rms':>12s} {'at 0.05':>8s} {'F rms':>8s} {'at 0.05':>8s}"
          f" {'F rms':>8s} {'at 0.05':>8s}")
    start, marks = time.perf_counter(), [args.every]

    def report(t):
        theta_only = with_parameters(model, np.asarray(ctrl.theta_, dtype=float))
        k_hat = float(ctrl.adaptive_parameters[1])
        applied = scaled(theta_only, k_hat)
        rows = (errors(applied.force, firmware), errors(theta_only.force, truth),
                errors(theta_only.force, firmware))
        cells = " ".join(f"{rms:{w}.2%} {at:+8.2%}" for (rms, at), w in zip(rows, (12, 8, 8)))
        print(f"{t:7.0f} {k_hat:7.4f} {cells}   ({time.perf_counter() - start:.0f} s)", flush=True)

    def tick(t):
        if marks and t >= marks[0]:
            report(marks.pop(0))
            if t + args.every <= args.duration + 1e-9:
                marks.append(t + args.every)
    ctrl.reset()
    report(0.0)
    simulate(default_axis(), [ctrl], reversing(), args.duration, on_sample=tick)
    report(args.duration)
    return 0


if __name__ == "__main__":
    sys.exit(main())
