"""The BLAS thread count of the running process, set for the length of a call.

The command line pins BLAS to one thread before numpy loads (``cli.pin_blas_threads``); a
program that imports fricgen has numpy loaded already, so the API sets the count of the
OpenBLAS libraries numpy and scipy loaded (found among the process's shared objects; their
functions may carry a ``scipy_`` prefix and a ``64_`` suffix) and restores it afterwards. Where
no OpenBLAS is found (another BLAS, another platform) nothing changes.
"""
from __future__ import annotations

import ctypes
import os
from contextlib import contextmanager
from typing import Iterator, List, Optional, Tuple

#: The name stems of OpenBLAS's thread functions, with their prefixes and suffixes.
_STEMS = ("openblas_{}_num_threads", "openblas_{}_num_threads64_",
          "scipy_openblas_{}_num_threads", "scipy_openblas_{}_num_threads64_")


def _openblas() -> List[Tuple[object, object]]:
    """(get, set) of every OpenBLAS loaded in this process; [] where none is found."""
    try:
        with open("/proc/self/maps") as fh:
            paths = sorted({line.split()[-1] for line in fh if "openblas" in line.lower()})
    except OSError:
        return []
    found = []
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for stem in _STEMS:
            get, put = (getattr(lib, stem.format(verb), None) for verb in ("get", "set"))
            if get is not None and put is not None:
                get.restype, put.argtypes = ctypes.c_int, [ctypes.c_int]
                found.append((get, put))
                break
    return found


def thread_count(text: str) -> Optional[int]:
    """A value of ``FRICGEN_BLAS_THREADS`` as a thread count: an integer from 1 to 1024, else
    None."""
    return int(text) if text.isascii() and text.isdigit() and 1 <= int(text) <= 1024 else None


def wanted_threads(environ=os.environ) -> int:
    """The BLAS threads fricgen's numerics use: ``FRICGEN_BLAS_THREADS`` (1 .. 1024), else 1."""
    return thread_count(environ.get("FRICGEN_BLAS_THREADS", "1")) or 1


@contextmanager
def blas_threads(count: int) -> Iterator[int]:
    """Run the block with ``count`` BLAS threads in every OpenBLAS of the process, restored
    after; yields how many libraries it set."""
    libraries = _openblas()
    before = [get() for get, _ in libraries]
    try:
        for _, put in libraries:
            put(int(count))
        yield len(libraries)
    finally:
        for (_, put), n in zip(libraries, before):
            put(n)


def thread_counts() -> List[int]:
    """The thread count of every OpenBLAS of the process (for tests and benchmarks)."""
    return [get() for get, _ in _openblas()]
