"""Cost per call of the emitted ``NAME_force`` for a network of M sigmoid units: a + b M.

The coefficients are least-squares lines through measurements, one per activation
implementation of ``fricgen emit``:

- Cortex-M4F instructions per call: ``python benchmarks/firmware_cost.py --json --sizes
  1,10,30,60 --targets cortex-m4f`` (QEMU mps2-an386, arm-none-eabi-gcc, newlib's ``expf``),
  which measured libm 131, 911, 2635, 5251 and fast 79, 304, 804, 1554 instructions for
  M = 1, 10, 30, 60 (libm within 10 instructions of its line: ``expf`` takes a few more or
  fewer by input range; fast exactly on its line).
- Host nanoseconds per call: ``python benchmarks/scale.py`` (its ``host_ns``: gcc -O2
  -ffp-contract=off, glibc's ``expf``, best of 5 runs of 4e5 calls) on the 2-core x86-64 machine
  fricgen is developed on, which measured 8.9, 99, 268, 572, 1156 ns for M = 1, 10, 30, 60, 120.
  Another host scales these by its speed; the benchmark measures it.
"""
from __future__ import annotations

from typing import Dict, Tuple

#: (a, b) of instructions = a + b M on Cortex-M4F, per ``--activation-impl``.
CORTEX_M4F_INSTRUCTIONS: Dict[str, Tuple[float, float]] = {"libm": (41.4, 86.76), "fast": (54.0, 25.0)}

#: (a, b) of ns = a + b M on the reference x86-64 host, ``--activation-impl libm``.
HOST_NS: Tuple[float, float] = (-5.7, 9.65)


def cortex_m4f_instructions(n_hidden: int, activation_impl: str = "libm") -> float:
    """Instructions per ``NAME_force`` call on Cortex-M4F for ``n_hidden`` sigmoid units."""
    a, b = CORTEX_M4F_INSTRUCTIONS[activation_impl]
    return a + b * n_hidden


def host_ns(n_hidden: int) -> float:
    """Nanoseconds per ``NAME_force`` call on the reference host for ``n_hidden`` sigmoid units."""
    a, b = HOST_NS
    return max(a + b * n_hidden, 0.0)
