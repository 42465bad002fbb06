"""``fricgen emit MODEL -o DIR``: NAME.h, NAME.c and the C runtime they need, in one folder,
with the folder's build files (CMake, Zephyr, PlatformIO: fricgen.codegen.package)."""
from __future__ import annotations

from typing import Optional

from .._io import check_destination, check_folder, write_files
from .._validate import PHYSICAL
from ..c_names import check_model_name
from ..codegen import (ACTIVATION_IMPLS, DTYPES, check_name_in_folder, check_overwrite,
                       package_files, render)
from ..codegen.cogging_table import CoggingTable
from ..codegen.package import remove_stale
from ..codegen.fixedpoint import DTYPE_PARAMS, covered_speed, input_range
from ..control.c_adapted import render_adapt
from ..effects import offset_left_out
from ..errors import UsageError
from ..model import FrictionModel
from .inputs import load_model
from .common import FORCE_C, add_output, check_targets, number, say


#: A sample time of NAME_step this many times faster or slower than the training log's is named.
SAMPLE_TIME_RATIO = 10.0


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("model", help="model.json")
    add_output(p, "output folder", force_also=FORCE_C)
    p.add_argument("--name", help="C name prefix, not beginning with fric_ (default: the model's name)")
    p.add_argument("--activation-impl", choices=ACTIVATION_IMPLS, default="libm",
                   help="sigmoid through libm's expf, or the fast one without libm (error <= 8.7e-7)")
    p.add_argument("--dtype", choices=DTYPES, default="float",
                   help="float, or integer-only fixed point for MCUs without FPU")
    p.add_argument("--v-max", type=number(0, PHYSICAL["speed"][1], low_open=True, unit="m/s"),
                   help="q15/q31: the fastest speed the fixed-point input must hold, m/s (default: "
                   "the fastest speed of the model's training data, from its axis record)")
    p.add_argument("--sample-time", type=number(0, 1.0, low_open=True, unit="s"),
                   help="the sample time of NAME_step for a model with pre-sliding, s (default: "
                   "its training log's)")
    p.add_argument("--with-controller", action="store_true",
                   help="also write the adaptive backstepping controller fric_ctrl.{h,c} (float)")
    p.add_argument("--adapt", action="store_true",
                   help="also write online adaptation of the model's output parameters: "
                   "NAME_adapt.{h,c}, fric_adapt.{h,c} and the controller (float, ELM "
                   "or grey-box models)")
    p.add_argument("--cogging-blob", metavar="FILE",
                   help="also write the model's cogging map as the blob NAME_cogging_map_restore "
                   "reads: the bytes of one unit's map for its non-volatile memory")
    p.set_defaults(run=run)


def input_range_note(model: FrictionModel, dtype: str, v_max) -> str:
    """One line on the speeds the fixed-point input covers, and where that range came from."""
    v_range = input_range(model, dtype, v_max)
    cover = covered_speed(model, v_max)
    speed = model.units.speed
    if cover is None:
        return (f"fricgen: warning: the {dtype} C takes |v| < {v_range:g} {speed} (2 v_sat): faster "
                "speeds clamp there; the model records no speed range (--v-max sets one)")
    source = "--v-max" if v_max is not None else "the model's axis: its training speeds"
    return f"fricgen: the {dtype} C takes |v| < {v_range:g} {speed}, covering {cover:.4g} {speed} ({source})"


def band_note(model: FrictionModel, name: str, dtype: str, v_max) -> str:
    """One line when the model's velocity band is under the fixed-point input's LSB: the C's
    band is then one LSB (``fixedpoint.BandSpec``), wider than the model's."""
    band = model.velocity_band
    lsb = input_range(model, dtype, v_max) / 2.0 ** (DTYPE_PARAMS[dtype]["bits"] - 1)
    if band is None or band >= lsb:
        return ""
    speed = model.units.speed
    return (f"fricgen: note: the velocity band {band:.4g} {speed} is under the {dtype} input's LSB "
            f"({lsb:.4g} {speed}): {name}_compensation_{dtype} is 0 up to one LSB, {lsb:.4g} {speed}, "
            "and ramps to the force at two")


def offset_note(model, name: str, dtype: str = "float") -> str:
    """One line when the model's axis records an offset that its curves leave out (a symmetric
    model's constant force, or a load) and no constant_load effect carries it: NAME_force is
    the friction alone, NAME_force_with_offset adds it (fixed point: the caller adds it)."""
    offset = offset_left_out(model)
    unit = model.units.force
    if offset is None:
        return ""
    head = f"fricgen: note: the axis's offset o = {offset:.4g} {unit} (training.axis.offset) is not in "
    if dtype != "float":
        return head + (f"{name}_force_{dtype}, the friction alone; add o * 2^{name.upper()}_F_FRAC_BITS "
                       "to its result where the drive needs it")
    return head + f"{name}_force, the friction alone; {name}_force_with_offset adds it"


def cogging_blob(args, model: FrictionModel, table: Optional[CoggingTable]) -> dict:
    """``--cogging-blob``'s destination, checked, and the bytes of the model's map (``table``:
    its ``CoggingTable``, None without a map)."""
    if table is None:
        raise UsageError(f"--cogging-blob: {args.model} holds no cogging map (train --cogging "
                         "identifies one)")
    path = check_destination(args.cogging_blob, [args.model], args.force, option="--cogging-blob")
    return {path: table.blob(model.model_hash)}


def run(args) -> int:
    check_folder(args.output, (), args.force)
    model = load_model(args.model)
    if args.name is None:
        name = check_model_name(model.name, f"field 'name' of {args.model} (override it with --name)")
    else:
        name = check_model_name(args.name, "--name")
    if args.v_max is not None and args.dtype == "float":
        raise UsageError("--v-max sets the input range of --dtype q15 or q31; float takes any speed")
    if args.adapt and args.dtype != "float":
        raise UsageError(f"--adapt is float; it cannot be emitted with --dtype {args.dtype}")
    logged = model.training.get("log", {}).get("sample_time")
    if args.sample_time is not None and isinstance(logged, (int, float)) and logged > 0 \
            and not 1 / SAMPLE_TIME_RATIO <= args.sample_time / logged <= SAMPLE_TIME_RATIO:
        say(f"fricgen: warning: --sample-time {args.sample_time:g} s is {args.sample_time / logged:.3g} "
            f"times the training log's {logged:.3g} s: a sample time in ms, or the wrong model?")
    files = render(model, name, activation_impl=args.activation_impl, dtype=args.dtype,
                   with_controller=args.with_controller or args.adapt, v_max=args.v_max,
                   adapt=args.adapt, sample_time=args.sample_time)
    if args.adapt:
        files.update(render_adapt(model, name, args.activation_impl))
    check_name_in_folder(args.output, name)
    files.update(package_files(args.output, files, name))     # CMake, Zephyr, PlatformIO
    targets = check_targets(args, files, [args.model])
    check_overwrite(targets.values(), args.force)
    table = None if model.cogging_map is None else CoggingTable.of(model.cogging_map)
    blob = {} if args.cogging_blob is None else cogging_blob(args, model, table)
    write_files({**{targets[n]: text for n, text in files.items()}, **blob})
    removed = remove_stale(args.output, name, files)
    if removed:
        say(f"removed {', '.join(removed)}: written for the model emitted before under the name "
            f"{name}, and used by no model in the folder now")
    if args.dtype != "float":
        say(input_range_note(model, args.dtype, args.v_max))
    notes = [offset_note(model, name, args.dtype), table and table.shortfall(name, model.units.force),
             args.dtype != "float" and band_note(model, name, args.dtype, args.v_max)]
    for note in filter(None, notes):
        say(note)
    say(f"wrote {', '.join(sorted(files))} to {args.output} (model {model.model_hash})"
        + "".join(f"; the cogging map's blob to {path}" for path in blob))
    return 0
