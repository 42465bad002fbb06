"""Instructions of one ``NAME_force`` call on the emulated MCUs, the largest over a set of speeds.

For each target (Cortex-M4F, Cortex-M0+), curve kind (a sigmoid ELM of [F7], the grey-box
[F1] with gauss sources) and ``--activation-impl`` (libm, fast), and two sizes each (M hidden
units or S sources), the firmware of examples/firmware/ calls the emitted ``fm_force`` once at
each speed of SPEEDS (times v_sat) and QEMU counts the instructions of that call (one per
translation block, as benchmarks/firmware_cost.py). The largest count over the speeds, for
the two sizes, gives the line a + b n that fricgen.codegen.cost.INSTRUCTIONS_MAX holds (printed
at the end, ready to paste).

    python benchmarks/instructions_per_call.py [--targets cortex-m4f,cortex-m0plus]

Needs arm-none-eabi-gcc, libnewlib-arm-none-eabi and qemu-system-arm.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

from fricgen import codegen
from fricgen.data import synthesize_benchmark
from fricgen.firmware import build as fw
from fricgen.fit.elm import ELMRegressor, EnlargedScheme
from fricgen.fit.oracle import OracleRegressor
from fricgen.friction import preset
from fricgen.model import FrictionModel

#: Speeds of one call each, times v_sat: standstill, the Stribeck region, saturation, beyond.
SPEEDS = (0.0, 1e-3, 0.02, 0.1, 0.3, 0.7, 1.0, 2.0, -0.3, -2.0)
#: The two sizes of each kind (M for the ELM, S for the grey-box).
SIZES = {"elm": (1, 10), "stribeck": (1, 3)}


def model_of(kind: str, n: int) -> FrictionModel:
    bench = synthesize_benchmark(preset("paper3"), seed=0)
    if kind == "elm":
        est = ELMRegressor(n_hidden=n, scheme=EnlargedScheme(w_max=30.0), solver="loo", random_state=0)
    else:
        est = OracleRegressor("gauss", n)
    return FrictionModel.fit(bench.dataset, est, name="fm")


def call_max(model: FrictionModel, impl: str, target: str, tmp: Path) -> tuple:
    """The largest instruction count of one fm_force call over SPEEDS, and its speed / v_sat."""
    src = tmp / "src"
    codegen.emit(model, src, "fm", activation_impl=impl, force=True)
    counts = []
    for k, s in enumerate(SPEEDS):
        cfg = fw.config_float("fm.h", "fm_force", [s * model.v_sat], 1)
        elf = fw.build_firmware(src, cfg, target, tmp / f"build{k}")
        counts.append(sum(fw.count_instructions(elf, target).values()))
    k = int(np.argmax(counts))
    return counts[k], SPEEDS[k]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--targets", default="cortex-m4f,cortex-m0plus")
    args = ap.parse_args(argv)
    reason = fw.missing_tools()
    if reason:
        print(f"instructions_per_call: {reason}", file=sys.stderr)
        return 2
    lines = {}
    with tempfile.TemporaryDirectory(prefix="fricgen_ipc_") as tmp:
        for kind, sizes in SIZES.items():
            models = {n: model_of(kind, n) for n in sizes}
            for impl in ("libm", "fast"):
                for target in args.targets.split(","):
                    worst = []
                    for n in sizes:
                        folder = Path(tmp) / f"{kind}_{impl}_{target}_{n}"
                        count, speed = call_max(models[n], impl, target, folder)
                        worst.append(count)
                        print(f"{target:14s} {kind:8s} {impl:4s} n={n:2d}: at most {count:6d} "
                              f"instructions per call (at v = {speed:g} v_sat)", flush=True)
                    b = (worst[1] - worst[0]) / (sizes[1] - sizes[0])
                    lines[(target, kind, impl)] = (round(worst[0] - b * sizes[0], 1), round(b, 2))
    print("\nINSTRUCTIONS_MAX = {")
    for key, ab in lines.items():
        print(f"    {key!r}: {ab!r},")
    print("}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
