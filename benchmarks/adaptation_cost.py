"""Instructions per update of the online adaptation (``emit --adapt``) on the emulated Cortex-M4F
and Cortex-M0+ (soft float).

For a 10-neuron sigmoid ELM and a grey-box model with S = 3 gauss sources, fitted to the
paper's benchmark, each recording its axis as every model ``fricgen train`` writes does (theta
ends with the axis's offset), each with ``--activation-impl`` libm and fast, the firmware of
examples/firmware/ runs ``fric_adapt_ctrl_step`` (the RLS or Lyapunov update, the adapted
force and the controller step of section 6) N_BENCH times at a speed where the update is
active (no dead zone, no saturation: with the default Lyapunov gain the repeated update at one
state drove a 5-neuron model's current up to the limit, where adaptation holds), and QEMU counts the instructions (as
benchmarks/firmware_cost.py). Side by side: ``fric_ctrl_step_fn`` with the fixed model, the
same controller step without adaptation; their difference is what adaptation costs. The
target: at most 2000 instructions per update at M = 10. ``--sizes`` measures ELMs of other sizes
as well (M <= 16: the C holds 18 parameters, M weights, B and an offset) and prints, per implementation and rule, the curve
a + b M (Lyapunov) or a + b M + c M^2 (RLS, whose covariance update is quadratic) through them:
what ``fricgen.codegen.cost.ADAPT_INSTRUCTIONS`` holds for the fit report.

    python benchmarks/adaptation_cost.py [--sizes 1,5,10,15] [--targets cortex-m4f,cortex-m0plus]

Needs arm-none-eabi-gcc, libnewlib-arm-none-eabi and qemu-system-arm.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from adaptation_offset import with_axis  # noqa: E402
from fricgen import codegen
from fricgen.control.c_adapted import render_adapt
from fricgen.data import synthesize_benchmark
from fricgen.firmware import build as fw
from fricgen.fit.elm import ELMRegressor, EnlargedScheme
from fricgen.fit.oracle import OracleRegressor
from fricgen.friction import preset
from fricgen.model import FrictionModel

N_BENCH = 200

WRAPPER = r"""
#include "fw_step.h"
#include "fm.h"
#include "fm_adapt.h"
static fric_adapt_t a;
static fric_ctrl_t c;
static int ready;
float fw_step(float v)
{
    float i = 0.0f;
    if (!ready) {
        fric_ctrl_params_t cp;
        fric_adapt_params_t ap;
        fric_ctrl_default_params(&cp);
        (void)fric_ctrl_init(&c, &cp);
        (void)fm_adapt_default_params(&ap, %(rule)s, 1e-3f);
        ap.e_dead = 0.0f;
        ap.gain = 1e-9f;   /* the same operations, but theta barely moves: no saturation */
        (void)fric_adapt_init(&a, &ap);
        ready = 1;
    }
    %(call)s
    return i;
}
"""
ADAPTED = "(void)fric_adapt_ctrl_step(&a, &c, fm_regressor, 0.0f, v, 1e-4f, v, 0.0f, &i);"
FIXED = "(void)fric_ctrl_step_fn(&c, 0.0f, v, 1e-4f, v, 0.0f, fm_force, &i);"


def models(sizes=(10,)):
    """The ELMs of ``sizes`` and a 3-source grey-box model, each with the axis record that
    every model ``fricgen train`` writes holds, so that theta ends with the axis's offset."""
    bench = synthesize_benchmark(preset("paper3"), seed=0)
    elms = {f"ELM M = {m}": FrictionModel.fit(bench.dataset, ELMRegressor(
                n_hidden=m, scheme=EnlargedScheme(w_max=30.0), solver="loo", random_state=0), name="fm")
            for m in sizes}
    fitted = {**elms, "grey-box S = 3": FrictionModel.fit(bench.dataset, OracleRegressor("gauss", 3),
                                                          name="fm")}
    return {label: with_axis(model, 1.0) for label, model in fitted.items()}


def per_call(model, impl: str, rule: str, call: str, tmp: Path, target: str) -> float:
    src = tmp / "src"
    codegen.emit(model, src, "fm", activation_impl=impl, with_controller=True)
    for name, text in render_adapt(model, "fm", impl).items():     # what emit --adapt adds
        (src / name).write_text(text)
    (src / "fw_step.h").write_text("float fw_step(float v);\n")
    (src / "fw_step.c").write_text(WRAPPER % {"rule": rule, "call": call})
    cfg = fw.config_float("fw_step.h", "fw_step", [0.05, 0.06], N_BENCH)
    elf = fw.build_firmware(src, cfg, target, tmp / "build", strict_model=False)
    return sum(fw.count_instructions(elf, target).values()) / N_BENCH


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="10", help="ELM sizes M, comma-separated (default 10)")
    ap.add_argument("--targets", default="cortex-m4f,cortex-m0plus",
                    help="targets, comma-separated (default both)")
    args = ap.parse_args(argv)
    targets = args.targets.split(",")
    sizes = [int(m) for m in args.sizes.split(",")]
    reason = fw.missing_tools()
    if reason:
        print(f"adaptation_cost: {reason}", file=sys.stderr)
        return 2
    print(f"{'target':13s} {'model':16s} {'impl':5s} {'rule':9s} {'adapted step':>12s} "
          f"{'fixed step':>10s} {'adaptation':>10s}  (instructions per call)", flush=True)
    cost = {}
    with tempfile.TemporaryDirectory(prefix="fricgen_acost_") as tmp:
        for target in targets:
            for label, model in models(sizes).items():
                for impl in ("libm", "fast"):
                    for rule in ("FRIC_ADAPT_RULE_LYAPUNOV", "FRIC_ADAPT_RULE_RLS"):
                        folder = Path(tmp) / f"{target}{label[:3]}{impl}{rule[-3:]}"
                        adapted = per_call(model, impl, rule, ADAPTED, folder / "a", target)
                        fixed = per_call(model, impl, rule, FIXED, folder / "f", target)
                        short = "lyapunov" if rule.endswith("LYAPUNOV") else "rls"
                        print(f"{target:13s} {label:16s} {impl:5s} {short:9s} {adapted:12.0f} "
                              f"{fixed:10.0f} {adapted - fixed:10.0f}", flush=True)
                        if label.startswith("ELM") and target == "cortex-m4f":
                            cost.setdefault((short, impl), []).append((model.aim.n_hidden,
                                                                       adapted - fixed))
    if len(sizes) > 1:
        print("\nadaptation alone through the ELM sizes on Cortex-M4F (instructions per update), "
              "a + b M [+ c M^2]:")
        for (rule, impl), points in sorted(cost.items()):
            m, n = np.array(points, dtype=float).T
            coef = np.polyfit(m, n, 2 if rule == "rls" else 1)[::-1]
            worst = float(np.max(np.abs(np.polyval(coef[::-1], m) - n)))
            print(f"  {rule:9s} {impl:5s} " + ", ".join(f"{k} = {c:.2f}" for k, c in zip("abc", coef))
                  + f"  (largest miss {worst:.0f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
