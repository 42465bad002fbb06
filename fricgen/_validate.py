"""Validation helpers shared by every boundary: one message shape, ``NAME must be ..., got X``."""
from __future__ import annotations

import contextlib
import contextvars
import math
from typing import Iterator, Optional, Type

import numpy as np

from .errors import ModelError
from .unit_sizes import size

#: The largest hidden layer (or rule base) a model may hold: fixed-size C tables.
MAX_HIDDEN = 4096
#: The magnitudes the emitted float32 C computes reliably: the sweep's speed and force scales,
#: v_sat, the force scale, B (float32 spans 1.2e-38 to 3.4e38).
FLOAT32_SCALE = (1e-30, 1e30)
#: The largest magnitude a float32 holds (FLT_MAX): every number the C tables hold stays below.
FLOAT32_MAX = float(np.finfo(np.float32).max)

#: The physical range of a real servo axis, from a micro stage to a heavy gantry, in SI units
#: (``fricgen.data.plausibility`` checks data against it, ``FrictionModel`` a model.json):
#: the fastest speed of the data, m/s (1 um/s scans to 20 m/s linear motors and belt drives);
#: v_sat, m/s, bounded as the speed (a textbook law's v_sat is the fastest speed of its data, a
#: grey-box's 3 vs_max, from Stribeck velocities of 0.03 um/s up); the largest friction
#: force, N (10 uN in a flexure stage to 100 kN in a heavy gantry); the moving mass, kg (1 g to
#: 100 t); the largest motor current of a log, A (1 uA in a voice coil to 10 kA in the largest
#: drives).
PHYSICAL = {"speed": (1e-6, 20.0, "m/s"), "v_sat": (1e-7, 20.0, "m/s"),
            "force": (1e-5, 1e5, "N"), "mass": (1e-3, 1e5, "kg"), "current": (1e-6, 1e4, "A")}
#: Within PHYSICAL, beyond what most axes do (a warning line; a sweep's speed beyond it is
#: refused without --accept-unusual, ``data.plausibility.check_bounds``): the fastest speed
#: above 5 m/s, v_sat above 0.3 m/s (Stribeck velocities above 0.1 m/s): speeds in m/min or
#: mm/s read as m/s land there; the largest current above 500 A: a current in mA read as A
#: lands there (and would give a mass and forces a thousand times the axis').
USUAL_MAX = {"speed": 5.0, "v_sat": 0.3, "current": 500.0}
#: ... and a largest friction force below 0.1 N: forces in kN read as N land there.
USUAL_MIN = {"force": 0.1}
#: The same of a rotary axis (a robot joint, a motor shaft), in rad/s, Nm and kg m^2: speeds of
#: 1 urad/s to 10000 rad/s (a small motor's shaft at 95000 rpm), v_sat likewise, friction
#: torques of 10 uNm to 100 kNm, inertias of 1e-8 kg m^2 (a small rotor) to 1e5 kg m^2; most
#: joints and shafts turn below 1000 rad/s (9500 rpm), with v_sat below 30 rad/s.
PHYSICAL_ROTARY = {"speed": (1e-6, 1e4, "rad/s"), "v_sat": (1e-7, 1e4, "rad/s"),
                   "force": (1e-5, 1e5, "Nm"), "mass": (1e-8, 1e5, "kg m^2"),
                   "current": PHYSICAL["current"]}
#: A joint's or shaft's largest friction torque above 2 kNm (beyond the base joints of the
#: largest arms): a torque in mNm read as Nm lands there.
USUAL_MAX_ROTARY = {"speed": 1000.0, "v_sat": 30.0, "current": 500.0, "force": 2000.0}
#: ... and its largest friction torque below 1 mNm (a small servo motor's is tens of mNm).
USUAL_MIN_ROTARY = {"force": 1e-3}
#: The units a rotary axis's position and speed are often logged in: (column, unit, its size in
#: rad or rad/s), which the hints of a speed beyond the bounds name.
ROTARY_UNITS = tuple((column, unit, size(unit)) for column, unit in (("x", "deg"), ("v", "rpm"), ("v", "deg/s")))
_ROTARY = contextvars.ContextVar("rotary", default=False)


@contextlib.contextmanager
def rotary_axis(rotary: bool) -> Iterator[None]:
    """Within: the physical bounds and their messages are those of a rotary axis (``rotary``)."""
    token = _ROTARY.set(bool(rotary))
    try:
        yield
    finally:
        _ROTARY.reset(token)


def in_rotary_axis() -> bool:
    """Whether within ``rotary_axis(True)``."""
    return _ROTARY.get()


def physical_range(quantity: str):
    """(low, high, unit) of PHYSICAL[quantity], or PHYSICAL_ROTARY's within ``rotary_axis(True)``."""
    return _tables()[0][quantity]


def physical_unit(quantity: str) -> str:
    """The unit of ``physical_range(quantity)``."""
    return physical_range(quantity)[2]


def _tables():
    return (PHYSICAL_ROTARY, USUAL_MAX_ROTARY) if _ROTARY.get() else (PHYSICAL, USUAL_MAX)


def usual_max(quantity: str) -> Optional[float]:
    """USUAL_MAX[quantity], or USUAL_MAX_ROTARY's within ``rotary_axis(True)``; None where the
    table bounds no such quantity."""
    return _tables()[1].get(quantity)


#: The option that accepts data or a model outside PHYSICAL (``--force`` means "overwrite").
ACCEPT_UNUSUAL = "--accept-unusual"


#: The relative rounding a value may carry past a bound of PHYSICAL and still be at it (a speed
#: of 2 m/s computed as 2.0000000000000004 is the 2 m/s bound, not above it).
BOUND_ROUNDING = 1e-9


def physical_problem(quantity: str, what: str, value: float) -> str:
    """'' if ``value`` (a magnitude) lies within PHYSICAL[quantity], else the clause saying it does
    not: "WHAT is 199 m/s, beyond the 20 m/s of any real axis"."""
    low, high, unit = _tables()[0][quantity]
    value = abs(float(value))
    if value > high * (1.0 + BOUND_ROUNDING):
        return f"{what} is {value:.4g} {unit}, above the {high:g} {unit} of any real axis"
    if value < low * (1.0 - BOUND_ROUNDING):
        return f"{what} is {value:.4g} {unit}, below the {low:g} {unit} of any real axis"
    return ""


def unusual(quantity: str, what: str, value: float, column: str = "v", given: str = "") -> str:
    """'' if ``value`` lies within ``usual_max(quantity)``, else the clause saying it is unusual,
    with the units of ``column`` that would explain it: "WHAT is 15 m/s, above the 5 m/s of
    most axes: is v in m/min (--scale v=0.0166667) or mm/s (--scale v=0.001)?" (for a speed
    taken from the position x: "is x in mm (--scale x=0.001), or ... (--rotary)?"; for a
    joint's torque: "is tau in mNm (--scale tau=0.001)?"). ``given``: what the user's own --scale of ``column`` was,
    said instead of asking about units."""
    physical, usual = _tables()
    high, unit = usual[quantity], physical[quantity][2]
    value = abs(float(value))
    if value <= high:
        return ""
    clause = f"{what} is {value:.4g} {unit}, above the {high:g} {unit} of most axes"
    if given:
        return clause + given
    if quantity == "current":
        units = f"mA (--scale {column}=0.001)"
    elif quantity == "force":
        units = f"m{unit} (--scale {column}=0.001)"
    elif _ROTARY.get():
        units = rotary_units(column, "x" if column == "x" else "v")
    elif column == "x":
        units = "mm (--scale x=0.001), or the axis a joint or shaft in rad (--rotary)"
    else:
        units = (f"m/min (--scale {column}=0.0166667) or mm/s (--scale {column}=0.001), or the axis a "
                 f"joint or shaft (--rotary) in rad/s, or in {rotary_units(column, 'v')}")
    return f"{clause}: is {column} in {units}?"


def rotary_units(column: str, kind: str, fits=lambda size: True) -> str:
    """The ``ROTARY_UNITS`` of a position ("x") or a speed ("v") ``kind`` whose size ``fits``,
    each with the --scale of ``column``: "rpm (--scale v=0.10472) or deg/s (--scale v=0.0174533)"."""
    return " or ".join(f"{unit} (--scale {column}={size:.6g})" for c, unit, size in ROTARY_UNITS
                       if c == kind and fits(size))


def unusually_small(quantity: str, what: str, value: float, column: str, given: str = "") -> str:
    """'' if ``value`` is at least USUAL_MIN[quantity] (USUAL_MIN_ROTARY's on a rotary axis), else
    the clause saying it is unusual, with the units that would explain it: "WHAT is 0.004 N,
    below the 0.1 N of most axes' friction: is f in kN (--scale f=1000)?" (``given`` as
    ``unusual``)."""
    low, unit = (USUAL_MIN_ROTARY if _ROTARY.get() else USUAL_MIN)[quantity], physical_unit(quantity)
    value = abs(float(value))
    if value >= low:
        return ""
    clause = f"{what} is {value:.4g} {unit}, below the {low:g} {unit} of most axes' friction"
    return clause + (given or f": is {column} in k{unit} (--scale {column}=1000)?")


def _is_number(value) -> bool:
    return not isinstance(value, bool) and isinstance(value, (int, float, np.integer, np.floating))


def finite_number(value) -> bool:
    """Whether ``value`` is a finite number as JSON gives one (not a bool)."""
    return _is_number(value) and _finite(value)


def _finite(value) -> bool:
    """Whether the number ``value`` is finite as a float (an integer beyond float's range is not)."""
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def positive(name: str, value, error: Type[Exception] = ValueError, allow_inf: bool = False) -> float:
    """``value`` as a float if it is a number > 0 (finite unless ``allow_inf``), else ``error``
    naming ``name``."""
    if not (_is_number(value) and value > 0 and (allow_inf or _finite(value))):
        raise error(f"{name} must be > 0, got {value!r}"[:200])
    return float(value)


def integer(name: str, value, minimum: int = 1, error: Type[Exception] = ValueError) -> int:
    """``value`` as an int if it is an integer >= ``minimum``, else ``error`` naming ``name``."""
    if not (_is_number(value) and _finite(value) and int(value) == value and value >= minimum):
        what = "a positive integer" if minimum == 1 else f"an integer >= {minimum}"
        raise error(f"{name} must be {what}, got {value!r}"[:200])
    return int(value)


def float32_scale(what: str, value: float, unit: str, hint: str,
                  error: Type[Exception] = ValueError) -> None:
    """``error`` unless |value| lies within FLOAT32_SCALE, where the emitted float32 C computes
    reliably; the message ends with ``hint``."""
    low, high = FLOAT32_SCALE
    if not low <= abs(value) <= high:
        raise error(f"{what} is {abs(value):.3g} {unit}; the float32 C needs it between "
                    f"{low:g} and {high:g} ({hint})")


def float32_overflow(value, where: str) -> str:
    """The path of the first number in ``value`` (nested dicts and lists, as JSON gives them)
    beyond FLOAT32_MAX, where the C's float tables would hold infinity; '' if none."""
    if isinstance(value, dict):
        items = ((f"{where}.{k}", v) for k, v in value.items())
    elif isinstance(value, list):
        items = ((f"{where}[{k}]", v) for k, v in enumerate(value))
    else:
        return where if finite_number(value) and abs(value) > FLOAT32_MAX else ""
    for path, item in items:
        found = float32_overflow(item, path)
        if found:
            return found
    return ""


# ----------------------------------------------------------------------------- JSON fields


def json_number(d: dict, key: str, where: str, positive: bool = False) -> float:
    """``d[key]``, a finite JSON number (> 0 with ``positive``), else ``ModelError``."""
    if key not in d:
        raise ModelError(f"{where}: missing field {key!r}")
    value = d[key]
    if not _is_number(value):
        raise ModelError(f"{where}.{key} must be a number, got {type(value).__name__}")
    if not _finite(value):
        raise ModelError(f"{where}.{key} must be finite, got {value}"[:200])
    if positive and value <= 0:
        raise ModelError(f"{where}.{key} must be > 0, got {value}")
    return float(value)


def json_vector(d: dict, key: str, where: str, positive: bool = False) -> np.ndarray:
    """``d[key]``, a list of 1 to MAX_HIDDEN finite JSON numbers, else ``ModelError``."""
    if key not in d:
        raise ModelError(f"{where}: missing field {key!r}")
    value = d[key]
    if not isinstance(value, list) or not 1 <= len(value) <= MAX_HIDDEN:
        raise ModelError(f"{where}.{key} must be a list of 1 to {MAX_HIDDEN} numbers")
    for i, item in enumerate(value):
        if not finite_number(item):
            raise ModelError(f"{where}.{key}[{i}] must be a finite number, got {item!r}"[:200])
        if positive and item <= 0:
            raise ModelError(f"{where}.{key} must all be > 0, got {item}")
    return np.asarray(value, dtype=float)


def json_equal_lengths(where: str, vectors: dict) -> None:
    """``ModelError`` unless the named vectors have one length."""
    if len({v.size for v in vectors.values()}) != 1:
        raise ModelError(f"{where}: {', '.join(vectors)} have lengths "
                         f"{', '.join(str(v.size) for v in vectors.values())}; they must be equal")
