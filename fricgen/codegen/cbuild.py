"""Compile emitted C with cffi and load it, for parity checks (tests, demo, simulate)."""
from __future__ import annotations

import hashlib
import importlib.util
import tempfile
from pathlib import Path
from typing import Iterable, Optional, Union

from ..errors import BuildError

#: Flags of the cffi builds: C99 without floating-point contraction, as the parity proofs assume.
CFLAGS = ["-std=c99", "-O2", "-ffp-contract=off"]
#: The strict warning set the emitted code must pass without a single warning.
STRICT_WARNINGS = ["-Wall", "-Wextra", "-Wpedantic", "-Wdouble-promotion", "-Wfloat-conversion",
                   "-Wconversion", "-Wshadow", "-Wfloat-equal", "-Werror"]


def model_cdef(name: str, model=None) -> str:
    """The cffi declarations of an emitted model's API: with ``NAME_force_with_offset`` for a
    ``model`` that records its axis (NAME.h declares it then)."""
    with_offset = getattr(model, "axis", None) is not None
    offset = f"float {name}_force_with_offset(float v);\n" if with_offset else ""
    return f"float {name}_force(float v);\nfloat {name}_aim(float x);\n{offset}"


def build(folder: Union[str, Path], header: str, cdef: str, sources: Optional[Iterable[Path]] = None,
          build_dir: Optional[Union[str, Path]] = None):
    """Compile every .c file in ``folder`` into a cffi extension; return its ``lib``
    (``build_module`` returns the module, with its ``ffi`` beside ``lib``)."""
    return build_module(folder, header, cdef, sources, build_dir).lib


def build_module(folder: Union[str, Path], header, cdef: str,
                 sources: Optional[Iterable[Path]] = None,
                 build_dir: Optional[Union[str, Path]] = None):
    """Compile every .c file in ``folder`` into a cffi extension; return the module.

    ``header`` is the file (or a sequence of files) the wrapper includes; ``cdef`` declares what
    Python may call.
    """
    import cffi

    folder = Path(folder).resolve()
    sources = sorted(folder.glob("*.c")) if sources is None else [Path(s) for s in sources]
    digest = hashlib.sha256(cdef.encode())
    for src in sorted(sources) + sorted(folder.glob("*.h")):
        digest.update(src.name.encode() + src.read_bytes())
    module = f"_fricgen_{digest.hexdigest()[:16]}"
    build_dir = Path(tempfile.mkdtemp(prefix="fricgen_cffi_") if build_dir is None else build_dir)
    ffi = cffi.FFI()
    ffi.cdef(cdef)
    headers = [header] if isinstance(header, str) else list(header)
    ffi.set_source(module, "".join(f'#include "{h}"\n' for h in headers),
                   sources=[str(s) for s in sources], include_dirs=[str(folder)],
                   extra_compile_args=CFLAGS, libraries=["m"])
    try:
        so_path = ffi.compile(tmpdir=str(build_dir), verbose=False)
    except Exception as exc:        # cffi's and setuptools' compiler errors share no base class
        first = next((line for line in str(exc).splitlines() if line.strip()), type(exc).__name__)
        raise BuildError(f"cannot compile the emitted C with cffi ({first.strip()[:160]}); is a C "
                         "compiler installed (CC)?") from exc
    spec = importlib.util.spec_from_file_location(module, so_path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def build_model(folder: Union[str, Path], name: str, build_dir=None):
    """Compile an emitted model folder and return the cffi ``lib`` with NAME_force, NAME_aim."""
    return build(folder, f"{name}.h", model_cdef(name), build_dir=build_dir)
