"""Firmware cost of emitted friction models on Cortex-M4F and Cortex-M0+, against emlearn.

Beside them, the grey-box [F1] with S = 3 gauss sources (rows greybox-libm, greybox-fast, M = 3).
For M in {6, 10, 20, 50} hidden sigmoids (paper benchmark, seed 0, fricgen's enlarged scheme
with C by leave-one-out) and each implementation -- fricgen libm, fast, q15, q31, and emlearn
converting the same network (one logistic hidden layer, identity output, 'loadable' method,
regressor) wrapped in the same [F3] -- the script cross-builds the firmware of
examples/firmware/ and measures:
  flash_bytes, ram_bytes: text + data and data + bss over the same harness without a model
                          (so what the model pulls in from libm/libgcc is counted);
  instructions_per_call:  QEMU, one instruction per translation block, between two marker
                          calls, averaged over the calls made there;
  max_abs_err_newton:     the emulated MCU's outputs against the float64 model on 201 velocities
                          in [-2 v_sat, 2 v_sat].

    python benchmarks/firmware_cost.py [--json] [--sizes 6,10,20,50]

Needs arm-none-eabi-gcc, libnewlib-arm-none-eabi, qemu-system-arm and `pip install emlearn`.
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

from fricgen import codegen
from fricgen.codegen import fixedpoint as fx
from fricgen.firmware import build as fw
from fricgen.c_literal import c_float
from fricgen.data import synthesize_benchmark
from fricgen.fit.elm import ELMRegressor, EnlargedScheme
from fricgen.fit.oracle import OracleRegressor
from fricgen.friction import preset
from fricgen.model import FrictionModel, ModelError

IMPLS = ("fricgen-libm", "fricgen-fast", "fricgen-q15", "fricgen-q31", "emlearn")
#: The float implementations of the grey-box model (M = S = 3 in the rows).
GREYBOX_IMPLS = ("greybox-libm", "greybox-fast")
N_BENCH = {"cortex-m4f": 8, "cortex-m0plus": 2}


def train(m: int) -> FrictionModel:
    bench = synthesize_benchmark(preset("paper3"), seed=0)
    est = ELMRegressor(n_hidden=m, scheme=EnlargedScheme(w_max=30.0), solver="loo", random_state=0)
    return FrictionModel.fit(bench.dataset, est, name="fm")


def train_greybox() -> FrictionModel:
    """The grey-box [F1] with S = 3 gauss sources (Table 1's structure), paper benchmark seed 0."""
    bench = synthesize_benchmark(preset("paper3"), seed=0)
    return FrictionModel.fit(bench.dataset, OracleRegressor("gauss", 3), name="fm")


def model_size(model: FrictionModel) -> int:
    """M hidden units of an ELM, S sources of a grey-box curve."""
    return getattr(model.aim, "n_hidden", None) or model.aim.n_sources


def import_emlearn():
    """emlearn, imported without its global ``numpy.seterr(all='raise')`` (emlearn/bayes.py)."""
    saved = np.geterr()
    try:
        import emlearn
        from emlearn import net  # noqa: F401
    finally:
        np.seterr(**saved)
    return emlearn


def emlearn_sources(model: FrictionModel, folder: Path) -> None:
    """emlearn's 'loadable' C for the same network, and [F3] around it as ``eml_fm_force``."""
    net = import_emlearn().net

    a = model.aim
    code = net.c_generate_net_loadable(
        ["logistic", "identity"],
        [a.input_weights.reshape(1, -1).astype(np.float32), a.output_weights.reshape(-1, 1).astype(np.float32)],
        [a.biases.astype(np.float32), np.zeros(1, dtype=np.float32)], "eml_fm")
    (folder / "eml_fm.h").write_text("float eml_fm_force(float v);\n")
    (folder / "eml_fm.c").write_text(f"""{code}

#include "eml_fm.h"
float eml_fm_force(float v)
{{
    const float speed = v < 0.0f ? -v : v;
    const float x = {c_float(model.scaling.k_in)} * (speed < {c_float(model.v_sat)} ? speed : {c_float(model.v_sat)});
    const float stribeck = eml_fm_regress1(&x, 1) * {c_float(1.0 / model.scaling.k_out)};
    const float signed_stribeck = v > 0.0f ? stribeck : (v < 0.0f ? -stribeck : 0.0f);
    return signed_stribeck + {c_float(model.viscous)} * v;
}}
""")


def baseline(kind: str, target: str, tmp: Path, inputs) -> dict:
    folder = tmp / f"base_{kind}_{target}"
    (folder / "src").mkdir(parents=True, exist_ok=True)
    if kind == "float":
        (folder / "src" / "ident.h").write_text("float fw_ident(float v);\n")
        (folder / "src" / "ident.c").write_text('#include "ident.h"\nfloat fw_ident(float v) { return v; }\n')
        cfg = fw.config_float("ident.h", "fw_ident", inputs, 1)
    else:
        (folder / "src" / "ident.h").write_text(f"#include <stdint.h>\n{kind} fw_ident({kind} v);\n")
        (folder / "src" / "ident.c").write_text(f'#include "ident.h"\n{kind} fw_ident({kind} v) {{ return v; }}\n')
        cfg = fw.config_int("ident.h", "fw_ident", kind, inputs, 1)
    return fw.section_sizes(fw.build_firmware(folder / "src", cfg, target, folder / "build"))


def measure(model: FrictionModel, impl: str, target: str, tmp: Path, bases: dict) -> dict:
    folder = tmp / f"{impl}_{target}_{model_size(model)}"
    src = folder / "src"
    src.mkdir(parents=True, exist_ok=True)
    v = np.linspace(-2 * model.v_sat, 2 * model.v_sat, 201).astype(np.float32)
    extra_inc = []
    if impl in ("fricgen-q15", "fricgen-q31"):
        dtype = impl.split("-")[1]
        spec = fx.FixedSpec.of(model, dtype)
        codegen.emit(model, src, "fm", dtype=dtype)
        ctype = "int16_t" if dtype == "q15" else "int32_t"
        v_q = fx.to_fixed(v, spec.f_v, spec.bits)
        cfg = fw.config_int("fm.h", f"fm_force_{dtype}", ctype, v_q, N_BENCH[target])
        base = bases[(ctype, target)]
    else:
        if impl == "emlearn":
            emlearn_sources(model, src)
            extra_inc = [import_emlearn().includedir]
            cfg = fw.config_float("eml_fm.h", "eml_fm_force", v, N_BENCH[target])
        else:
            codegen.emit(model, src, "fm", activation_impl=impl.split("-")[1])
            for ctrl in src.glob("fric_ctrl.*"):
                ctrl.unlink()  # the model alone
            cfg = fw.config_float("fm.h", "fm_force", v, N_BENCH[target])
        base = bases[("float", target)]
    elf = fw.build_firmware(src, cfg, target, folder / "build", strict_model=impl != "emlearn",
                            include_dirs=extra_inc)
    sizes = fw.section_sizes(elf)
    lines = fw.run(elf, target)
    if impl in ("fricgen-q15", "fricgen-q31"):
        out = fw.parse_int_bits(lines) * 2.0 ** -spec.f_f
        v_used = v_q * 2.0 ** -spec.f_v
    else:
        out = fw.parse_float_bits(lines).astype(float)
        v_used = v.astype(float)
    counts = fw.count_instructions(elf, target)
    return {"impl": impl, "target": target, "n_hidden": model_size(model),
            "flash_bytes": sizes["flash"] - base["flash"], "ram_bytes": sizes["ram"] - base["ram"],
            "instructions_per_call": sum(counts.values()) / N_BENCH[target],
            "max_abs_err_newton": float(np.max(np.abs(out - model.force(v_used))))}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print {'rows': [...]} as JSON")
    ap.add_argument("--sizes", default="6,10,20,50", help="hidden-layer sizes (comma-separated)")
    ap.add_argument("--targets", default="cortex-m4f,cortex-m0plus")
    ap.add_argument("--no-greybox", action="store_true",
                    help="leave out the grey-box [F1] with S = 3 gauss sources")
    args = ap.parse_args(argv)
    reason = fw.missing_tools()
    if reason:
        print(f"firmware_cost: {reason}", file=sys.stderr)
        return 2
    rows, refused = [], []
    targets = args.targets.split(",")
    with tempfile.TemporaryDirectory(prefix="fricgen_fwcost_") as tmp:
        tmp = Path(tmp)
        probe = np.zeros(4, dtype=np.float32)
        bases = {(k, t): baseline(k, t, tmp, probe) for k in ("float", "int16_t", "int32_t") for t in targets}
        runs = [(train(int(s)), IMPLS) for s in args.sizes.split(",")]
        if not args.no_greybox:
            runs.append((train_greybox(), GREYBOX_IMPLS))
        for model, impls in runs:
            m = model_size(model)
            for impl in impls:
                for target in targets:
                    try:
                        rows.append(measure(model, impl, target, tmp, bases))
                    except ModelError as exc:
                        refused.append({"impl": impl, "target": target, "n_hidden": m, "reason": str(exc)})
                    if not args.json:
                        print(_fmt(rows[-1]) if rows and rows[-1]["impl"] == impl and rows[-1]["n_hidden"] == m
                              and rows[-1]["target"] == target else f"{impl:14s} {target:14s} M={m:3d} refused",
                              flush=True)
    if args.json:
        print(json.dumps({"rows": rows, "refused": refused}, indent=1))
    else:
        _ratios(rows)
    return 0


def _fmt(r: dict) -> str:
    return (f"{r['impl']:14s} {r['target']:14s} M={r['n_hidden']:3d} flash {r['flash_bytes']:6d} B  "
            f"ram {r['ram_bytes']:4d} B  {r['instructions_per_call']:9.1f} instr/call  "
            f"max err {r['max_abs_err_newton']:.3g} N")


def _ratios(rows) -> None:
    by = {(r["impl"], r["target"], r["n_hidden"]): r for r in rows}
    print("\nratios to emlearn (flash, instructions per call):")
    for (impl, target, m), r in sorted(by.items()):
        e = by.get(("emlearn", target, m))
        if e and impl != "emlearn":
            print(f"  {impl:14s} {target:14s} M={m:3d}  flash x{r['flash_bytes'] / e['flash_bytes']:.2f}  "
                  f"instructions x{r['instructions_per_call'] / e['instructions_per_call']:.2f}")


if __name__ == "__main__":
    sys.exit(main())
