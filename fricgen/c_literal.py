"""C literals that read back exactly as the float32 values of a model (emitted tables, effects)."""
from __future__ import annotations

from typing import Iterable

import numpy as np

from .errors import ModelError


def c_float(value: float) -> str:
    """A C float literal that round-trips the float32 rounding of ``value`` exactly (9 digits)."""
    with np.errstate(over="ignore"):
        f = np.float32(value)
    if not np.isfinite(f):
        raise ModelError(f"the model holds {float(value):.6g}, not representable as a finite C "
                         "float (float32); it cannot be emitted")
    text = f"{float(f):.9g}"
    if not any(c in text for c in ".en"):
        text += ".0"
    elif "e" in text and "." not in text.split("e")[0]:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}.0e{exponent}"
    return text + "f"


def c_list(items: Iterable[str], per_line: int = 4) -> str:
    """Body of a C array initializer: the literals ``items``, ``per_line`` to an indented line."""
    items = list(items)
    lines = [", ".join(items[i:i + per_line]) for i in range(0, len(items), per_line)]
    return ",\n".join("    " + line for line in lines)


def c_array(values: Iterable[float], per_line: int = 4) -> str:
    """A float table's initializer body, every value an exact float literal."""
    return c_list((c_float(v) for v in values), per_line)
