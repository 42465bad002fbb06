"""The controller's contract under faults, and the runtime's meaning under compiler flags.

1. Fault injection (fric_ctrl.h's contract): the C controller (cffi, the default model's
   compensation evaluated as the float32 twin does) closes the loop around the built-in 2 kg
   axis for 60 s at 1 kHz, with one glitch of every input (x, v, x_d, x_d', x_d'', the friction
   force) x kind (NaN, +-inf, 1e20, a float32 denormal) at random steps (30 glitches, 1 to 20
   samples each, at least 1.5 s apart). Per glitch: the recovery time, from the glitch's end
   until |e1| is back within 2x its RMS over the 0.5 s before the glitch (and stays there for
   0.1 s); the peak |e1| after it. Also: the current finite and within +-i_max at every step,
   the estimates within their bounds, the C bit-equal to its float32 twin.
2. Flag matrix: the runtime with two emitted models (--activation-impl fast: the 10-neuron ELM
   and Table 1 as a grey-box gauss model) and the controller on the glitched inputs of part 1,
   built with every compiler installed (gcc, clang; arm-none-eabi-gcc for the Cortex-M4F under
   QEMU) x -std=c99/gnu99 x -O0/-O2/-Os (host builds with -mfma where the CPU has FMA):
   bit-equal to the twins or not, and the fused multiply-adds in the objects; then the same
   without the runtime's float-semantics block, to show what it does.

    python benchmarks/controller_faults.py [--duration 60] [--seed 0] [--no-matrix]
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

from fricgen import codegen
from fricgen.control.backstepping import AdaptiveBackstepping
from fricgen.control.c_abi import FLAGS
from fricgen.control.c_controller import CController, build_controller
from fricgen.control.faults import INPUTS, KINDS, Glitched, random_glitches
from fricgen.control.loop import default_axis, default_model, paper_benchmark, simulate
from fricgen.fit.elm import ELMRegressor, EnlargedScheme
from fricgen.firmware import flag_matrix as fm
from fricgen.model import FrictionModel

PRE, HOLD, GAP = 500, 100, 1500   # samples: pre-glitch RMS window, recovery hold, clean gap


def recovery(e1: np.ndarray, start: int, end: int, horizon: int):
    """(samples from ``end`` until |e1| <= 2 rms(e1 before ``start``) for HOLD samples, or None
    within ``horizon``; the peak |e1| from the start to the end of the horizon)."""
    bound = 2.0 * np.sqrt(np.mean(e1[max(0, start - PRE):start] ** 2))
    within = np.abs(e1[end:end + horizon]) <= bound
    peak = float(np.max(np.abs(e1[start:end + horizon])))
    for k in range(within.size - HOLD):
        if within[k:k + HOLD].all():
            return k, peak
    return None, peak


def fault_injection(duration: float, seed: int):
    model = default_model()
    settings = AdaptiveBackstepping(compensation=model)
    n = int(round(duration / settings.ts))
    glitches = random_glitches(n - GAP, np.random.default_rng(seed), len(INPUTS) * len(KINDS),
                               gap=GAP, first=PRE)
    c = Glitched(CController(build_controller(), settings), glitches)
    twin = Glitched(settings.clone(dtype="float32"), glitches)
    c_run, twin_run = simulate(default_axis(), [c, twin], duration=duration, substeps=4)
    flags = np.array(c.flags_)
    lo, hi = settings.a_min, settings.a_max
    print(f"== fault injection: {duration:g} s at {1 / settings.ts:g} Hz, {len(glitches)} glitches "
          f"(seed {seed}), C controller with the default model's compensation")
    print(f"current finite and within +-{settings.i_max:g} A at every step: "
          f"{c_run.finite and bool(np.all(np.abs(c_run.i) <= settings.i_max))}")
    print(f"m_o_hat within [{lo[0]:g}, {hi[0]:g}] and k_hat within [{lo[1]:g}, {hi[1]:g}] at every step: "
          f"{bool(np.all((lo[0] <= c_run.m_o_hat) & (c_run.m_o_hat <= hi[0]) & (lo[1] <= c_run.k_hat) & (c_run.k_hat <= hi[1])))}"
          f" (m_o_hat {c_run.m_o_hat.min():.4g}..{c_run.m_o_hat.max():.4g}, "
          f"k_hat {c_run.k_hat.min():.4g}..{c_run.k_hat.max():.4g})")
    equal = all(np.array_equal(getattr(c_run, k).astype(np.float32), getattr(twin_run, k).astype(np.float32))
                for k in ("i", "x", "m_o_hat", "k_hat")) and c.flags_ == twin.flags_
    print(f"C bit-equal to its float32 twin (current, position, estimates, flags): {equal}")
    print("steps flagged: " + ", ".join(f"{m.key} {int(np.sum(flags & m.value > 0))}"
                                        for m in FLAGS.members if m.value > 1))
    print(f"\n{'input':8} {'kind':9} {'t (s)':>7} {'len (ms)':>8} {'peak |e1| (mm)':>15} "
          f"{'recovery (ms)':>13}")
    times = {k: [] for k in KINDS}
    for g in sorted(glitches, key=lambda g: (INPUTS.index(g.input), list(KINDS).index(g.kind))):
        k, peak = recovery(c_run.e1, g.start, g.end, GAP)
        ms = "never" if k is None else f"{k * settings.ts * 1e3:.0f}"
        times[g.kind].append(np.inf if k is None else k * settings.ts * 1e3)
        print(f"{g.input:8} {g.kind:9} {g.start * settings.ts:7.3f} {g.length:8d} {peak * 1e3:15.4f} {ms:>13}")
    print("\nrecovery by kind (ms): " + "; ".join(
        f"{kind} median {np.median(t):.0f}, max {np.max(t):.0f}" for kind, t in times.items()))
    return model, settings, np.array(twin.rows_)


def matrix(model_settings_rows, tmp: Path) -> None:
    _, settings, rows = model_settings_rows
    bench = paper_benchmark()
    elm = FrictionModel.fit(bench.dataset, ELMRegressor(random_state=0, n_hidden=10, solver="loo",
                                                        scheme=EnlargedScheme(w_max=30.0)), name="fm")
    models = {"fm": elm, "gb": fm.table1_greybox(bench)}
    v = np.linspace(-2 * elm.v_sat, 2 * elm.v_sat, 201).astype(np.float32)
    rows = rows[:2000]
    settings = settings.clone(compensation=elm)
    twin = fm.twin_lines(models, "fast", v, rows, settings)
    flag_sets = fm.available_flag_sets()
    results = {}
    for variant in ("with", "without"):
        src = tmp / variant / "src"
        for name, model in models.items():
            codegen.emit(model, src, name, activation_impl="fast", with_controller=True)
        if variant == "without":
            fm.strip_fp_blocks(src)
        results[variant] = fm.run_matrix(src, list(models), flag_sets, tmp / variant / "out", v, rows,
                                         settings)
    host = " ".join(fm.host_fma_flags()) or "none"
    print(f"\n== flag matrix: forces of 2 models x {v.size} velocities and {len(rows)} controller steps "
          f"(glitched) against the twins; host FMA flag: {host}")
    print(f"{'compiler -std -O':34} {'bit-equal':>9} {'FMA':>4}   {'without the block:':>18} "
          f"{'bit-equal':>9} {'FMA':>4}")
    for with_, without in zip(results["with"], results["without"]):
        eq = lambda r: "yes" if fm.first_difference(r.lines, twin) is None else "no"
        print(f"{with_.flags.label:34} {eq(with_):>9} {with_.fma:4d}   {'':18} {eq(without):>9} "
              f"{without.fma:4d}")
    absent = [c for c in fm.HOST_COMPILERS if not any(r.flags.compiler == c for r in results["with"])]
    if absent or not any(r.flags.target != "host" for r in results["with"]):
        print("not installed here: " + ", ".join(absent + ([] if any(r.flags.target != "host"
              for r in results["with"]) else ["arm-none-eabi-gcc / qemu-system-arm"])))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=60.0, help="s (default 60)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--no-matrix", action="store_true", help="only the fault injection")
    args = ap.parse_args(argv)
    result = fault_injection(args.duration, args.seed)
    if not args.no_matrix:
        with tempfile.TemporaryDirectory(prefix="fricgen_flags_") as tmp:
            matrix(result, Path(tmp))
    return 0


if __name__ == "__main__":
    sys.exit(main())
