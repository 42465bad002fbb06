"""Units written in a header's names, read: a drive's export names its columns "Speed [rpm]",
"Torque (mNm)", "Iq [mA]", and the values are in those units. A column so named is read as its
quantity (the name before the unit, as ``export.ALIASES`` reads plain names, or as --columns
maps it) and scaled to SI by its unit, unless the user's --scale names that quantity (it wins).

A unit of another kind than its quantity's (a velocity column in Nm: swapped columns), units
that mix a linear and a rotary axis, and a unit of no size the file gives (%, encoder
increments) or not known here are refused in one line; the last two are read as the user's
--scale says where it names the quantity.
"""
from __future__ import annotations

import re
from typing import Dict, Mapping, NamedTuple, Optional, Sequence, Tuple

from ..errors import DataError
from ..unit_sizes import UNITS

#: "Name [unit]" or "Name (unit)".
_NAMED_UNIT = re.compile(r"\s*(.*?)\s*[\[(]\s*([^\])]+?)\s*[\])]\s*")

#: Units whose size the file does not give: a share of a rating, encoder steps, raw numbers.
SIZELESS = ("%", "‰", "inc", "incr", "increments", "counts", "count", "cnt", "cts", "ticks",
            "digits", "lsb", "pu")
#: The kind of each quantity a column can be read as.
KIND = {"t": "time", "x": "position", "v": "velocity", "a": "acceleration", "f": "force", "force": "force",
        "f_std": "force",
        "load": "force", "i": "current", "temperature": "temperature"}


class HeaderUnit(NamedTuple):
    """A header cell's unit as read: the cell, the unit as written, its factor to SI."""
    cell: str
    unit: str
    factor: float


def named_unit(cell: str) -> Optional[Tuple[str, str]]:
    """The name and the unit of a cell written "Name [unit]" or "Name (unit)"; None otherwise."""
    found = _NAMED_UNIT.fullmatch(cell)
    return (found.group(1), found.group(2)) if found and found.group(1) else None


def row_unit(cell: str) -> Optional[str]:
    """The unit a cell of a units row writes ("rpm", "[rpm]", "(mNm)"), when fricgen knows it or
    knows it has no size; None otherwise."""
    unit = cell.strip()
    if len(unit) > 2 and unit[0] + unit[-1] in ("[]", "()"):
        unit = unit[1:-1].strip()
    return unit if unit and (_key(unit) in UNITS or _key(unit) in SIZELESS) else None


def _key(unit: str) -> str:
    """The unit as ``UNITS`` writes it: lower case, 'µ' as 'u', '°' as 'deg', no spaces, dots,
    hyphens or multiplication signs (N.m, N·m, N*m as nm; oz-in as ozin; min-1 kept; s² as s^2)."""
    key = unit.strip().lower().replace("µ", "u").replace("μ", "u").replace("°c", "degc")
    key = key.replace("²", "^2")
    return re.sub(r"[\s.·*-](?!1)", "", key.replace("°", "deg"))


def is_rotary_unit(cell: str, bare: bool = False) -> bool:
    """Whether a cell writes a rotary unit (rad, deg, rpm, Nm, ...) as "Name [unit]"; ``bare``:
    or as a word of its own ("rpm", "torque Nm")."""
    found = named_unit(cell)
    words = [found[1]] if found else cell.split() if bare else []
    return any(UNITS.get(_key(w), ("", 0.0, False))[2] for w in words)


def header_units(cells: Sequence[str], mapped: Mapping[str, str], known: Mapping[str, str],
                 scaled: Sequence[str] = ()) -> Tuple[Dict[str, str], Dict[str, HeaderUnit]]:
    """The quantities that the header's cells with units name, and their units.

    ``mapped``: --columns (quantity to cell); ``known``: the plain names read as a quantity
    (``export.ALIASES`` and the quantities' own). Returns the cells to map (quantity to cell,
    for the cells with a unit whose name is a known one and that --columns leaves unmapped) and
    each quantity's unit (``HeaderUnit``). ``DataError`` for a unit of another kind than its
    quantity, for units that mix a linear axis's and a rotary one's, and for a unit of no size
    or not known here, unless ``scaled`` (the quantities --scale names) holds its quantity."""
    by_cell = {c.strip().lower(): q for q, c in mapped.items()}
    plain = {known[c.strip().lower()] for c in cells if c.strip().lower() in known}
    to_map, units = {}, {}
    for cell in cells:
        found = named_unit(cell)
        if found is None:
            continue
        name, unit = found
        quantity = by_cell.get(cell.strip().lower())
        if quantity is None and name.lower() in known:
            quantity = known[name.lower()]
            if quantity in mapped or quantity in to_map or quantity in plain:
                continue                # a column is read as it already
            to_map[quantity] = cell
        if quantity not in KIND:
            continue
        key = _key(unit)
        if key not in UNITS and quantity in scaled:
            continue                    # the user's factor reads it
        if key in SIZELESS or key not in UNITS:
            what = "a unit of no size the file gives" if key in SIZELESS else "a unit fricgen does not know"
            raise DataError(f"column {cell.strip()!r} ({quantity}) is in {unit}, {what}: --scale "
                            f"{quantity}=FACTOR brings it to SI")
        kind, factor, _ = UNITS[key]
        if kind != KIND[quantity]:
            article = "an" if KIND[quantity][0] in "aeiou" else "a"
            raise DataError(f"column {cell.strip()!r} is read as {quantity}, {article} {KIND[quantity]}, "
                            f"but its unit {unit} is a {kind}'s: are the columns swapped? (--columns "
                            "maps them)")
        units[quantity] = HeaderUnit(cell.strip(), unit, factor)
    _check_one_axis(units, scaled)
    return to_map, units


def _check_one_axis(units: Mapping[str, HeaderUnit], scaled: Sequence[str]) -> None:
    """``DataError`` where the units of position, velocity and force that --scale leaves mix a
    linear axis's and a rotary one's (a table's speed in mm/s beside a motor's torque in Nm)."""
    rotary = {q: UNITS[_key(u.unit)][2] for q, u in units.items()
              if q not in scaled and KIND[q] in ("position", "velocity", "acceleration", "force")}
    if len(set(rotary.values())) > 1:
        linear = next(units[q] for q, r in rotary.items() if not r)
        turning = next(units[q] for q, r in rotary.items() if r)
        raise DataError(f"the header's units mix a linear axis's ({linear.cell!r}) and a rotary one's "
                        f"({turning.cell!r}): --scale one of them to the other's axis (through the "
                        "screw's lead or the gear)")
