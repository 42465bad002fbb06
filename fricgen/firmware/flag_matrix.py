"""The C runtime and emitted models built under a matrix of compiler flags: compiler x C standard
x optimization, on the host and on the Cortex-M4F under QEMU.

Each build runs one probe (``probe_source``): the forces of each emitted model at given
velocities, and controller steps (``fric_ctrl_step``) on given input rows, every result printed
as the hex bits of its float. ``twin_lines`` gives the same lines from the Python twins, so a
build means what the twins mean when its lines are equal. ``fma_count`` counts the fused
multiply-add instructions in the runtime's and models' objects: the runtime turns contraction
off (fric_float.h, included by every runtime and model source), so every build should
have none.

On an x86-64 host that has FMA, the host builds get ``-mfma``, so the compiler may contract
(without it x86-64 has no FMA instruction and the matrix would prove nothing).
"""
from __future__ import annotations

import platform
import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Sequence

import numpy as np

from ..codegen.cbuild import STRICT_WARNINGS
from ..codegen.render import FLOAT_HEADER
from ..codegen.twin import force_f32
from ..control.c_abi import params_initializer
from ..friction import preset
from ..model import FrictionModel
from ..networks import StribeckCurve
from . import build as fw

STDS = ("c99", "gnu99")
#: Flags that relax IEEE arithmetic one by one: each build must give the twins' bits or fail
#: to compile (``fric_float.h``).
RELAXING_FLAGS = ("-funsafe-math-optimizations", "-fassociative-math", "-freciprocal-math",
                  "-ffp-contract=fast")
OPTS = ("-O0", "-O2", "-Os")
HOST_COMPILERS = ("gcc", "clang")
#: Mnemonics of fused multiply-add: x86 (vfmadd231ss ...), Arm VFP (vfma.f32 ...), AArch64.
_FMA = re.compile(r"^(vfn?m(add|sub)\w*|vfn?m[as](\.f32)?|fn?m(add|sub))$")


def table1_greybox(bench, shape: str = "gauss", name: str = "gb"):
    """Table 1 itself as a grey-box model of [F3] with the scaling of ``bench`` (a
    ``synthesize_benchmark`` result): a model with [F1]'s exponentials to build."""
    d, friction = bench.dataset, preset("paper3", shape)
    k_in, k_out = d.scaling.k_in, d.scaling.k_out
    curve = StribeckCurve(shape, k_out * sum(s.fc for s in friction.sources),
                          np.array([k_out * (s.fs - s.fc) for s in friction.sources]),
                          np.array([k_in * s.vs for s in friction.sources]))
    return FrictionModel(curve, d.scaling, friction.viscous, d.v_sat, name=name)


def host_fma_flags() -> List[str]:
    """["-mfma"] on an x86-64 host whose CPU has FMA, else [] (AArch64 always has it)."""
    if platform.machine() not in ("x86_64", "AMD64"):
        return []
    try:
        cpu = Path("/proc/cpuinfo").read_text()
    except OSError:
        return []
    return ["-mfma"] if re.search(r"^flags\s*:.*\bfma\b", cpu, re.M) else []


@dataclass(frozen=True)
class FlagSet:
    """One build of the flag matrix: compiler, C standard and optimization.

    Parameters
    ----------
    compiler : str
        "gcc", "clang" (host builds) or ``build.CC`` (the Cortex-M4F under QEMU).
    std : str
        The C standard: "c99" or "gnu99".
    opt : str
        The optimization flag: "-O0", "-O2" or "-Os".
    extra : str
        More flags, space-separated ("" for none), e.g. "-funsafe-math-optimizations"
        (``RELAXING_FLAGS``).

    Examples
    --------
    >>> from fricgen.firmware import FlagSet
    >>> fs = FlagSet("gcc", "gnu99", "-Os")
    >>> fs.target, fs.lang_flags, fs.label
    ('host', ['-std=gnu99', '-Os'], 'gcc -std=gnu99 -Os')
    """

    compiler: str
    std: str
    opt: str
    extra: str = ""

    @property
    def target(self) -> str:
        return "cortex-m4f" if self.compiler == fw.CC else "host"

    @property
    def lang_flags(self) -> List[str]:
        return [f"-std={self.std}", self.opt] + self.extra.split()

    @property
    def label(self) -> str:
        return " ".join([self.compiler, f"-std={self.std}", self.opt] + self.extra.split())


def available_flag_sets(stds: Sequence[str] = STDS, opts: Sequence[str] = OPTS,
                        arm: bool = True) -> List[FlagSet]:
    """Every flag set whose compiler is installed (the Cortex-M4F also needs QEMU).

    Parameters
    ----------
    stds, opts : sequence of str
        The C standards and optimization flags to combine.
    arm : bool
        Whether the Cortex-M4F builds are included when its tools are installed.

    Returns
    -------
    list of FlagSet
        Compiler x standard x optimization, host compilers first.

    Examples
    --------
    >>> from fricgen.firmware import available_flag_sets
    >>> sets = available_flag_sets(stds=("c99",), opts=("-O2",), arm=False)
    >>> all(fs.target == "host" and fs.opt == "-O2" for fs in sets)
    True
    """
    compilers = [c for c in HOST_COMPILERS if shutil.which(c)]
    if arm and fw.missing_tools() is None:
        compilers.append(fw.CC)
    return [FlagSet(c, s, o) for c in compilers for s in stds for o in opts]


def _bits_list(values) -> str:
    words = [f"0x{int(u):08x}u" for u in np.asarray(values, dtype=np.float32).ravel().view(np.uint32)]
    return ",\n".join(", ".join(words[k:k + 6]) for k in range(0, len(words), 6))


def probe_source(models: Sequence[str], velocities, rows, settings) -> Dict[str, str]:
    """probe.h, probe.c (``probe_run(write)``: "f HEX" per model and velocity, then
    "c I FLAGS M_O_HAT K_HAT" per row of ``rows`` (n x 6: x, v, xd, xd', xd'', force) through
    ``fric_ctrl_step`` with the parameters of ``settings``), and probe_main.c (the host's
    main, printing to stdout), by file name."""
    v = np.asarray(velocities, dtype=np.float32).ravel()
    rows = np.asarray(rows, dtype=np.float32).reshape(-1, 6)
    includes = "".join(f'#include "{m}.h"\n' for m in models)
    header = ("/* probe.h: written by fricgen.firmware.flag_matrix. */\n"
              "#ifndef PROBE_H\n#define PROBE_H\n"
              "void probe_run(void (*write)(const char *text));\n#endif\n")
    source = f"""/* probe.c: written by fricgen.firmware.flag_matrix. */
#include <stdint.h>
#include "fric_ctrl.h"
{includes}#include "probe.h"

typedef float (*probe_force_fn)(float v);
static const probe_force_fn probe_models[{len(models)}] = {{{", ".join(f"{m}_force" for m in models)}}};
static const uint32_t probe_v[{v.size}] = {{
{_bits_list(v)}
}};
static const uint32_t probe_rows[{rows.size}] = {{  /* 6 per row */
{_bits_list(rows)}
}};
static const fric_ctrl_params_t probe_params = {params_initializer(settings)};

static float probe_float(uint32_t u)
{{
    union {{ uint32_t u; float f; }} c;
    c.u = u;
    return c.f;
}}

static uint32_t probe_bits(float f)
{{
    union {{ uint32_t u; float f; }} c;
    c.f = f;
    return c.u;
}}

static char *probe_hex(char *out, uint32_t u)
{{
    int k;
    *out++ = ' ';
    for (k = 7; k >= 0; --k) {{
        out[k] = "0123456789abcdef"[u & 0xfu];
        u >>= 4;
    }}
    return out + 8;
}}

void probe_run(void (*write)(const char *text))
{{
    char line[1 + 4 * 9 + 2];
    fric_ctrl_t c;
    unsigned m, k;
    for (m = 0; m < {len(models)}u; ++m) {{
        for (k = 0; k < {v.size}u; ++k) {{
            char *p = line;
            *p++ = 'f';
            p = probe_hex(p, probe_bits(probe_models[m](probe_float(probe_v[k]))));
            *p++ = '\\n';
            *p = '\\0';
            write(line);
        }}
    }}
    if (fric_ctrl_init(&c, &probe_params) != FRIC_CTRL_OK) {{
        write("c init-failed\\n");
        return;
    }}
    for (k = 0; k < {rows.shape[0]}u; ++k) {{
        const uint32_t *r = &probe_rows[6u * k];
        float i = 0.0f;
        const fric_ctrl_flags_t flags = fric_ctrl_step(&c, probe_float(r[0]), probe_float(r[1]),
            probe_float(r[2]), probe_float(r[3]), probe_float(r[4]), probe_float(r[5]), &i);
        char *p = line;
        *p++ = 'c';
        p = probe_hex(p, probe_bits(i));
        p = probe_hex(p, (uint32_t)flags);
        p = probe_hex(p, probe_bits(c.m_o_hat));
        p = probe_hex(p, probe_bits(c.k_hat));
        *p++ = '\\n';
        *p = '\\0';
        write(line);
    }}
}}
"""
    main = ("/* probe_main.c: written by fricgen.firmware.flag_matrix. */\n#include <stdio.h>\n"
            '#include "probe.h"\n\nstatic void probe_write(const char *text)\n{\n'
            "    (void)fputs(text, stdout);\n}\n\nint main(void)\n{\n"
            "    probe_run(probe_write);\n    return 0;\n}\n")
    return {"probe.h": header, "probe.c": source, "probe_main.c": main}


def twin_lines(models: Dict[str, object], impl: str, velocities, rows, settings) -> List[str]:
    """The lines the probe prints, from the twins: ``fricgen.twin.force_f32`` (``impl`` as
    emitted) and ``settings`` as a float32 ``AdaptiveBackstepping``."""
    hexes = lambda *vals: " ".join(f"{int(np.asarray(x, dtype=np.float32).view(np.uint32)):08x}"
                                   for x in vals)
    v = np.asarray(velocities, dtype=np.float32).ravel()
    lines = [f"f {u:08x}" for model in models.values()
             for u in force_f32(model, v, impl).astype(np.float32).view(np.uint32)]
    ctrl = settings.clone(dtype="float32").reset()
    with np.errstate(all="ignore"):
        for r in np.asarray(rows, dtype=np.float32).reshape(-1, 6):
            i = ctrl.step_with_force(*r)
            lines.append(f"c {hexes(i)} {int(ctrl.flags_):08x} {hexes(*ctrl.a_)}")
    return lines


def fma_count(objects: Iterable[Path], objdump: str) -> int:
    """Fused multiply-add instructions in the disassembly of ``objects``."""
    out = subprocess.run([objdump, "-d", *map(str, objects)], capture_output=True, text=True,
                         check=True).stdout
    mnemonics = (line.split("\t")[2].split()[0] for line in out.splitlines()
                 if line.count("\t") >= 2 and line.split("\t")[2].strip())
    return sum(1 for m in mnemonics if _FMA.match(m))


@dataclass(frozen=True)
class MatrixRow:
    """One build: its flag set, the lines its probe printed, its FMA count."""

    flags: FlagSet
    lines: List[str]
    fma: int


def _host_build(folder: Path, fs: FlagSet, out: Path) -> MatrixRow:
    out.mkdir(parents=True, exist_ok=True)
    flags = host_fma_flags() + STRICT_WARNINGS + fs.lang_flags + [f"-I{folder}"]   # extra last
    runtime = []
    for src in sorted(folder.glob("*.c")):
        obj = out / (src.stem + ".o")
        proc = subprocess.run([fs.compiler, *flags, "-c", str(src), "-o", str(obj)],
                              capture_output=True, text=True)
        if proc.returncode != 0:
            raise fw.FirmwareError(f"{fs.label}: {src.name} does not build:\n{proc.stderr[:2000]}")
        if not src.stem.startswith("probe"):
            runtime.append(obj)
    exe = out / "probe"
    subprocess.run([fs.compiler, *fs.lang_flags, *host_fma_flags(), *map(str, sorted(out.glob("*.o"))),
                    "-o", str(exe), "-lm"], check=True, capture_output=True)
    lines = subprocess.run([str(exe)], capture_output=True, text=True, check=True,
                           timeout=120).stdout.splitlines()
    return MatrixRow(fs, lines, fma_count(runtime, "objdump"))


def _arm_build(folder: Path, models: Sequence[str], fs: FlagSet, out: Path) -> MatrixRow:
    model_dir = out / "model"
    shutil.copytree(folder, model_dir, ignore=shutil.ignore_patterns("probe*"))
    cfg = fw.config_float(f"{models[0]}.h", f"{models[0]}_force", [0.0],
                          extra='#include "probe.h"\n#define FW_EXTRA() probe_run(sh_write0)\n')
    elf = fw.build_firmware(model_dir, cfg, fs.target, out / "build",
                            extra_sources=[folder / "probe.c"], include_dirs=[folder],
                            strict_extra=True, lang_flags=fs.lang_flags)
    objects = sorted((out / "build" / "model").glob("*.o"))
    lines = [line for line in fw.run(elf, fs.target) if line[:2] in ("f ", "c ")]  # the probe's
    return MatrixRow(fs, lines, fma_count(objects, "arm-none-eabi-objdump"))


def run_matrix(folder, models: Sequence[str], flag_sets: Sequence[FlagSet], out_dir,
               velocities, rows, settings) -> List[MatrixRow]:
    """Write the probe into ``folder`` (an emit folder with the models ``models`` and the
    controller runtime), build it under each flag set in ``out_dir`` and run it."""
    folder, out_dir = Path(folder), Path(out_dir)
    for name, text in probe_source(models, velocities, rows, settings).items():
        (folder / name).write_text(text)
    result = []
    for k, fs in enumerate(flag_sets):
        out = out_dir / f"{k:02d}"
        result.append(_host_build(folder, fs, out) if fs.target == "host"
                      else _arm_build(folder, models, fs, out))
    return result


#: The block of FLOAT_HEADER (c_runtime/fric_float.h): the #error under -ffast-math and the
#: pragmas that turn contraction off.
FP_BLOCK = re.compile(r"#if defined\(__FAST_MATH__\).*?#pragma STDC FP_CONTRACT OFF\n#endif\n", re.S)
#: A local include, ``#include "file"``.
LOCAL_INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*"([^"]+)"', re.M)


def fp_blocks(folder) -> Dict[str, str]:
    """The float-semantics block of each C file in ``folder`` that has one, by file name."""
    found = {}
    for path in sorted(Path(folder).glob("*.[ch]")):
        m = FP_BLOCK.search(path.read_text())
        if m:
            found[path.name] = m.group(0)
    return found


def includes_float_semantics(folder) -> Dict[str, bool]:
    """Whether each .c file in ``folder`` includes FLOAT_HEADER, directly or through the local
    headers it includes (followed within ``folder``), by file name."""
    folder = Path(folder)

    def reaches(name: str, seen: set) -> bool:
        path = folder / name
        if name in seen or not path.is_file():
            return False
        seen.add(name)
        included = LOCAL_INCLUDE.findall(path.read_text())
        return FLOAT_HEADER in included or any(reaches(inc, seen) for inc in included)

    return {path.name: reaches(path.name, set()) for path in sorted(folder.glob("*.c"))}


def strip_fp_blocks(folder) -> List[str]:
    """Remove the float-semantics block from the C files in ``folder`` (what the runtime was
    without it, for the benchmark's comparison); the names of the files changed."""
    changed = []
    for name in fp_blocks(folder):
        path = Path(folder) / name
        path.write_text(FP_BLOCK.sub("", path.read_text()))
        changed.append(name)
    return changed


def first_difference(lines: Sequence[str], expected: Sequence[str]) -> Optional[str]:
    """None when the lines are equal, else where they first differ."""
    if list(lines) == list(expected):
        return None
    k = next((j for j, (a, b) in enumerate(zip(lines, expected)) if a != b),
             min(len(lines), len(expected)))
    got = lines[k] if k < len(lines) else "<end>"
    want = expected[k] if k < len(expected) else "<end>"
    return f"line {k}: {got!r}, twin {want!r} ({len(lines)} lines, twin {len(expected)})"
