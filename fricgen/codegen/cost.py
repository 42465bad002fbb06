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

import math
from typing import Dict, Sequence, Tuple

#: (a, b) of instructions = a + b M on Cortex-M4F, per ``--activation-impl``.
CORTEX_M4F_INSTRUCTIONS: Dict[str, Tuple[float, float]] = {"libm": (41.4, 86.76), "fast": (54.0, 25.0)}

#: (a, b) of ns = a + b M on the reference x86-64 host, ``--activation-impl libm``.
HOST_NS: Tuple[float, float] = (-5.7, 9.65)


#: The most output parameters online adaptation holds (FRIC_ADAPT_MAX_PARAMS of fric_adapt.h):
#: an ELM of at most 16 units, B and the axis's offset.
ADAPT_MAX_PARAMS = 18

#: Instructions of one online-adaptation update (``emit --adapt``: ``fric_adapt_ctrl_step`` less
#: the fixed model's controller step) on Cortex-M4F for an ELM of M sigmoid units that records its
#: axis (theta ends with the offset, as for every model ``fricgen train`` writes), a + b M + c M^2,
#: by (rule, ``--activation-impl``): through M = 1, 5, 10, 15 of ``python
#: benchmarks/adaptation_cost.py --sizes 1,5,10,15`` (largest miss 12 instructions; RLS is
#: quadratic through its covariance update).
ADAPT_INSTRUCTIONS: Dict[Tuple[str, str], Tuple[float, float, float]] = {
    ("lyapunov", "libm"): (253.91, 139.79, 0.0), ("lyapunov", "fast"): (253.83, 115.28, 0.0),
    ("rls", "libm"): (449.88, 231.73, 10.77), ("rls", "fast"): (441.47, 207.69, 10.78)}


def adapt_instructions(n_hidden: int, rule: str = "lyapunov", activation_impl: str = "libm") -> float:
    """Instructions per online-adaptation update on Cortex-M4F for ``n_hidden`` sigmoid units."""
    a, b, c = ADAPT_INSTRUCTIONS[rule, activation_impl]
    return a + b * n_hidden + c * n_hidden ** 2


def cortex_m4f_instructions(n_hidden: int, activation_impl: str = "libm") -> float:
    """Instructions per ``NAME_force`` call on Cortex-M4F for ``n_hidden`` sigmoid units."""
    a, b = CORTEX_M4F_INSTRUCTIONS[activation_impl]
    return a + b * n_hidden


def host_ns(n_hidden: int) -> float:
    """Nanoseconds per ``NAME_force`` call on the reference host for ``n_hidden`` sigmoid units."""
    a, b = HOST_NS
    return max(a + b * n_hidden, 0.0)


#: Instructions of one ``NAME_force`` call, a + b n (n: sigmoid units of an ELM, [F7], or gauss
#: sources of the grey-box [F1]), by (target, curve kind, ``--activation-impl``): the line
#: through the largest count of one call over 10 speeds from standstill to 2 v_sat, for two
#: sizes (n = 1, 10 and S = 1, 3), from ``python benchmarks/instructions_per_call.py`` (QEMU,
#: one instruction per translation block, arm-none-eabi-gcc 12 -O2, newlib's expf; the M0+ in
#: soft float).
INSTRUCTIONS_MAX: Dict[Tuple[str, str, str], Tuple[float, float]] = {
    ("cortex-m4f", "elm", "libm"): (49.7, 94.33),
    ("cortex-m0plus", "elm", "libm"): (583.2, 3551.78),
    ("cortex-m4f", "elm", "fast"): (54.0, 25.0),
    ("cortex-m0plus", "elm", "fast"): (655.3, 1769.67),
    ("cortex-m4f", "stribeck", "libm"): (32.5, 94.5),
    ("cortex-m0plus", "stribeck", "libm"): (777.5, 3122.5),
    ("cortex-m4f", "stribeck", "fast"): (32.0, 45.0),
    ("cortex-m0plus", "stribeck", "fast"): (752.5, 1691.5),
}
#: The allowance NAME.h adds to INSTRUCTIONS_MAX for speeds and weights the 10 speeds did not
#: meet (libm's expf and soft float take data-dependent paths): a stated margin, not a bound.
INSTRUCTIONS_MARGIN = 0.25
#: The targets of INSTRUCTIONS_MAX and their C macro suffixes.
TARGETS = {"cortex-m4f": "CORTEX_M4F", "cortex-m0plus": "CORTEX_M0PLUS"}


def curve_cost_key(net) -> Tuple[str, int]:
    """A curve's (kind, n) in INSTRUCTIONS_MAX, or None where no line applies: ELM activations
    other than the sigmoid, and the rational shape (no exponential; the gauss line, one
    multiplication more than the exponential shape's, covers that shape)."""
    if net.kind == "elm":
        return ("elm", net.n_hidden) if net.activation == "sigmoid" else None
    return ("stribeck", net.n_sources) if net.shape in ("gauss", "exponential") else None


def instructions_max(nets: Sequence, activation_impl: str) -> Dict[str, int]:
    """The instructions of one ``NAME_force`` call with the curves ``nets`` (one per direction;
    a call runs one of them), at most, by target: (1 + INSTRUCTIONS_MARGIN) times the largest
    line, rounded up. Empty when a curve has no line (``curve_cost_key``)."""
    keys = [curve_cost_key(net) for net in nets]
    if any(k is None for k in keys):
        return {}
    result = {}
    for target in TARGETS:
        worst = max(a + b * n for (kind, n) in keys
                    for a, b in [INSTRUCTIONS_MAX[target, kind, activation_impl]])
        result[target] = int(math.ceil((1.0 + INSTRUCTIONS_MARGIN) * worst))
    return result
