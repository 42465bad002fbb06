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

from .cbuild import STRICT_WARNINGS
from .codegen import c_float

CC = "arm-none-eabi-gcc"
SIZE = "arm-none-eabi-size"
NM = "arm-none-eabi-nm"
QEMU = "qemu-system-arm"
#: Flags of every cross build: C99, no floating-point contraction (so the Python twins stay
#: exact), one section per function so the linker drops what nobody calls.
COMMON_FLAGS = ["-std=c99", "-O2", "-ffp-contract=off", "-ffunction-sections", "-fdata-sections"]


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
    """A cross build or an emulator run failed; the message holds the tool's output."""


def missing_tools(run: bool = True) -> Optional[str]:
    """Why cross builds (and, with ``run``, emulator runs) cannot happen here, or None."""
    tools = [CC, SIZE, NM] + ([QEMU] if run else [])
    absent = [t for t in tools if shutil.which(t) is None]
    if absent:
        return f"{', '.join(absent)} not installed (apt-get install gcc-arm-none-eabi " \
               f"libnewlib-arm-none-eabi qemu-system-arm)"
    return None


def firmware_dir() -> Path:
    """examples/firmware/ of the source tree: startup, linker script, semihosting, harness."""
    path = Path(__file__).resolve().parent.parent / "examples" / "firmware"
    if not (path / "fw_main.c").is_file():
        raise FirmwareError(f"firmware sources not found in {path} (a source checkout is needed)")
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
                    include_dirs: Iterable[Union[str, Path]] = (), strict: bool = True) -> List[Path]:
    """Compile each C source to an object for ``target_name`` (strict warnings: -Werror)."""
    tgt, out_dir = target(target_name), Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    flags = COMMON_FLAGS + list(tgt.cpu_flags) + (STRICT_WARNINGS if strict else ["-Wall", "-Wextra"])
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
                   include_dirs: Sequence[Union[str, Path]] = ()) -> Path:
    """The firmware ELF: harness + startup + every .c of ``model_dir`` (+ ``extra_sources``).

    ``config_h`` is the text of fw_config.h (see ``config_float``); the model's own files are
    compiled with the strict warning set.
    """
    fw, out_dir, model_dir = firmware_dir(), Path(out_dir), Path(model_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "fw_config.h").write_text(config_h)
    incs = [out_dir, model_dir, fw] + [Path(d) for d in include_dirs]
    objs = compile_objects(sorted(model_dir.glob("*.c")), target_name, out_dir / "model", incs, strict_model)
    objs += compile_objects(list(extra_sources), target_name, out_dir / "extra", incs, strict=False)
    objs += compile_objects([fw / "startup.c", fw / "fw_main.c"], target_name, out_dir / "fw", incs,
                            strict=False)
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
    """Run the firmware on QEMU; return the lines it printed between begin and end markers."""
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


def _c_array(values: Iterable[str], per_line: int = 4) -> str:
    items = list(values)
    return ",\n".join("    " + ", ".join(items[i:i + per_line]) for i in range(0, len(items), per_line))


def config_float(model_header: str, fn: str, inputs, n_bench: int = 0, extra: str = "") -> str:
    """fw_config.h for a float model function ``float fn(float)`` over ``inputs``."""
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
{_c_array(c_float(v) for v in inputs)}
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
{_c_array(f"({ctype})({int(v)}{'L' if ctype == 'int32_t' else ''})" for v in inputs)}
}};
{extra}
"""


def parse_float_bits(lines: Iterable[str]) -> np.ndarray:
    return np.array([int(s, 16) for s in lines], dtype=np.uint32).view(np.float32)


def parse_int_bits(lines: Iterable[str]) -> np.ndarray:
    return np.array([int(s, 16) for s in lines], dtype=np.uint32).view(np.int32).astype(np.int64)
