"""What commands read: data files through the vendor-export options (``train``, ``diagnose``),
and model.json with a warning when it was edited after training."""
from __future__ import annotations

import re
from contextlib import contextmanager

import numpy as np

from ..data.export import (KNOWN_NAMES, SWEEP_NAME, ExportLayout, check_scaled, merge_on_time,
                           parse_assignments, parse_scales, read_export, scaled_column)
from ..data.header_units import header_units
from ..data.matfile import is_matfile
from ..data.inverse_dynamics import is_log
from ..data.table import DELIMITERS, DETECT, header_cells
from ..data.wrapping import unwrapped
from ..data.plausibility import check_columns, check_merge_shift
from ..errors import DataError, FricgenError, UsageError
from ..model import FrictionModel
from ..training.record import law_record_edits
from .common import number, say


def load_model(path, of_v_alone: str = ""):
    """``FrictionModel.load(path)``, and one warning line when the file was edited after training
    (its recorded model_hash no longer matches its content). ``of_v_alone``: the command, which
    runs the friction of v alone, refuses a model with inputs (load, temperature) in one line
    rather than drop them."""
    model = FrictionModel.load(path)
    if of_v_alone and model.inputs is not None:
        raise UsageError(f"{of_v_alone} runs the friction of v alone; {path} depends on the "
                         f"{' and the '.join(model.inputs.names)} (eval and emit take them: "
                         "NAME_force_lt)")
    warning = model.hash_warning(path)
    if warning:
        say(warning)
    edited = [] if warning else law_record_edits(model)      # the force fields' edit said first
    if edited:
        say(f"fricgen: warning: {path}: {' and '.join(edited)}'s law (coulomb, viscous, static, "
            "v_s) no longer gives the model's force (edited by hand?): eval and emit run the "
            "model's aim, scaling and viscous, which the record only describes")
    return model


# ----------------------------------------------------------------------------- vendor exports


def add_export_options(p) -> None:
    """The vendor-export options every command that reads data takes (``read_data``): a preamble,
    the file's column names, units, a second instrument's file merged on time, and
    ``--accept-unusual`` for data outside the physical bounds of a real axis."""
    export = p.add_argument_group("vendor exports")
    export.add_argument("--skip", type=number(0, 1e6, integer=True), default=0,
                        help="preamble lines before the header (default 0; not for a .mat file)")
    export.add_argument("--delimiter", choices=list(DELIMITERS),
                        help="the cells' delimiter (default: read off the header line)")
    export.add_argument("--decimal-comma", action="store_true", default=None,
                        help="numbers written with a decimal comma, 0,25 (default: detected "
                        "where the cells are not ','-separated)")
    export.add_argument("--columns", action="append", default=[], metavar="NAME=COLUMN,...",
                        help="the file's column (a .mat file's variable) of each quantity (t, x, v, "
                        "f, force, i, load, temperature), e.g. 't=Time [s],v=Speed [rpm]'")
    export.add_argument("--scale", action="append", default=[], metavar="NAME=FACTOR,...",
                        help="multiply a quantity to SI units, e.g. v=0.000333333 (rpm to m/s), "
                        "or by a scalar variable of a .mat file, e.g. force=gtau; applies to the "
                        "--merge file too, for the quantities --merge-scale does not name")
    export.add_argument("--sample-rate", type=number(0, 1e9, low_open=True, unit="Hz"),
                        help="the rate, Hz, a file without a time column was logged at: its rows "
                        "are then a motion log's, t = row / rate")
    export.add_argument("--merge", metavar="FILE", help="a second instrument's CSV or .mat, merged on "
                        "time onto the slower of the two clocks (linear interpolation)")
    export.add_argument("--merge-columns", action="append", default=[], metavar="NAME=COLUMN,...",
                        help="--columns of the --merge file")
    export.add_argument("--merge-skip", type=number(0, 1e6, integer=True), default=0,
                        help="preamble lines of the --merge file")
    export.add_argument("--merge-scale", action="append", default=[], metavar="NAME=FACTOR,...",
                        help="--scale of the --merge file alone, e.g. t=0.001 when only it is "
                        "timed in ms (overrides --scale there)")
    export.add_argument("--merge-shift", type=number(-1e6, 1e6, unit="s"), default=0.0,
                        help="seconds to add to the --merge file's time to reach the first file's clock")
    export.add_argument("--accept-unusual", action="store_true",
                        help="use data (and write a model) beyond the physical bounds of a real axis "
                        "or that look swapped, with a warning instead of a refusal (--force means "
                        "overwrite)")


def source_name(path, merge=None) -> str:
    """The input as messages name it: the file, or both files of a merge ("a.csv + b.csv")."""
    return " + ".join(str(f) for f in (path, merge) if f)


def read_data(args, path, min_rows=None, drop_text: bool = False):
    """The columns of ``path`` by fricgen's names, read with the vendor-export options of
    ``args`` (``add_export_options``): the preamble skipped, vendor names mapped, units scaled,
    and a second instrument's file merged on time (``min_rows(columns)``: the fewest common rows
    the merged data need); then checked for plausibility (``data.plausibility``)."""
    scales = parse_scales(args.scale)
    dialect = dict(delimiter=DELIMITERS[args.delimiter] if args.delimiter else DETECT,
                   decimal_comma=args.decimal_comma)
    mapped, units = _header_units(args, path, args.skip, parse_assignments(args.columns, "--columns"),
                                  scales, dialect["delimiter"])
    columns = _in_si(read_export(path, ExportLayout(args.skip, mapped, **dialect), scales, drop_text), units)
    rate = getattr(args, "sample_rate", None)
    if rate is not None:
        if args.merge is not None:
            raise UsageError("--sample-rate gives a file without a time column its time; --merge "
                             "joins files on their own time columns")
        if "t" in columns:
            raise UsageError(f"--sample-rate: {path} has a time column t already")
        columns = {"t": np.arange(len(next(iter(columns.values())))) / rate, **columns}
    if args.merge is None:
        if args.merge_columns or args.merge_skip or args.merge_shift or args.merge_scale:
            raise UsageError("--merge-columns, --merge-skip, --merge-scale and --merge-shift need "
                             "--merge FILE")
        check_scaled(scales, {path: columns})
    else:
        merge_scales = parse_scales(args.merge_scale, "--merge-scale")
        both = {**scales, **merge_scales}
        merge_mapped, merge_units = _header_units(args, args.merge, args.merge_skip, parse_assignments(
            args.merge_columns, "--merge-columns"), both, dialect["delimiter"])
        second = _in_si(read_export(args.merge, ExportLayout(args.merge_skip, merge_mapped, **dialect),
                                    both, drop_text, "--merge-columns"), merge_units)
        units = {**units, **merge_units}
        check_scaled({k: f for k, f in scales.items() if k not in merge_scales},
                     {path: columns, args.merge: second})
        check_scaled(merge_scales, {args.merge: second}, "--merge-scale")
        names = (path, args.merge)
        least = min_rows({**columns, **second}) if min_rows else 2
        merged = merge_on_time(columns, second, args.merge_shift, names, least)
        check_merge_shift(columns, second, args.merge_shift, names, args.accept_unusual, _warn(args))
        columns = merged
    columns = unwrapped(columns, _warn(args))
    check_timed(columns, source_name(path, args.merge))
    given = {**{q: f"the header's {u.unit}" for q, u in units.items()},
             **{k: f"--scale {k}={f:g}" for k, f in scales.items() if not isinstance(f, str)}}
    check_columns(columns, source_name(path, args.merge), is_log(columns), args.accept_unusual,
                  _warn(args), given)
    return columns


def _in_si(columns, units):
    """The columns with the header's ``units`` applied (a sweep's force is read as f)."""
    for quantity, unit in units.items():
        name = scaled_column(quantity, columns)
        if name in columns:
            columns[name] = columns[name] * unit.factor
    return columns


def _header_units(args, path, skip, mapped, scales, delimiter):
    """The columns to read of ``path`` (its mapping and the cells whose names write a unit,
    ``data.header_units``) and the units to scale by: those --scale leaves (a --scale that
    differs from its column's unit is warned about); one line for each unit applied."""
    if is_matfile(path):
        return mapped, {}
    cells = header_cells(path, skip, delimiter)
    warn = _warn(args)

    def users(quantity):                        # the user's --scale of a quantity, or None
        return scales.get(quantity, scales.get(SWEEP_NAME.get(quantity, quantity)))

    scaled = [q for q in set(KNOWN_NAMES.values()) if users(q) is not None]
    extra, units = header_units(cells, mapped, KNOWN_NAMES, scaled)
    applied = {}
    for quantity, unit in units.items():
        factor = users(quantity)
        if isinstance(factor, float) and unit.factor != 1 and abs(factor / unit.factor - 1) > 0.01:
            warn(f"fricgen: warning: --scale {quantity}={factor:g} is not the factor of the header's "
                 f"{unit.unit} ({unit.factor:.6g}, {unit.cell!r}): --scale is used")
        elif factor is None and unit.factor != 1:
            warn(f"fricgen: {quantity} read in {unit.unit} ({unit.cell!r}): scaled by "
                 f"{unit.factor:.6g} to SI")
            applied[quantity] = unit
    return {**extra, **mapped}, applied


#: Column names that look like a position: a log's, never a sweep's (``check_timed``).
POSITION_NAME = re.compile(r"pos|angle|encoder")


def check_timed(columns, source: str) -> None:
    """``DataError`` for a file read as a sweep (v and f, no time column) that holds a position
    (x, or a column named like one): a motion log, whose rows read as a sweep's points would
    take its accelerations for friction."""
    if "t" in columns or not {"v", "f"} <= set(columns):
        return
    position = next((c for c in columns if c == "x" or POSITION_NAME.search(c)), None)
    if position is not None:
        raise DataError(f"{source}: column {position!r} holds a position, and the file has no time "
                        "column: a motion log read as a sweep would take its accelerations for "
                        "friction; --sample-rate HZ gives a log logged at a fixed rate its time "
                        "(--columns t=NAME names its time column)")


def _warn(args):
    """Where the data checks put a warning line: kept for ``data_warnings`` when it runs, else
    said at once."""
    held = getattr(args, "data_warnings", None)
    return say if held is None else held.append


@contextmanager
def data_warnings(args):
    """Hold the warning lines of the data checks (``read_data``) while a command runs: said by
    ``say_data_warnings`` before its results, or, when the command then fails, added to its one
    error line (a speed in m/min warned about explains a fit that then fails)."""
    args.data_warnings = []
    try:
        yield
    except FricgenError as exc:
        notes = [w.partition(": warning: ")[2] or w for w in args.data_warnings]
        args.data_warnings = []
        if notes:
            raise type(exc)(f"{exc} (and: {'; '.join(notes)})") from None
        raise
    finally:
        say_data_warnings(args)


def say_data_warnings(args) -> None:
    """Say the warning lines ``data_warnings`` holds, once."""
    for line in getattr(args, "data_warnings", None) or ():
        say(line)
    args.data_warnings = []
