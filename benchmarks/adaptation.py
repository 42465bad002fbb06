"""Online adaptation of the friction model in the closed loop of section 6, with friction that
drifts: the plant's Stribeck (Coulomb and static) levels rise +30 % over 300 s with a thermal
time constant, its viscous B falls -20 %, then at 300 s a step change in lubrication (levels back
to +10 %, B to -10 %). Compared on rms e1 over the last 100 s, all in the C runtime through cffi:
no compensation, the fixed trained model, the adapted model (RLS and Lyapunov rules), and exact
compensation with the true friction at each instant; "lyapunov, no hold" is Lyapunov with
``hold_at_rest=False`` (the estimates adapt through every stick). Then with no drift: adapted vs
fixed.
``--plot FILE`` draws the adapted parameters over time (each as its change from the trained
value over its projection half-width, so that +-1 is the edge of the box) with the drift.

    python benchmarks/adaptation.py [--duration 400] [--drift-end 300] [--window 100] [--plot adaptation.png]
"""
from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fricgen._plot import pyplot  # noqa: E402
from fricgen.control.adaptation import adapted  # noqa: E402
from fricgen.control.backstepping import AdaptiveBackstepping  # noqa: E402
from fricgen.control.c_adapted import CAdaptedController, build_adapted  # noqa: E402
from fricgen.control.c_controller import CController  # noqa: E402
from fricgen.control.loop import default_axis, default_model, simulate  # noqa: E402
from fricgen.control.regressor import trained_parameters  # noqa: E402
from fricgen.friction import preset  # noqa: E402
from fricgen.sim.axis import MotorAxis  # noqa: E402
from fricgen.sim.effect_law import EffectLaw  # noqa: E402
from fricgen.sim.trajectory import reversing  # noqa: E402


class Clock:
    """The time of the current sample, set by ``simulate(on_sample=...)``."""
    t = 0.0


@dataclass
class Drift:
    """The relative change of the Stribeck levels and of B at time t (module doc)."""

    level: float = 0.3
    viscous: float = -0.2
    tau: float = 100.0
    end: float = 300.0
    step_level: float = 0.1
    step_viscous: float = -0.1

    def factors(self, t: float):
        if t >= self.end:
            return self.step_level, self.step_viscous
        h = (1.0 - math.exp(-t / self.tau)) / (1.0 - math.exp(-self.end / self.tau))
        return self.level * h, self.viscous * h


class DriftEffect:
    """The drift as a sliding-friction effect of the plant (``sim.effect_law``): it reads the
    time of the simulation's signals."""

    acts_at_rest = via_dynamics = via_timing = via_current = via_contact = False
    mass_delta = force_constant_delta = lag_tau = input_delay = 0.0
    name = "drift"

    def __init__(self, drift: Drift, friction):
        self.drift, self.friction = drift, friction

    def force(self, sig):
        t = float(np.ravel(sig.t)[0]) if np.ndim(sig.t) else float(sig.t)
        level, visc = self.drift.factors(t)
        v = np.asarray(sig.v, dtype=float)
        return level * self.friction.stribeck(v) * np.sign(v) + visc * self.friction.viscous * v


class TrueFriction:
    """The plant's friction at the clock's time: exact compensation."""

    def __init__(self, drift: Drift, friction, clock: Clock):
        self.drift, self.friction, self.clock = drift, friction, clock

    def __call__(self, v):
        level, visc = self.drift.factors(self.clock.t)
        v = np.asarray(v, dtype=float)
        return (1 + level) * self.friction.stribeck(v) * np.sign(v) + (1 + visc) * self.friction.viscous * v


def drifting_axis(drift):
    """The built-in axis (Table 1's friction) with ``drift`` (None: none)."""
    friction = preset("paper3")
    law = default_axis().law
    effects = (DriftEffect(drift, friction),) if drift else ()
    return MotorAxis(EffectLaw(friction, effects, mass=law.mass, force_constant=law.force_constant,
                               i_max=law.i_max))


def run(duration, window, drift, model, module, substeps):
    friction = preset("paper3")
    axis = drifting_axis(drift)
    clock = Clock()
    exact = TrueFriction(drift or Drift(0, 0, 1, 1e9, 0, 0), friction, clock)
    settings = AdaptiveBackstepping()
    ctrls = {"none": CController(module, settings.clone(compensation=None)),
             "fixed": CController(module, settings.clone(compensation=model), "fm_force"),
             "rls": CAdaptedController(module, adapted(model, "rls", dtype="float32")),
             "lyapunov": CAdaptedController(module, adapted(model, "lyapunov", dtype="float32")),
             "lyapunov, no hold": CAdaptedController(module, adapted(model, "lyapunov", dtype="float32",
                                                                     hold_at_rest=False)),
             "exact": CController(module, settings.clone(compensation=exact))}

    adapting = {k: c for k, c in ctrls.items() if isinstance(c, CAdaptedController)}
    history = {k: [] for k in adapting}
    every = int(round(0.1 / settings.ts))
    count = [0]

    def tick(t):
        clock.t = t
        if count[0] % every == 0:
            for k, c in adapting.items():
                history[k].append((t, *c.theta_))
        count[0] += 1
    runs = simulate(axis, list(ctrls.values()), reversing(), duration, substeps, on_sample=tick)
    out = {}
    for name, r in zip(ctrls, runs):
        last = r.t >= duration - window
        out[name] = float(np.sqrt(np.mean(r.e1[last] ** 2))) if r.finite else float("nan")
    thetas = {k: np.round(np.asarray(c.theta_) - trained_parameters(model), 3) for k, c in adapting.items()}
    return out, thetas, {k: np.asarray(h) for k, h in history.items()}, adapting


def plot(path, history, adapting, model, drift):
    """Each adapted parameter's (theta - theta0) / (box half-width) over time, per rule."""
    plt = pyplot()
    if plt is None:
        print("--plot needs matplotlib (pip install -e .[plot])")
        return
    theta0 = trained_parameters(model)
    fig, axes = plt.subplots(len(history), 1, sharex=True, figsize=(8, 2.6 * len(history)),
                             constrained_layout=True)
    for ax, (rule, h) in zip(np.atleast_1d(axes), history.items()):
        lo, hi = adapting[rule].twin.adapter.bounds()
        rel = (h[:, 1:] - theta0) / (0.5 * (hi - lo))
        ax.plot(h[:, 0], rel, lw=0.8)
        ax.axhline(1, color="k", lw=0.5, ls="--")
        ax.axhline(-1, color="k", lw=0.5, ls="--")
        ax.axvline(drift.end, color="r", lw=0.5)
        ax.set_ylabel(f"{rule}: (theta - theta0) / box")
    np.atleast_1d(axes)[-1].set_xlabel("time (s); red: the lubrication step")
    fig.suptitle("adapted parameters under drift (dashed: the projection box)")
    fig.savefig(path, dpi=100)
    print(f"wrote {path}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=400.0)
    ap.add_argument("--drift-end", type=float, default=300.0)
    ap.add_argument("--window", type=float, default=100.0)
    ap.add_argument("--substeps", type=int, default=4)
    ap.add_argument("--plot", help="PNG of the adapted parameters over time, with the drift")
    args = ap.parse_args(argv)
    model = default_model("fm")
    module = build_adapted(model, "fm")
    print(f"model: {model.aim.n_hidden}-neuron ELM (paper3 benchmark, seed 0); axis 2 kg, Ts 1 ms; "
          f"rms e1 over the last {args.window:g} s of {args.duration:g} s (C runtime via cffi)")
    for label, drift in (("drift", Drift(end=args.drift_end)), ("no drift", None)):
        rms, thetas, history, adapting = run(args.duration, args.window, drift, model, module,
                                             args.substeps)
        if drift is not None and args.plot:
            for a in adapting.values():
                a.twin.adapter.reset()                            # its bounds
            plot(args.plot, history, adapting, model, drift)
        ref = rms["exact"]
        print(f"{label}: " + ", ".join(f"{k} {v * 1e6:.3f} um ({v / ref:.3f}x exact)" for k, v in rms.items()))
        for k in adapting:
            print(f"  {label}: {k} / fixed = {rms[k] / rms['fixed']:.3f}; theta - theta0 = {thetas[k].tolist()}")


if __name__ == "__main__":
    main()
