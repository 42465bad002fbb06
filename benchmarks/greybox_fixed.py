"""Grey-box models in fixed point (``--dtype q15|q31``: [F1] as an AIM table) on the MCUs.

The default model fitted to a Table 1 sweep (each shape, seed 1000), and the asymmetric default
of a 20-speed sweep per direction (``asymmetric_model``: a table per direction, and its
NAME_compensation_q15 with a velocity band, "q15 band"), is emitted in q15 and q31
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
from dataclasses import replace
from pathlib import Path

import numpy as np

from default_vs_oracle import sweep
from small_sweeps import sweep as small_sweep

import fricgen
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
    firmware) of ``variant`` (q15, q31, libm, fast; "q15 band": NAME_compensation_q15)."""
    src = tmp / "src"
    v_sat = max(c.v_sat for c in model.directions)
    if variant.startswith("q"):
        dtype = variant.split()[0]
        codegen.emit(model, src, "fm", dtype=dtype, force=True)
        spec = ft.table_specs(model, dtype)[0]
        ctype = "int16_t" if dtype == "q15" else "int32_t"
        function = f"fm_compensation_{dtype}" if variant.endswith("band") else f"fm_force_{dtype}"
        configs = [fw.config_int("fm.h", function, ctype,
                                 [int(round(s * v_sat * 2.0 ** spec.f_v))], 1) for s in SPEEDS]
    else:
        codegen.emit(model, src, "fm", activation_impl=variant, force=True)
        configs = [fw.config_float("fm.h", "fm_force", [s * v_sat], 1) for s in SPEEDS]
    counts = []
    for k, cfg in enumerate(configs):
        elf = fw.build_firmware(src, cfg, target, tmp / f"build{k}")
        counts.append(sum(fw.count_instructions(elf, target).values()))
    return max(counts), fw.section_sizes(elf)["flash"]


def asymmetric_model() -> FrictionModel:
    """The default of a sweep of 20 log-spaced speeds per direction of small_sweeps.py's
    "textbook" law (seed 1000): a textbook law per direction; with a velocity band of 2 mm/s,
    as a log's resolution gives one."""
    v, f = small_sweep("textbook", 20, np.random.default_rng(1000))
    model = fricgen.train({"v": v, "f": f}, warn=lambda line: None).model
    return replace(model, name="fm", velocity_band=0.002)


def models():
    """(label, model, variants): the default of a Table 1 sweep of each shape, and an asymmetric one."""
    for shape in ("gauss", "exponential", "rational"):
        model = FrictionModel.fit(prepare(sweep(preset("paper3", shape), 1000), vs_max=0.02),
                                  DefaultRegressor(), name="fm")
        yield shape, model, ("q15", "q31", "libm", "fast")
    yield "asymmetric", asymmetric_model(), ("q15", "q15 band", "q31", "libm", "fast")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--targets", default="cortex-m0plus,cortex-m4f")
    args = ap.parse_args(argv)
    reason = fw.missing_tools()
    if reason:
        print(f"greybox_fixed: {reason}", file=sys.stderr)
        return 2
    print(f"{'model':12s} {'target':14s} {'variant':8s} {'instr/call':>10s} {'flash B':>8s} "
          f"{'table':>6s} {'bound N':>9s} {'max err N':>9s}", flush=True)
    with tempfile.TemporaryDirectory(prefix="fricgen_gbq_") as tmp:
        for label, model, variants in models():
            if not all(c.aim.kind == "stribeck" for c in model.directions):
                print(f"{label:12s} the default chose an ELM; skipped", flush=True)
                continue
            for target in args.targets.split(","):
                for variant in variants:
                    count, flash = call_max(model, variant, target,
                                            Path(tmp) / f"{label}{target}{variant.replace(' ', '')}")
                    extra = ""
                    if variant in ("q15", "q31"):
                        specs = ft.table_specs(model, variant)
                        v_q = np.arange(-2 ** 15, 2 ** 15) * (1 if variant == "q15" else 2 ** 16)
                        err = np.abs(ft.force_tables_q(specs, v_q) * 2.0 ** -specs[0].f_f
                                     - model.force(v_q * 2.0 ** -specs[0].f_v)).max()
                        extra = (f"{sum(s.table.size for s in specs):6d} "
                                 f"{ft.tables_error_bound(specs, model):9.3g} {err:9.3g}")
                    print(f"{label:12s} {target:14s} {variant:8s} {count:10d} {flash:8d} {extra}",
                          flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
