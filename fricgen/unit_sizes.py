"""The units fricgen reads by name, with their sizes: one table for the header units a file
writes (``data.header_units``) and for the units the hints name where a value looks like one of
them (``_validate``, the cogging map's warnings)."""
from __future__ import annotations

import math
from typing import Dict, Tuple

_DEG = math.pi / 180.0
_TURN = 2.0 * math.pi
#: Each unit (written in lower case, without spaces, dots or the multiplication sign) by the
#: kind of quantity it measures, its factor to SI (rad for angles) and whether it is rotary.
UNITS: Dict[str, Tuple[str, float, bool]] = {
    "s": ("time", 1.0, False), "sec": ("time", 1.0, False), "ms": ("time", 1e-3, False),
    "us": ("time", 1e-6, False), "min": ("time", 60.0, False),
    "m": ("position", 1.0, False), "cm": ("position", 1e-2, False), "mm": ("position", 1e-3, False),
    "um": ("position", 1e-6, False), "rad": ("position", 1.0, True), "mrad": ("position", 1e-3, True),
    "deg": ("position", _DEG, True), "rev": ("position", _TURN, True), "turn": ("position", _TURN, True),
    "turns": ("position", _TURN, True),
    "m/s": ("velocity", 1.0, False), "mm/s": ("velocity", 1e-3, False), "um/s": ("velocity", 1e-6, False),
    "m/min": ("velocity", 1 / 60, False), "mm/min": ("velocity", 1e-3 / 60, False),
    "rad/s": ("velocity", 1.0, True), "mrad/s": ("velocity", 1e-3, True), "deg/s": ("velocity", _DEG, True),
    "rpm": ("velocity", _TURN / 60, True), "1/min": ("velocity", _TURN / 60, True),
    "u/min": ("velocity", _TURN / 60, True), "rev/min": ("velocity", _TURN / 60, True),
    "r/min": ("velocity", _TURN / 60, True), "min^-1": ("velocity", _TURN / 60, True),
    "min-1": ("velocity", _TURN / 60, True), "upm": ("velocity", _TURN / 60, True),
    "krpm": ("velocity", 1e3 * _TURN / 60, True), "in/s": ("velocity", 0.0254, False),
    "inch/s": ("velocity", 0.0254, False), "in": ("position", 0.0254, False),
    "inch": ("position", 0.0254, False), "lbf": ("force", 4.4482216, False),
    "unm": ("force", 1e-6, True), "ozin": ("force", 7.0615518e-3, True),
    "lbfin": ("force", 0.11298483, True),
    "rps": ("velocity", _TURN, True), "rev/s": ("velocity", _TURN, True), "turn/s": ("velocity", _TURN, True),
    "n": ("force", 1.0, False), "kn": ("force", 1e3, False), "mn": ("force", 1e-3, False),
    "nm": ("force", 1.0, True), "mnm": ("force", 1e-3, True), "ncm": ("force", 1e-2, True),
    "nmm": ("force", 1e-3, True), "knm": ("force", 1e3, True),
    "a": ("current", 1.0, False), "ma": ("current", 1e-3, False),
    "degc": ("temperature", 1.0, False), "c": ("temperature", 1.0, False),
    "m/s^2": ("acceleration", 1.0, False), "m/s2": ("acceleration", 1.0, False),
    "mm/s^2": ("acceleration", 1e-3, False), "mm/s2": ("acceleration", 1e-3, False),
    "rad/s^2": ("acceleration", 1.0, True), "rad/s2": ("acceleration", 1.0, True),
    "deg/s^2": ("acceleration", _DEG, True), "deg/s2": ("acceleration", _DEG, True),
}


def size(unit: str) -> float:
    """The factor to SI of a unit of ``UNITS`` (rad for angles)."""
    return UNITS[unit][1]
