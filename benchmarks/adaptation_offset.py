"""Online adaptation of the axis's offset (its constant force, ``fricgen.control.regressor``) in
the closed loop of section 6, all in the C runtime through cffi.

The model is fricgen's default (paper3 benchmark, seed 0) with a recorded axis whose offset is
``--trained`` N, as ``fricgen train`` identifies one. The plant's constant force starts there,
ramps to ``--ramp-to`` N over the first ``--ramp`` s (a payload taken on an inclined axis), and
steps to ``--step-to`` N at ``--step-at`` s (the payload let go). Compared: the fixed model with
its trained offset (``NAME_force_with_offset``); the adapted models, whose last parameter is the offset
(Lyapunov and RLS, the defaults); the adapted model without the offset term (the model without
its axis record); and exact compensation, the true friction and constant force at each instant.

Printed: how far the offset the loop applies, (phi / phi_N) k_hat theta_offset in newtons (the
firmware's forces are phi_N times a current), is from the plant's, as an rms over each settled
window (``--settle`` s after each change until the next) and at the end; rms
e1 over each window, beside exact compensation.

    python benchmarks/adaptation_offset.py [--duration 300] [--plot adaptation_offset.png]
"""
from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from adaptation import Clock  # noqa: E402
from fricgen._plot import pyplot  # noqa: E402
from fricgen.control.adaptation import adapted  # noqa: E402
from fricgen.control.backstepping import AdaptiveBackstepping  # noqa: E402
from fricgen.control.c_adapted import CAdaptedController, build_adapted  # noqa: E402
from fricgen.control.c_controller import CController  # noqa: E402
from fricgen.control.loop import default_axis, default_model, simulate  # noqa: E402
from fricgen.friction import preset  # noqa: E402
from fricgen.sim.axis import MotorAxis  # noqa: E402
from fricgen.sim.effect_law import EffectLaw  # noqa: E402
from fricgen.sim.trajectory import reversing  # noqa: E402


class Offset:
    """The plant's constant force at time t (module doc), N."""

    def __init__(self, trained, ramp_to, ramp, step_to, step_at):
        self.trained, self.ramp_to, self.ramp = trained, ramp_to, ramp
        self.step_to, self.step_at = step_to, step_at

    def __call__(self, t: float) -> float:
        if t >= self.step_at:
            return self.step_to
        return self.trained + (self.ramp_to - self.trained) * min(t / self.ramp, 1.0)

    def windows(self, settle: float, duration: float):
        """(label, start, end) of the settled windows."""
        return [("after the ramp", self.ramp + settle, self.step_at),
                ("after the step", self.step_at + settle, duration)]


class OffsetEffect:
    """The offset as an external force of the plant (``sim.effect_law``): it acts at rest too."""

    acts_at_rest = True
    via_dynamics = via_timing = via_current = via_contact = False
    mass_delta = force_constant_delta = lag_tau = input_delay = 0.0
    name = "offset"

    def __init__(self, offset: Offset):
        self.offset = offset

    def force(self, sig):
        t = np.asarray(sig.t, dtype=float)
        return np.vectorize(self.offset)(t) + 0.0 * np.asarray(sig.x, dtype=float)


def with_axis(model, offset: float):
    """``model`` with the axis record ``fricgen train`` writes, holding ``offset`` (N)."""
    axis = {"speed_min": 0.001, "speed_max": 0.3, "mass": None, "mass_se": None, "mass_from": None,
            "force_constant": None, "offset": offset, "offset_se": None}
    return replace(model, training={**model.training, "axis": axis})


def run(args):
    friction = preset("paper3")
    offset = Offset(args.trained, args.ramp_to, args.ramp, args.step_to, args.step_at)
    law = default_axis().law
    axis = MotorAxis(EffectLaw(friction, (OffsetEffect(offset),), mass=law.mass,
                               force_constant=law.force_constant, i_max=law.i_max))
    plain = default_model("fm")
    model = with_axis(plain, args.trained)
    module, plain_module = build_adapted(model, "fm"), build_adapted(plain, "fm")
    clock = Clock()
    settings = AdaptiveBackstepping()

    def exact(v):
        v = np.asarray(v, dtype=float)
        return friction(v) + offset(clock.t)

    ctrls = {"fixed": CController(module, settings.clone(compensation=model.force_with_offset),
                                  "fm_force_with_offset"),
             "lyapunov": CAdaptedController(module, adapted(model, "lyapunov", dtype="float32")),
             "rls": CAdaptedController(module, adapted(model, "rls", dtype="float32")),
             "lyapunov, no offset term": CAdaptedController(
                 plain_module, adapted(plain, "lyapunov", dtype="float32")),
             "exact": CController(module, settings.clone(compensation=exact))}
    applied = {k: [] for k in ("lyapunov", "rls")}
    times = []
    newtons = law.force_constant / settings.phi_n

    def tick(t):
        clock.t = t
        times.append(t)
        for k in applied:
            c = ctrls[k]
            applied[k].append(newtons * float(c.adaptive_parameters[1]) * float(c.theta_[-1]))

    runs = simulate(axis, list(ctrls.values()), reversing(), args.duration, args.substeps,
                    on_sample=tick)
    truth = np.array([offset(t) for t in times])
    return offset, dict(zip(ctrls, runs)), np.asarray(times), truth, {k: np.asarray(a) for k, a in applied.items()}


def plot(path, times, truth, applied):
    plt = pyplot()
    if plt is None:
        print("--plot needs matplotlib (pip install -e .[plot])")
        return
    fig, ax = plt.subplots(figsize=(8, 3.2), constrained_layout=True)
    ax.plot(times, truth, "k", lw=1.2, label="the plant's offset")
    for k, a in applied.items():
        ax.plot(times, a, lw=0.8, label=f"{k}: (phi / phi_N) k_hat theta_offset")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("N")
    ax.legend(loc="best", fontsize=8)
    fig.savefig(path, dpi=100)
    print(f"wrote {path}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=300.0)
    ap.add_argument("--trained", type=float, default=2.0, help="the model's offset, N")
    ap.add_argument("--ramp-to", type=float, default=6.0)
    ap.add_argument("--ramp", type=float, default=60.0)
    ap.add_argument("--step-to", type=float, default=-2.0)
    ap.add_argument("--step-at", type=float, default=180.0)
    ap.add_argument("--settle", type=float, default=30.0)
    ap.add_argument("--substeps", type=int, default=4)
    ap.add_argument("--plot", help="PNG of the applied offsets over time")
    args = ap.parse_args(argv)
    print(f"offset: trained {args.trained:g} N, ramp to {args.ramp_to:g} N over {args.ramp:g} s, "
          f"step to {args.step_to:g} N at {args.step_at:g} s; {args.duration:g} s, Ts 1 ms, "
          "the built-in 2 kg axis (C runtime via cffi)")
    offset, runs, times, truth, applied = run(args)
    for label, start, end in offset.windows(args.settle, args.duration):
        w = (times >= start) & (times < end)
        rw = {k: (r.t >= start) & (r.t < end) for k, r in runs.items()}
        rms = {k: float(np.sqrt(np.mean(r.e1[rw[k]] ** 2))) for k, r in runs.items()}
        print(f"{label} ({start:g}-{end:g} s, true offset {truth[w][-1]:g} N):")
        for k, a in applied.items():
            err = a[w] - truth[w]
            print(f"  {k}: applied offset rms error {np.sqrt(np.mean(err ** 2)):.3f} N, "
                  f"at {end:g} s {a[w][-1]:.3f} N")
        print("  rms e1: " + ", ".join(f"{k} {v * 1e6:.1f} um ({v / rms['exact']:.2f}x exact)"
                                      for k, v in rms.items()))
    if args.plot:
        plot(args.plot, times, truth, applied)


if __name__ == "__main__":
    main()
