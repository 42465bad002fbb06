"""Cross builds of emitted C for Cortex-M and runs on QEMU's emulated MCUs (examples/firmware/).

Targets: ``cortex-m4f`` (hard float, run on QEMU's ``mps2-an386``) and ``cortex-m0plus``
(ARMv6-M soft float, run on QEMU's ``microbit``, a Cortex-M0: the same instruction set).
Instructions are counted deterministically: QEMU translates one instruction per block
(``-singlestep``) and logs every block it executes (``-d exec,nochain``) with the name of the
function it lies in; the count is the number of logged blocks between the calls to
``fw_mark_begin`` and ``fw_mark_end``, outside the harness's own ``main``.
"""
from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from .._io import resource_dir
from ..c_literal import c_float, c_list
from ..codegen.cbuild import STRICT_WARNINGS
from ..codegen.package import emit

CC = "arm-none-eabi-gcc"
SIZE = "arm-none-eabi-size"
NM = "arm-none-eabi-nm"
QEMU = "qemu-system-arm"
#: Flags of every cross build: C99, no floating-point contraction (so the Python twins stay
#: exact), one section per function so the linker drops what nobody calls.
COMMON_FLAGS = ["-std=c99", "-O2", "-ffp-contract=off", "-ffunction-sections", "-fdata-sections"]
#: The part of COMMON_FLAGS that is not the language and optimization (``lang_flags`` replace those).
SECTION_FLAGS = ["-ffunction-sections", "-fdata-sections"]


@dataclass(frozen=True)
class Target:
    name: str
    cpu_flags: Tuple[str, ...]
    machine: str


TARGETS: Dict[str, Target] = {
    "cortex-m4f": Target("cortex-m4f", ("-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard",
                                        "-mfpu=fpv4-sp-d16"), "mps2-an386"),
    "cortex-m0plus": Target("cortex-m0plus", ("-mcpu=cortex-m0plus", "-mthumb", "-mfloat-abi=soft"),
                            "microbit"),
}


class FirmwareError(RuntimeError):
    """A cross build or an emulator run failed; the message holds the tool's output.

    Examples
    --------
    >>> from fricgen.firmware import FirmwareError
    >>> issubclass(FirmwareError, RuntimeError)
    True
    """


def missing_tools(run: bool = True) -> Optional[str]:
    """Why cross builds (and, with ``run``, emulator runs) cannot happen here: the tools not
    installed and how to install them; None when all are.

    Parameters
    ----------
    run : bool
        Whether QEMU is needed too.

    Examples
    --------
    >>> from fricgen.firmware import missing_tools
    >>> missing_tools() is None or "not installed" in missing_tools()
    True
    """
    tools = [CC, SIZE, NM] + ([QEMU] if run else [])
    absent = [t for t in tools if shutil.which(t) is None]
    if absent:
        return f"{', '.join(absent)} not installed (apt-get install gcc-arm-none-eabi " \
               f"libnewlib-arm-none-eabi qemu-system-arm)"
    return None


def firmware_dir() -> Path:
    """The bare-metal harness (examples/firmware/): startup, linker script, semihosting, harness."""
    try:
        path = resource_dir("firmware_sources")
    except FileNotFoundError as exc:
        raise FirmwareError(str(exc)) from None
    if not (path / "fw_main.c").is_file():
        raise FirmwareError(f"firmware sources not found in {path} (broken install?)")
    return path


def target(name: str) -> Target:
    if name not in TARGETS:
        raise ValueError(f"target must be one of {sorted(TARGETS)}, got {name!r}")
    return TARGETS[name]


def _run(cmd: Sequence[str], timeout: float = 120) -> subprocess.CompletedProcess:
    proc = subprocess.run(list(cmd), capture_output=True, text=True, timeout=timeout,
                          stdin=subprocess.DEVNULL)
    if proc.returncode != 0:
        raise FirmwareError(f"{' '.join(cmd[:3])} ... failed ({proc.returncode}):\n{proc.stderr}{proc.stdout}"[:4000])
    return proc


def compile_objects(sources: Iterable[Union[str, Path]], target_name: str, out_dir: Union[str, Path],
                    include_dirs: Iterable[Union[str, Path]] = (), strict: bool = True,
                    lang_flags: Optional[Sequence[str]] = None) -> List[Path]:
    """Compile each C source to an object for ``target_name`` (strict warnings: -Werror).
    ``lang_flags`` (e.g. ["-std=gnu99", "-Os"]) replace COMMON_FLAGS' language, optimization
    and contraction flags."""
    tgt, out_dir = target(target_name), Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    base = COMMON_FLAGS if lang_flags is None else list(lang_flags) + SECTION_FLAGS
    flags = base + list(tgt.cpu_flags) + (STRICT_WARNINGS if strict else ["-Wall", "-Wextra"])
    flags += [f"-I{d}" for d in include_dirs]
    objects = []
    for src in sources:
        obj = out_dir / (Path(src).stem + ".o")
        _run([CC] + flags + ["-c", str(src), "-o", str(obj)])
        objects.append(obj)
    return objects


def link(objects: Iterable[Path], target_name: str, elf: Union[str, Path], gc_sections: bool = True) -> Path:
    """Link objects with the firmware's linker script, newlib's libm/libc and libgcc."""
    tgt = target(target_name)
    flags = list(tgt.cpu_flags) + ["-nostartfiles", "-T", str(firmware_dir() / "cortex_m.ld"),
                                   "--specs=nano.specs"]
    if gc_sections:
        flags.append("-Wl,--gc-sections")
    _run([CC] + flags + [str(o) for o in objects] + ["-o", str(elf), "-lm", "-lc", "-lgcc"])
    return Path(elf)


def build_firmware(model_dir: Union[str, Path], config_h: str, target_name: str,
                   out_dir: Union[str, Path], extra_sources: Sequence[Union[str, Path]] = (),
                   strict_model: bool = True, gc_sections: bool = True,
                   include_dirs: Sequence[Union[str, Path]] = (), strict_extra: bool = False,
                   lang_flags: Optional[Sequence[str]] = None) -> Path:
    """The firmware ELF (returned): harness + startup + every .c of ``model_dir``.

    Parameters
    ----------
    model_dir, out_dir : path
        An emit folder, and where fw_config.h, the objects and fw.elf go.
    config_h : str
        The text of fw_config.h (``config_float``).
    target_name : str
        A key of ``TARGETS``.
    extra_sources, include_dirs : sequence of path
        More C sources and include directories.
    strict_model, strict_extra, gc_sections : bool
        Strict warnings (-Werror) for the model's and the extra sources; --gc-sections.
    lang_flags : sequence of str, optional
        Replace the C standard and optimization flags (``compile_objects``).

    Examples
    --------
    >>> from fricgen.firmware import build_firmware, config_float
    >>> build_firmware(tmp, config_float("m.h", "m_force", [0.0]), "cortex-m7", tmp / "fw")
    Traceback (most recent call last):
    ValueError: target must be one of ['cortex-m0plus', 'cortex-m4f'], got 'cortex-m7'
    """
    fw, out_dir, model_dir = firmware_dir(), Path(out_dir), Path(model_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "fw_config.h").write_text(config_h)
    incs = [out_dir, model_dir, fw] + [Path(d) for d in include_dirs]
    objs = compile_objects(sorted(model_dir.glob("*.c")), target_name, out_dir / "model", incs, strict_model,
                           lang_flags)
    objs += compile_objects(list(extra_sources), target_name, out_dir / "extra", incs,
                            strict=strict_extra, lang_flags=lang_flags)
    objs += compile_objects([fw / "startup.c", fw / "fw_main.c"], target_name, out_dir / "fw", incs,
                            strict=False, lang_flags=lang_flags)
    return link(objs, target_name, out_dir / "fw.elf", gc_sections)


def section_sizes(elf: Union[str, Path]) -> Dict[str, int]:
    """text, data, bss bytes of an ELF (arm-none-eabi-size, Berkeley format)."""
    out = _run([SIZE, "-B", str(elf)]).stdout.splitlines()
    text, data, bss = (int(x) for x in out[1].split()[:3])
    return {"text": text, "data": data, "bss": bss, "flash": text + data, "ram": data + bss}


def symbols(elf: Union[str, Path]) -> List[str]:
    """Names of the symbols linked into an ELF."""
    out = _run([NM, str(elf)]).stdout.splitlines()
    return [line.split()[-1] for line in out if line.strip()]


def _qemu_cmd(elf: Path, target_name: str) -> List[str]:
    return [QEMU, "-M", target(target_name).machine, "-nographic", "-semihosting", "-kernel", str(elf)]


def run(elf: Union[str, Path], target_name: str, timeout: float = 120) -> List[str]:
    """Run the firmware on QEMU: the lines (hex bits of results) it printed between its markers.

    Parameters
    ----------
    elf : path
        A linked firmware.
    target_name : str
        A key of ``TARGETS`` (chooses the emulated board).
    timeout : float
        Seconds before the run is abandoned.

    Examples
    --------
    >>> from fricgen.firmware import TARGETS
    >>> {name: t.machine for name, t in TARGETS.items()}
    {'cortex-m4f': 'mps2-an386', 'cortex-m0plus': 'microbit'}
    """
    proc = _run(_qemu_cmd(Path(elf), target_name), timeout)
    lines = (proc.stdout + proc.stderr).splitlines()  # QEMU 7.2 prints semihosting on stderr
    try:
        first, last = lines.index("fricgen-fw begin"), lines.index("fricgen-fw end")
    except ValueError:
        raise FirmwareError(f"firmware output lacks its markers:\n{proc.stdout[-2000:]}") from None
    return lines[first + 1:last]


_TRACE = re.compile(r"^Trace \d+: \S+ \[[0-9a-f/]+\] (\S*)")


def count_instructions(elf: Union[str, Path], target_name: str, timeout: float = 300) -> Dict[str, int]:
    """Instructions executed between fw_mark_begin and fw_mark_end, by function (main excluded)."""
    with tempfile.TemporaryDirectory(prefix="fricgen_qemu_") as tmp:
        log = Path(tmp) / "exec.log"
        _run(_qemu_cmd(Path(elf), target_name) + ["-singlestep", "-d", "exec,nochain", "-D", str(log)],
             timeout)
        counts: Dict[str, int] = {}
        state = 0
        with open(log, errors="replace") as fh:
            for line in fh:
                m = _TRACE.match(line)
                if not m:
                    continue
                fn = m.group(1)
                if state == 0:
                    state = 1 if fn == "fw_mark_begin" else 0
                elif fn == "fw_mark_end":
                    break
                elif fn not in ("fw_mark_begin", "main"):
                    counts[fn] = counts.get(fn, 0) + 1
        if state == 0:
            raise FirmwareError("the execution log never reached fw_mark_begin")
    return counts


def most_instructions(model_dir: Union[str, Path], header: str, entry: str, inputs,
                      target_name: str, work_dir: Union[str, Path], extra: str = "") -> int:
    """The most instructions one call of ``entry`` (float (float), ``extra`` may define it as a
    wrapper) takes over ``inputs``: one firmware build per input (a call from a fresh state),
    counted under QEMU (``count_instructions``)."""
    counts = []
    for k, value in enumerate(inputs):
        cfg = config_float(header, entry, [value], 1, extra=extra)
        elf = build_firmware(model_dir, cfg, target_name, Path(work_dir) / f"{target_name}_{entry}_{k}")
        counts.append(sum(count_instructions(elf, target_name).values()))
    return max(counts)


def print_call_costs(model, wrappers: Dict[str, Tuple[str, str]], inputs, unit: str,
                     **emit_options) -> None:
    """Print the table of ``most_instructions`` of each of ``wrappers`` (column name -> (entry,
    extra)) over ``inputs`` (in ``unit``), for ``model`` emitted as ``fm`` with the libm and the
    fast activation (``emit_options`` beside), on the emulated M0+ and M4F."""
    print(f"instructions of one call (most over the inputs {', '.join(f'{v:g}' for v in inputs)} "
          f"{unit}; QEMU, arm-none-eabi-gcc -O2, newlib; the M0+ in soft float)")
    print(f"  {'target':14s} {'impl':5s} " + " ".join(f"{fn:>16s}" for fn in wrappers))
    with tempfile.TemporaryDirectory(prefix="fricgen_cost_") as tmp:
        for impl in ("libm", "fast"):
            src = Path(tmp) / f"src_{impl}"
            emit(model, src, "fm", activation_impl=impl, force=True, **emit_options)
            for target_name in ("cortex-m0plus", "cortex-m4f"):
                cells = [most_instructions(src, "fm.h", entry, inputs, target_name, Path(tmp) / impl, extra)
                         for entry, extra in wrappers.values()]
                print(f"  {target_name:14s} {impl:5s} " + " ".join(f"{c:16d}" for c in cells), flush=True)


def c_inputs(ctype: str, values) -> str:
    """``values`` as the body of a C array initializer of ``ctype`` (float, int16_t or int32_t)."""
    if ctype == "float":
        return c_list(c_float(v) for v in np.asarray(values, dtype=np.float32))
    suffix = "L" if ctype == "int32_t" else ""
    return c_list(f"({ctype})({int(v)}{suffix})" for v in np.asarray(values, dtype=np.int64))


def config_float(model_header: str, fn: str, inputs, n_bench: int = 0, extra: str = "") -> str:
    """fw_config.h for a float model function ``float fn(float)`` over ``inputs``.

    Parameters
    ----------
    model_header, fn : str
        The header that declares ``fn``, and the C function.
    inputs : array_like
        The inputs (float32).
    n_bench : int
        Further evaluations timed between the benchmark markers.
    extra : str
        C text appended (e.g. ``FW_EXTRA()``).

    Examples
    --------
    >>> from fricgen.firmware import config_float
    >>> [ln for ln in config_float("a.h", "a_force", [0.0, 0.01]).splitlines() if "FW_N_" in ln]
    ['#define FW_N_INPUTS 2u', '#define FW_N_BENCH 0u']
    """
    inputs = np.asarray(inputs, dtype=np.float32)
    return f"""/* fw_config.h: written by fricgen.firmware. */
#include <stdint.h>
#include "{model_header}"
typedef float fw_input_t;
typedef float fw_output_t;
#define FW_EVAL(x) {fn}(x)
static uint32_t fw_bits(float y) {{ union {{ float f; uint32_t u; }} c; c.f = y; return c.u; }}
#define FW_BITS(y) fw_bits(y)
#define FW_N_INPUTS {inputs.size}u
#define FW_N_BENCH {int(n_bench)}u
static const float fw_inputs[{inputs.size}] = {{
{c_inputs("float", inputs)}
}};
{extra}
"""


def config_int(model_header: str, fn: str, ctype: str, inputs, n_bench: int = 0, extra: str = "") -> str:
    """fw_config.h for a fixed-point model function ``int32_t fn(ctype)`` over integer ``inputs``."""
    inputs = np.asarray(inputs, dtype=np.int64)
    return f"""/* fw_config.h: written by fricgen.firmware. */
#include <stdint.h>
#include "{model_header}"
typedef {ctype} fw_input_t;
typedef {ctype} fw_output_t;
#define FW_EVAL(x) {fn}(x)
#define FW_BITS(y) ((uint32_t)(int32_t)(y))
#define FW_N_INPUTS {inputs.size}u
#define FW_N_BENCH {int(n_bench)}u
static const {ctype} fw_inputs[{inputs.size}] = {{
{c_inputs(ctype, inputs)}
}};
{extra}
"""


def parse_float_bits(lines: Iterable[str]) -> np.ndarray:
    """The float32 values of hex bit lines (what a float model's run printed)."""
    return np.array([int(s, 16) for s in lines], dtype=np.uint32).view(np.float32)


def parse_int_bits(lines: Iterable[str]) -> np.ndarray:
    """The int32 values (as int64) of hex bit lines (a fixed-point model's run)."""
    return np.array([int(s, 16) for s in lines], dtype=np.uint32).view(np.int32).astype(np.int64)


# ----------------------------------------------------------------------------- several axes


@dataclass(frozen=True)
class Axis:
    """One model function of a several-axis program: ``fn`` from ``header``, of C type ``ctype``
    (``float``, or ``int16_t``/``int32_t`` for fixed point), evaluated at each of ``inputs``."""

    header: str
    fn: str
    ctype: str
    inputs: Sequence

    def parse(self, lines: Sequence[str]) -> np.ndarray:
        """This axis's printed results: float32, or int64 for fixed point."""
        return parse_float_bits(lines) if self.ctype == "float" else parse_int_bits(lines)


_FLOAT_BITS = "static uint32_t fw_axis_bits_f32(float y) { union { float f; uint32_t u; } c; c.f = y; return c.u; }"
_AXIS_LOOP = """    for (i = 0; i < {n}u; ++i) {{
        sh_put_hex({bits});
        sh_write0("\\n");
    }}"""


def config_axes(axes: Sequence[Axis], n_bench: int = 0, extra: str = "") -> str:
    """fw_config.h of one program that evaluates several models (e.g. two axes emitted into one
    folder): the first axis as ``config_float``/``config_int`` write it (and benchmarked), each
    further one through ``FW_AXES()`` right after it; ``parse_axes`` splits the output."""
    first, further = axes[0], list(axes[1:])
    decls, loops = [f'#include "{a.header}"' for a in further], []
    if any(a.ctype == "float" for a in further):
        decls.append(_FLOAT_BITS)
    for k, a in enumerate(further, start=1):
        n = np.asarray(a.inputs).size
        decls.append(f"static const {a.ctype} fw_axis{k}_inputs[{n}] = {{\n{c_inputs(a.ctype, a.inputs)}\n}};")
        call = f"{a.fn}(fw_axis{k}_inputs[i])"
        loops.append(_AXIS_LOOP.format(n=n, bits=f"fw_axis_bits_f32({call})" if a.ctype == "float"
                                       else f"(uint32_t)(int32_t){call}"))
    if further:
        decls += ["static void fw_axes(void)\n{\n    uint32_t i;", *loops, "}", "#define FW_AXES() fw_axes()"]
    more = "\n".join(decls) + "\n" + extra
    if first.ctype == "float":
        return config_float(first.header, first.fn, first.inputs, n_bench, more)
    return config_int(first.header, first.fn, first.ctype, first.inputs, n_bench, more)


def parse_axes(lines: Sequence[str], axes: Sequence[Axis]) -> List[np.ndarray]:
    """The results a ``config_axes`` program printed, one array per axis."""
    sizes = [np.asarray(a.inputs).size for a in axes]
    if len(lines) != sum(sizes):
        raise FirmwareError(f"expected {sum(sizes)} result lines for {len(axes)} axes, got {len(lines)}")
    ends = np.cumsum(sizes)
    return [a.parse(lines[end - n:end]) for a, n, end in zip(axes, sizes, ends)]
