"""The adaptation's defaults given the loop's sample time: a 10 kHz loop adapts as a 1 kHz one.

The section 6 loop (the built-in 2 kg axis, the reversing trajectory) with the 8-neuron default
ELM adapted in C (``fric_adapt_ctrl_step`` through cffi) while the plant's Coulomb and static
levels rise +30 % over the run; the controller and the adaptation take their defaults for the
sample time (``adapted(model, rule, controller=AdaptiveBackstepping(ts=...))``, the C
``NAME_adapt_default_params(p, ts)``). Per rule and rate: rms e1 over the last 10 s, the same
for the fixed trained model at that rate, their ratio, and how far the adapted force at 0.03
m/s moved. Target: the 10 kHz ratio within 1.2x of the 1 kHz one.

    python benchmarks/adaptation_rate.py [--duration 60]
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from adaptation import Clock, Drift, drifting_axis  # noqa: E402
from fricgen.control.adaptation import adapted  # noqa: E402
from fricgen.control.backstepping import AdaptiveBackstepping  # noqa: E402
from fricgen.control.c_adapted import CAdaptedController, build_adapted  # noqa: E402
from fricgen.control.c_controller import CController  # noqa: E402
from fricgen.control.loop import default_model, simulate  # noqa: E402
from fricgen.sim.trajectory import reversing  # noqa: E402


def run(module, model, ts, duration):
    """rms e1 over the last 10 s: {rule or "fixed": value}, and the adapted force moves."""
    axis = drifting_axis(Drift(level=0.3, viscous=0.0, tau=30.0, end=duration))
    clock = Clock()
    settings = AdaptiveBackstepping(ts=ts)
    ctrls = {"fixed": CController(module, settings.clone(compensation=model), "fm_force"),
             **{rule: CAdaptedController(module, adapted(model, rule, controller=settings,
                                                          dtype="float32"))
                for rule in ("lyapunov", "rls")}}

    def tick(t):
        clock.t = t
    substeps = max(1, int(round(4 * ts / 1e-3)))
    loops = simulate(axis, list(ctrls.values()), reversing(), duration, substeps, on_sample=tick)
    last = loops[0].t >= duration - 10.0
    rms = {name: float(np.sqrt(np.mean(r.e1[last] ** 2))) for name, r in zip(ctrls, loops)}
    moved = {}
    for rule in ("lyapunov", "rls"):
        twin = ctrls[rule].twin.adapter
        twin.reset()
        trained = float(twin.force(0.03))
        twin.theta_ = np.float32(ctrls[rule].theta_)
        moved[rule] = float(twin.force(0.03)) - trained
    return rms, moved


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=60.0)
    args = ap.parse_args(argv)
    model = default_model("fm")
    module = build_adapted(model, "fm")
    print(f"{args.duration:g} s, +30 % Coulomb drift; rms e1 over the last 10 s (C runtime via cffi)")
    ratios = {}
    for ts in (1e-3, 1e-4):
        t0 = time.perf_counter()
        rms, moved = run(module, model, ts, args.duration)
        for rule in ("lyapunov", "rls"):
            ratios[rule, ts] = rms[rule] / rms["fixed"]
            print(f"  {1 / ts:6.0f} Hz {rule:8s}: {rms[rule] * 1e6:8.3f} um, fixed {rms['fixed'] * 1e6:8.3f} um, "
                  f"ratio {ratios[rule, ts]:.3f}; F(0.03 m/s) moved {moved[rule]:+.3f} N")
        print(f"  ({1 / ts:.0f} Hz: {time.perf_counter() - t0:.0f} s)", flush=True)
    for rule in ("lyapunov", "rls"):
        print(f"{rule}: 10 kHz ratio / 1 kHz ratio = {ratios[rule, 1e-4] / ratios[rule, 1e-3]:.3f} "
              "(target <= 1.2)")


if __name__ == "__main__":
    main()
