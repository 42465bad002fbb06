"""Fault campaign against the online adaptation, all in the C runtime through cffi.

60 s at 1 kHz of the section 6 loop (the built-in 2 kg axis, the reversing trajectory, the
8-neuron default ELM adapted) while the plant's Coulomb and static levels drift +30 %. Every
adaptation entry point: through the controller (``fric_adapt_ctrl_step``, glitches in x, v,
x_d, x_d', x_d'') and low-level (``fric_ctrl_step`` then ``fric_adapt_lyapunov`` or
``fric_adapt_rls``, glitches in the rule's v and its error input e2 or observed force), each
rule. Per entry point x rule: one run per kind (NaN, +-inf, +-1e20, a float32 denormal: single
samples; stuck: the input held at its value for 100 ms), 18 glitches 2.5 s apart cycling
through the inputs; one storm run (2 s of a glitch every 10 ms, random kind and input); and the
clean run beside them. Counted:

- band: samples at which the force applied leaves +-band around the trained model (target 0),
  and the same on a grid of 41 speeds every 10 ms;
- recovery: glitches (for the storm: the storm) after which the adapted force (|v| in [0.01, 0.1] m/s) is not within 5 %
  of the clean run's 1 s after the glitch's end (target 0);
- tracking: rms e1 over the last 10 s against the clean run's (target <= 1.2x).

    python benchmarks/adaptation_faults.py [--duration 60] [--seed 1000]
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
from fricgen.control.c_abi import FLAGS as CTRL_FLAGS  # noqa: E402
from fricgen.control.c_adapted import build_adapted, c_params  # noqa: E402
from fricgen.control.c_controller import CController  # noqa: E402
from fricgen.control.loop import default_model, simulate  # noqa: E402
from fricgen.sim.trajectory import reversing  # noqa: E402

VALUES = {"nan": float("nan"), "+inf": float("inf"), "-inf": float("-inf"), "+1e20": 1e20,
          "-1e20": -1e20, "denormal": 1e-41}
KINDS = (*VALUES, "stuck")
CTRL_INPUTS = ("x", "v", "xd", "xd_dot", "xd_ddot")
RULE_INPUTS = ("v", "e")
STUCK = 100                      # samples: 100 ms at 1 kHz
GRID = np.concatenate([-np.linspace(0.2, 0.001, 20), [0.0], np.linspace(0.001, 0.2, 20)])
RECOVERY_SPEEDS = np.concatenate([-np.linspace(0.1, 0.01, 10), np.linspace(0.01, 0.1, 10)])


class Harness:
    """The adapted controller of one entry point ("ctrl" or "low") and rule, with glitches:
    {sample: (input, kind, length)}; records the applied force's distance to the band and theta
    at the samples asked for."""

    def __init__(self, module, model, rule, entry, glitches, snapshots=()):
        self.module, self.model, self.rule, self.entry = module, model, rule, entry
        self.glitches, self.snapshots = glitches, set(snapshots)
        self.twin = adapted(model, rule, dtype="float32")
        self.ts = self.twin.ts

    def reset(self):
        ffi, lib = self.module.ffi, self.module.lib
        self.twin.reset()
        self.ctrl = CController(self.module, self.twin.controller).reset()
        self.a = ffi.new("fric_adapt_t *")
        assert lib.fric_adapt_init(self.a, c_params(self.module, self.twin.adapter)) == 0
        self.reg = ffi.addressof(lib, "fm_regressor")
        self.current = ffi.new("float *")
        self.band = float(self.a.p.band)
        self.k, self.active, self.stuck = 0, [], {}
        self.out_of_band = self.grid_out_of_band = 0
        self.theta = {}
        self.v_prev, self.i_prev, self.held = np.float32(0), np.float32(0), True
        return self

    def _glitch(self, name, value):
        for inp, kind, end in self.active:
            if inp == name:
                if kind == "stuck":
                    return self.stuck.setdefault(name, value)
                return VALUES[kind]
        return value

    def step(self, x, v, xd, xd_dot, xd_ddot):
        lib, k = self.module.lib, self.k
        if k in self.glitches:
            inp, kind, length = self.glitches[k]
            self.active.append((inp, kind, k + length))
        self.active = [g for g in self.active if g[2] > k]
        self.stuck = {n: s for n, s in self.stuck.items() if any(g[0] == n for g in self.active)}
        if self.entry == "ctrl":
            x, v, xd, xd_dot, xd_ddot = (self._glitch(n, q) for n, q in
                                         zip(CTRL_INPUTS, (x, v, xd, xd_dot, xd_ddot)))
            u = float(v)
            lib.fric_adapt_ctrl_step(self.a, self.ctrl._c, self.reg, x, v, xd, xd_dot, xd_ddot,
                                     self.current)
        else:
            u = float(v)
            force = lib.fric_adapt_force(self.a, self.reg, u)
            flags = lib.fric_ctrl_step(self.ctrl._c, x, v, xd, xd_dot, xd_ddot, force, self.current)
            held = bool(flags & (CTRL_FLAGS.value("saturated") | CTRL_FLAGS.value("input fault")))
            v32 = np.float32(v)
            if self.rule == "lyapunov":
                lib.fric_adapt_lyapunov(self.a, self.reg, self._glitch("v", float(v32)),
                                        self._glitch("e", float(self.ctrl._c.e2)), int(held))
            else:
                with np.errstate(all="ignore"):
                    accel = (v32 - self.v_prev) / np.float32(self.ts)
                    observed = np.float32(self.ctrl._c.p.phi_n) * (self.i_prev - np.float32(self.ctrl._c.m_o_hat) * accel)
                    v_mid = np.float32(0.5) * (v32 + self.v_prev)
                lib.fric_adapt_rls(self.a, self.reg, self._glitch("v", float(v_mid)),
                                   self._glitch("e", float(observed)), int(held or self.held))
            self.v_prev, self.i_prev, self.held = v32, np.float32(self.current[0]), held
        if np.isfinite(u):
            applied = lib.fric_adapt_force(self.a, self.reg, u)
            if abs(applied - lib.fm_force(u)) > self.band * (1 + 1e-6):
                self.out_of_band += 1
        if k % 10 == 0:
            gaps = [abs(lib.fric_adapt_force(self.a, self.reg, float(g)) - lib.fm_force(float(g)))
                    for g in GRID]
            self.grid_out_of_band += int(max(gaps) > self.band * (1 + 1e-6))
        if k in self.snapshots:
            self.theta[k] = np.float32(list(self.a.theta)[:self.a.p.n])
        self.k += 1
        return self.current[0]

    @property
    def adaptive_parameters(self):
        return self.ctrl.adaptive_parameters


def schedule(kind, inputs, n, rng, storm=False):
    """{start sample: (input, kind, length)}: 18 glitches 2.5 s apart from 5 s, or a storm."""
    if storm:
        starts = range(20000, 22000, 10)
        return {s: (inputs[rng.integers(len(inputs))], KINDS[rng.integers(len(KINDS))],
                    int(rng.integers(1, 5))) for s in starts if s < n}
    starts = [s for s in range(5000, n - 2000, 2500)][:18]
    return {s: (inputs[j % len(inputs)], kind, STUCK if kind == "stuck" else 1)
            for j, s in enumerate(starts)}


def force_curve(adapter, theta):
    """The adapted force (float32 twin) at RECOVERY_SPEEDS with parameters theta."""
    adapter.theta_ = np.asarray(theta, dtype=np.float32)
    return np.array([float(adapter.force(v)) for v in RECOVERY_SPEEDS])


def campaign(module, model, rule, entry, duration, seed):
    n = int(round(duration / 1e-3))
    rng = np.random.default_rng(seed)
    inputs = CTRL_INPUTS if entry == "ctrl" else RULE_INPUTS
    plans = {kind: schedule(kind, inputs, n, rng) for kind in KINDS}
    plans["storm"] = schedule(None, inputs, n, rng, storm=True)
    checks = {}
    for name, plan in plans.items():
        ends = [s + length for s, (_, _, length) in plan.items()]
        if name == "storm":                         # 1 s after the storm, not within it
            ends = [max(ends)] if ends else []
        checks[name] = [e + 1000 for e in ends if e + 1000 < n]
    every_check = sorted({c for cs in checks.values() for c in cs})
    clean = Harness(module, model, rule, entry, {}, every_check)
    runs = {name: Harness(module, model, rule, entry, plan, checks[name]) for name, plan in plans.items()}
    axis = drifting_axis(Drift(level=0.3, viscous=0.0, tau=30.0, end=duration))
    clock = Clock()

    def tick(t):
        clock.t = t
    loops = simulate(axis, [clean, *runs.values()], reversing(), duration, 4, on_sample=tick)
    last = loops[0].t >= duration - 10.0
    rms = [float(np.sqrt(np.mean(r.e1[last] ** 2))) if r.finite else float("inf") for r in loops]
    scratch = adapted(model, rule, dtype="float32").adapter.reset()
    rows = []
    for (name, h), r in zip(runs.items(), rms[1:]):
        late = 0
        for c in checks[name]:
            ref = force_curve(scratch, clean.theta[c])
            got = force_curve(scratch, h.theta[c])
            late += int(np.max(np.abs(got - ref) / np.abs(ref)) > 0.05)
        rows.append((name, len(plans[name]), h.out_of_band, h.grid_out_of_band, late,
                     len(checks[name]), r / rms[0]))
    return rows, clean


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--seed", type=int, default=1000)
    args = ap.parse_args(argv)
    model = default_model("fm")
    module = build_adapted(model, "fm")
    print(f"{args.duration:g} s at 1 kHz, +30 % Coulomb drift, 8-neuron ELM adapted in C; per run: "
          "glitches, samples out of band (applied / grid), glitches not recovered within 5 % "
          "after 1 s, rms e1 last 10 s / clean")
    total = {"glitches": 0, "out": 0, "late": 0, "checks": 0, "worst": 0.0}
    for entry in ("ctrl", "low"):
        for rule in ("lyapunov", "rls"):
            t0 = time.perf_counter()
            rows, clean = campaign(module, model, rule, entry, args.duration, args.seed)
            for name, count, out, grid_out, late, checks, ratio in rows:
                print(f"  {entry:4s} {rule:8s} {name:8s} glitches {count:4d}  out of band {out} / {grid_out}"
                      f"  not recovered {late}/{checks}  tracking {ratio:.3f}x")
                total["glitches"] += count
                total["out"] += out + grid_out
                total["late"] += late
                total["checks"] += checks
                total["worst"] = max(total["worst"], ratio)
            print(f"  ({entry} {rule}: {time.perf_counter() - t0:.0f} s)", flush=True)
    print(f"total: {total['glitches']} glitches; samples out of band {total['out']}; not recovered "
          f"{total['late']}/{total['checks']}; worst tracking {total['worst']:.3f}x clean")


if __name__ == "__main__":
    main()
