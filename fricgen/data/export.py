"""Vendor exports: a preamble to skip, vendor column names, other units, two instruments' files.

An ``ExportLayout`` says how to read one file: the lines before its header, and which of its
columns hold fricgen's quantities (``t`` s, ``x`` m, ``v`` m/s, ``f`` or ``force`` N, ``i`` A).
``read_export`` reads the file with the one CSV reader (``table.read_table_csv``), or a MATLAB
file's vectors as columns (``matfile``), names the columns, and multiplies each by its scale
factor (a number, or a MATLAB file's scalar variable); ``merge_on_time`` joins a second
instrument's file whose clock runs ``shift`` seconds behind, on the slower of the two clocks.
"""
from __future__ import annotations

import difflib
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, Iterator, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from .._io import plain_float
from ..errors import DataError, UsageError
from .header_units import is_rotary_unit
from .matfile import MatFile, is_matfile, read_matfile
from .motionlog import check_finite
from .table import DETECT, SLOW_SIGNALS, header_cells, read_table_csv

#: The quantities a column may be mapped to, with their SI units.
QUANTITIES = {"t": "s", "x": "m", "v": "m/s", "a": "m/s^2", "f": "N", "force": "N", "i": "A",
              "load": "N", "temperature": "degC"}

#: Column names of robot and drive logs, read as fricgen's quantities where the file has no
#: column of fricgen's own name for it and ``--columns`` maps none: a joint's position q,
#: velocity dq (qd), acceleration ddq (qdd), torque tau (effort, torque), motor current
#: (current, a drive's iq), the
#: plain English names, and a sweep's standard deviation per point (std, sd, stdev, sigma) and
#: count. The joint's names name a rotary axis (``names_rotary_axis``).
ALIASES = {"q": "x", "dq": "v", "qd": "v", "tau": "force", "effort": "force", "torque": "force",
           "current": "i", "iq": "i", "temp": "temperature", "time": "t", "position": "x",
           "pos": "x", "angle": "x", "velocity": "v", "vel": "v", "speed": "v", "trq": "force",
           "std": "f_std", "sd": "f_std", "stdev": "f_std", "sigma": "f_std", "f_sd": "f_std",
           "f_std": "f_std",
           "count": "n", "ddq": "a", "qdd": "a", "acc": "a", "accel": "a", "acceleration": "a"}
#: Every plain name read as a quantity: the quantities' own and the aliases.
KNOWN_NAMES = {**{q: q for q in QUANTITIES}, **ALIASES}
#: The aliases that name a joint: a file that uses them speaks rad, rad/s and Nm.
ROTARY_NAMES = ("q", "dq", "qd", "ddq", "qdd", "tau", "effort", "torque", "angle", "trq")

#: Two files whose time spans differ by this factor or more are not timed in one unit.
SPAN_RATIO = 100.0

#: A scale factor: a number, or the name of a MATLAB file's scalar variable (``read_export``).
Factor = Union[float, str]


def assignments(items: Sequence[str]) -> Iterator[Tuple[str, str, str, str]]:
    """Each NAME=VALUE of an option's values ``["a=b,c=d", "e=f"]``, as (name in lower case,
    "=" or "" where it lacks one, value, the part as written), names and values stripped."""
    for item in items:
        for part in item.split(","):
            name, sep, value = part.partition("=")
            yield name.strip().lower(), sep, value.strip(), part


def parse_assignments(items: Sequence[str], option: str) -> Dict[str, str]:
    """``["a=b,c=d", "e=f"]`` as {a: b, c: d, e: f}: the value of an option given once or more,
    each a comma-separated list of NAME=VALUE, NAME a quantity or one of its ``ALIASES``
    (``UsageError`` naming ``option``)."""
    out: Dict[str, str] = {}
    for name, sep, value, part in assignments(items):
        name = name if name in QUANTITIES else ALIASES.get(name, name)    # tau=... as force=...
        if not sep or not name or not value:
            raise UsageError(f"{option}: expected NAME=VALUE, got {part.strip()[:60]!r}")
        if name not in QUANTITIES:
            raise UsageError(f"{option}: {name[:40]!r} is not one of {', '.join(QUANTITIES)}")
        if name in out:
            raise UsageError(f"{option}: {name} is given twice")
        out[name] = value
    return out


def parse_scales(items: Sequence[str], option: str = "--scale") -> Dict[str, Factor]:
    """The factors of ``--scale v=0.000333333,t=1e-3``: finite numbers other than 0, or (text
    that is no number) the name of a scalar variable of a MATLAB file, ``force=gtau``, which
    ``read_export`` looks up in the file."""
    scales: Dict[str, Factor] = {}
    for name, text in parse_assignments(items, option).items():
        try:
            factor = plain_float(text)
        except ValueError:
            scales[name] = text
            continue
        _check_factor(factor, f"{option}: the factor of {name}", text)
        scales[name] = factor
    return scales


def _check_factor(factor: float, what: str, text: str) -> None:
    if not (math.isfinite(factor) and factor != 0):
        raise UsageError(f"{what} must be finite and not 0, got {text[:40]}")


def _factor(name: str, factor: Factor, path, mat: Optional[MatFile], option: str = "--scale") -> float:
    """The number ``factor`` is: itself, or the value of the scalar variable of ``mat`` it names
    (``UsageError`` for a CSV file, or a name that is no scalar of ``mat``, listing them)."""
    if not isinstance(factor, str):
        return factor
    if mat is None:
        raise UsageError(f"{option}: {name}={factor[:40]!r} is not a number")
    key = factor.lower()
    if key not in mat.scalars:
        what = f" ({factor} is {mat.others[key]})" if key in mat.others else ""
        raise UsageError(f"{option}: {name}={factor[:40]!r} is neither a number nor a scalar variable "
                         f"of {path}{what} (its scalars: {', '.join(mat.scalars)[:80] or 'none'})")
    value = mat.scalars[key]
    _check_factor(value, f"{option}: {name}={factor}, the variable of {path},", f"{value:g}")
    return value


#: A sweep's force is read as f (``read_export``): a scale of either is one of both.
SWEEP_NAME = {"force": "f", "f": "force"}


def scaled_column(name: str, columns: Mapping[str, np.ndarray]) -> str:
    """The column a scale of ``name`` applies to: ``name``, else its twin of ``SWEEP_NAME``."""
    return name if name in columns else SWEEP_NAME.get(name, name)


def check_scaled(scales: Mapping[str, Factor], files: Mapping[str, Dict[str, np.ndarray]],
                 option: str = "--scale") -> None:
    """``UsageError`` naming a scaled quantity that none of ``files`` (columns by file name)
    has, and the columns each has."""
    for name in scales:
        if not any(scaled_column(name, columns) in columns for columns in files.values()):
            listed = [(path, ", ".join(columns)[:80]) for path, columns in files.items()]
            where = (f"is not a column of {listed[0][0]} (its columns: {listed[0][1]})"
                     if len(listed) == 1 else "is a column of neither " +
                     " nor ".join(f"{path} ({cols})" for path, cols in listed))
            raise UsageError(f"{option}: {name} {where}")


@dataclass(frozen=True)
class ExportLayout:
    """How to read one exported file: ``skip`` preamble lines (0: found, ``table.header_skip``),
    then a header whose columns ``columns`` maps from fricgen's names to the file's (unmapped
    columns keep their own name); ``delimiter`` (a value of ``table.DELIMITERS``, or
    ``table.DETECT``) and ``decimal_comma`` (None to detect) as ``table.read_table_csv`` takes
    them."""

    skip: int = 0
    columns: Mapping[str, str] = field(default_factory=dict)
    delimiter: Optional[str] = DETECT
    decimal_comma: Optional[bool] = None

    def __post_init__(self):
        vendor = [name.strip().lower() for name in self.columns.values()]
        repeated = sorted({n for n in vendor if vendor.count(n) > 1})
        if repeated:
            raise UsageError(f"column {repeated[0]!r} is mapped to more than one quantity")


def _header_line(path, layout: ExportLayout, lines: int = 50) -> int:
    """The line (from 1) among the first ``lines`` whose cells hold every column ``layout``
    maps, or 0: where the header of a file with a longer preamble is."""
    wanted = {v.strip().lower() for v in layout.columns.values()}
    for k in range(lines):
        cells = header_cells(path, k, layout.delimiter)
        if not cells:
            return 0
        if wanted <= {c.strip().lower() for c in cells}:
            return k + 1
    return 0


def _check_mapped(path, layout: ExportLayout, option: str) -> None:
    """``UsageError`` naming a column ``layout`` maps that the CSV's header lacks, with the
    header's closest name (a typo is no matter of units)."""
    cells = header_cells(path, layout.skip, layout.delimiter)
    if not cells:
        return                          # unreadable: the reader says why
    names = {c.strip().lower(): c for c in cells}
    for quantity, vendor in layout.columns.items():
        if vendor.strip().lower() not in names:
            close = difflib.get_close_matches(vendor.strip().lower(), list(names), n=1, cutoff=0.5)
            line = _header_line(path, layout)
            hint = (f"; did you mean {names[close[0]]!r}?" if close else
                    f"; its header looks to be line {line}: --skip {line - 1}" if line else "")
            raise UsageError(f"{option}: {quantity}={vendor[:40]!r}: {path} has no such column "
                             f"(header is {','.join(cells)[:80]}){hint}")


def read_export(path: Union[str, Path], layout: ExportLayout = ExportLayout(),
                scales: Mapping[str, Factor] = {}, drop_text: bool = False,
                option: str = "--columns") -> Dict[str, np.ndarray]:
    """The columns of ``path`` (a CSV, or a MATLAB file's vectors) by fricgen's names, scaled to
    SI by ``scales`` (factor per name; a name the file lacks is left for the caller:
    ``check_scaled``). ``drop_text``: a CSV's column holding text is left out, unless mapped or
    named as a quantity (``KNOWN_NAMES``): a drive's status column.
    ``option`` names the layout's columns in messages (a column the header lacks)."""
    rename = {vendor.strip().lower(): name for name, vendor in layout.columns.items()}
    mat = None
    if is_matfile(path):
        if layout.skip:
            raise UsageError(f"{path} is a MATLAB file: it has no preamble lines to skip")
        mat = read_matfile(path)
        raw = mat.columns(rename, [q for q in QUANTITIES if q not in layout.columns])
    else:
        _check_mapped(path, layout, option)
        sparse = [h for h, name in rename.items() if name == "temperature"] or list(SLOW_SIGNALS)
        raw = read_table_csv(path, list(rename), keep_extra=True, skip=layout.skip, drop_text=drop_text,
                             delimiter=layout.delimiter, decimal_comma=layout.decimal_comma,
                             sparse=sparse, numeric={*KNOWN_NAMES, *KNOWN_NAMES.values()})
    columns = {}
    for header, values in raw.items():
        name = rename.get(header, header)
        if name in columns:
            raise DataError(f"{path}: column {name!r} appears twice once the columns are named "
                            f"({header!r} is mapped to it)")
        columns[name] = values
    columns = by_quantity(columns, mapped=layout.columns)
    for name, factor in scales.items():
        column = scaled_column(name, columns)
        if column in columns:
            columns[column] = columns[column] * _factor(name, factor, path, mat)
    return columns


def by_quantity(columns: Mapping[str, np.ndarray], mapped=()) -> Dict[str, np.ndarray]:
    """``columns`` (named in lower case) with the ``ALIASES`` read as fricgen's quantities,
    where no column of the quantity's own name is there and none is ``mapped`` to it (then
    the alias is dropped; two columns that read as one quantity differ nowhere, else
    ``DataError``: ``_check_one_reading``); a sweep's force (a velocity and a force, no time,
    position or current) is its ``f``."""
    columns = dict(columns)
    for name in dict.fromkeys(ALIASES.values()):
        if name not in mapped:
            _check_one_reading(columns, name)
    for alias, name in ALIASES.items():
        if alias == name or alias not in columns:
            continue
        values = columns.pop(alias)     # else equal to the quantity's column, or one not mapped
        if name not in columns and name not in mapped:
            columns[name] = values
    if "f" not in columns and "v" in columns and "force" in columns and not {"t", "x", "i"} & set(columns):
        columns["f"] = columns.pop("force")
    return columns


def _check_one_reading(columns: Mapping[str, np.ndarray], name: str) -> None:
    """``DataError`` where two columns read as the quantity ``name`` (its own name or its
    ``ALIASES``: dq and qd, tau and torque) and hold different values: which one the file
    means is not fricgen's guess (a motor's velocity beside the joint's, a command beside a
    measurement)."""
    cells = [c for c in (name, *(a for a, q in ALIASES.items() if q == name and a != name))
             if c in columns]
    for other in cells[1:]:
        if not np.array_equal(np.asarray(columns[cells[0]], dtype=float),
                              np.asarray(columns[other], dtype=float), equal_nan=True):
            raise DataError(f"columns {cells[0]!r} and {other!r} both read as {name!r} and differ: "
                            f"name the one to use (--columns {name}=COLUMN) or drop the other")


#: Words in a column's name that ``suggested_columns`` reads beside the ``ALIASES``.
SUGGESTED_WORDS = {"t": "t", "time": "t", "timestamp": "t", "stamp": "t", "friction": "force"}


def suggested_columns(cells: Sequence[str]) -> str:
    """A --columns mapping of a header whose names hold the common names as words
    ('actual_velocity', 'Joint Torque'): "; --columns t=...,v=...,force=..." where the words
    name a log's columns (t, v or x, force or i) or a sweep's (v and the force, as f); else ""."""
    found: Dict[str, str] = {}
    for cell in cells:
        for word in filter(None, re.split(r"[^a-z0-9]+", cell.strip().lower())):
            name = SUGGESTED_WORDS.get(word, ALIASES.get(word) if len(word) > 1 else None)
            if name in ("t", "x", "v", "force", "i") and name not in found:
                found[name] = cell.strip()
                break
    log = "t" in found and ({"v", "x"} & set(found)) and ({"force", "i"} & set(found))
    if not log and not {"v", "force"} <= set(found):
        return ""
    if not log:
        found = {"v": found["v"], "f": found["force"]}
    mapped = ",".join(f"{name}={cell}" for name, cell in found.items())
    return f"; its names read as {'a log' if log else 'a sweep'}'s? --columns '{mapped}'"


def names_rotary_axis(cells) -> bool:
    """Whether a header's names are a robot joint's (q, dq, qd, tau, effort, torque:
    ``ROTARY_NAMES``) or write a rotary unit ("torque [Nm]", "rpm": ``is_rotary_unit``)."""
    return any(c.strip().lower() in ROTARY_NAMES or is_rotary_unit(c, bare=True) for c in cells)


def _increasing_time(columns: Dict[str, np.ndarray], path, option: str) -> np.ndarray:
    t = columns.get("t")
    if t is None:
        raise DataError(f"{path}: no time column 't' to merge on (map one: {option} t=NAME)")
    if t.size < 2 or not np.all(np.diff(t) > 0):         # finite: merge_on_time checked it
        raise DataError(f"{path}: the time column must be finite and increase to merge on it")
    return t


def merge_on_time(first: Dict[str, np.ndarray], second: Dict[str, np.ndarray], shift: float = 0.0,
                  names: Tuple[str, str] = ("first file", "second file"),
                  min_rows: int = 2) -> Dict[str, np.ndarray]:
    """The columns of both files on the slower clock (the larger median step), over the time
    both cover: the other file's columns linearly interpolated there. The second file's sample
    at t2 happened at t2 + ``shift`` on the first file's clock. A column other than t in both
    files, or a common time of fewer than ``min_rows`` rows, is refused naming both files."""
    for columns, name in zip((first, second), names):       # rows counted in each file
        for k, values in columns.items():
            check_finite(k, values, str(name))
    t1 = _increasing_time(first, names[0], "--columns")
    t2 = _increasing_time(second, names[1], "--merge-columns") + shift
    both = sorted((set(first) & set(second)) - {"t"})
    if both:
        raise DataError(f"column {both[0]!r} is in {names[0]} and in {names[1]}; keep one of them")
    slow_first = np.median(np.diff(t1)) >= np.median(np.diff(t2))
    (ts, slow), (tf, fast) = ((t1, first), (t2, second)) if slow_first else ((t2, second), (t1, first))
    inside = (ts >= max(t1[0], t2[0])) & (ts <= min(t1[-1], t2[-1]))
    shifted = f" (after the shift of {shift:g} s)" if shift else ""
    spans = (t1[-1] - t1[0]) / (t2[-1] - t2[0])
    if not 1 / SPAN_RATIO < spans < SPAN_RATIO:
        shifted += (f"; {names[0]} spans {spans:.3g} times the time of {names[1]}: is one timed in "
                    "ms? (--scale applies to both files; --merge-scale t=FACTOR to the --merge "
                    "file alone)")
    if inside.sum() < 2:
        raise DataError(f"{names[0]} and {names[1]} share no time span{shifted}")
    if inside.sum() < min_rows:
        common = ts[inside]
        raise DataError(f"{names[0]} and {names[1]} share {common[-1] - common[0]:.3g} s "
                        f"({int(inside.sum())} rows on the slower clock), need {min_rows} rows{shifted}")
    merged = {"t": ts[inside]}
    merged.update({k: a[inside] for k, a in slow.items() if k != "t"})
    merged.update({k: np.interp(merged["t"], tf, a) for k, a in fast.items() if k != "t"})
    return merged
