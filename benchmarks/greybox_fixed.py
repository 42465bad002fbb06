"""Grey-box models in fixed point (``--dtype q15|q31``: [F1] as an AIM table) on the MCUs.

The default model fitted to a Table 1 sweep (each shape, seed 1000) is emitted in q15 and q31
(``fricgen.codegen.fixed_table``) and, side by side, in float (libm and the fast activation).
For each, on Cortex-M0+ (no FPU: float is soft float) and Cortex-M4F, the firmware of
examples/firmware/ calls ``fm_force*`` once at each speed of SPEEDS (times v_sat) and QEMU
counts the instructions of that call (as benchmarks/instructions_per_call.py). Printed: the
largest count over the speeds, the flash bytes of the whole firmware (one harness for every
variant: the differences are the model's), the table's
size and the error bound of NAME.h against the float64 model, and the largest error measured
over every q15 input.

    python benchmarks/greybox_fixed.py [--targets cortex-m0plus,cortex-m4f]

Needs arm-none-eabi-gcc, libnewlib-arm-none-eabi and qemu-system-arm.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

from default_vs_oracle import sweep
from fricgen import codegen
from fricgen.codegen import fixed_table as ft
from fricgen.data import prepare
from fricgen.firmware import build as fw
from fricgen.fit import DefaultRegressor
from fricgen.friction import preset
from fricgen.model import FrictionModel

#: Speeds of one call each, times v_sat: standstill, the Stribeck region, saturation, beyond.
SPEEDS = (0.0, 1e-3, 0.02, 0.1, 0.3, 0.7, 1.0, 1.5, -0.3, -1.5)


def call_max(model: FrictionModel, variant: str, target: str, tmp: Path) -> tuple:
    """(the largest instruction count of one call over SPEEDS, the flash bytes of the
    firmware) of ``variant`` (q15, q31, libm, fast)."""
    src = tmp / "src"
    if variant in ("q15", "q31"):
        codegen.emit(model, src, "fm", dtype=variant, force=True)
        spec = ft.TableSpec.of(model, variant)
        ctype = "int16_t" if variant == "q15" else "int32_t"
        configs = [fw.config_int("fm.h", f"fm_force_{variant}", ctype,
                                 [int(round(s * model.v_sat * 2.0 ** spec.f_v))], 1) for s in SPEEDS]
    else:
        codegen.emit(model, src, "fm", activation_impl=variant, force=True)
        configs = [fw.config_float("fm.h", "fm_force", [s * model.v_sat], 1) for s in SPEEDS]
    counts = []
    for k, cfg in enumerate(configs):
        elf = fw.build_firmware(src, cfg, target, tmp / f"build{k}")
        counts.append(sum(fw.count_instructions(elf, target).values()))
    return max(counts), fw.section_sizes(elf)["flash"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--targets", default="cortex-m0plus,cortex-m4f")
    args = ap.parse_args(argv)
    reason = fw.missing_tools()
    if reason:
        print(f"greybox_fixed: {reason}", file=sys.stderr)
        return 2
    print(f"{'shape':12s} {'target':14s} {'variant':7s} {'instr/call':>10s} {'flash B':>8s} "
          f"{'table':>6s} {'bound N':>9s} {'max err N':>9s}", flush=True)
    with tempfile.TemporaryDirectory(prefix="fricgen_gbq_") as tmp:
        for shape in ("gauss", "exponential", "rational"):
            model = FrictionModel.fit(prepare(sweep(preset("paper3", shape), 1000), vs_max=0.02),
                                      DefaultRegressor(), name="fm")
            if model.aim.kind != "stribeck":
                print(f"{shape:12s} the default chose an ELM; skipped", flush=True)
                continue
            for target in args.targets.split(","):
                for variant in ("q15", "q31", "libm", "fast"):
                    count, flash = call_max(model, variant, target, Path(tmp) / f"{shape}{target}{variant}")
                    extra = ""
                    if variant in ("q15", "q31"):
                        spec = ft.TableSpec.of(model, variant)
                        v_q = np.arange(-2 ** 15, 2 ** 15) * (1 if variant == "q15" else 2 ** 16)
                        err = np.abs(ft.force_table_q(spec, v_q) * 2.0 ** -spec.f_f
                                     - model.force(v_q * 2.0 ** -spec.f_v)).max()
                        extra = (f"{spec.table.size:6d} {ft.table_error_bound(spec, model):9.3g} "
                                 f"{err:9.3g}")
                    print(f"{shape:12s} {target:14s} {variant:7s} {count:10d} {flash:8d} {extra}",
                          flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
