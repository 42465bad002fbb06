"""``fricgen diagnose LOG --model M``: name the effects a friction model misses in a measured log."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .._io import check_folder, named_data
from ..codegen.render import check_overwrite
from ..data.motionlog import MIN_SAMPLES, log_from_columns
from ..data.table import header_cells
from ..diagnose.decision import p_text
from ..diagnose.diagnoser import MAX_EFFECTS, Diagnoser, candidates_with
from ..diagnose.report import format_value, refinement_note, render_files, service_hint, written_by_diagnose
from ..effects import ConstantLoad, FrictionalLag, model_effects, offset_left_out, range_notes, with_effects
from ..errors import UsageError
from ..model import FrictionModel
from ..diagnose.operating_point import missing_dependence, named_lines, without_load
from .inputs import (add_export_options, data_warnings, load_model, read_data, say_data_warnings,
                     source_name)
from .common import (add_json, add_model, add_output, check_targets,
                     number, out, say, write_folder)


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("log", help="measured log with columns t, x, v, i (uniformly sampled; force in "
                   "N in place of the current i, v from x where the log has no v): a CSV, or a "
                   "MATLAB .mat file with these variables (a vendor's export: see the options below)")
    add_model(p)
    p.add_argument("--mass", type=number(0, 1e6, low_open=True, unit="kg"),
                   help="nominal moving mass m, kg (default: the mass of the model's axis record)")
    p.add_argument("--force-constant", type=number(0, 1e6, low_open=True, unit="N/A"),
                   help="nominal force constant phi, N/A (default: that of the model's axis record)")
    p.add_argument("--max-effects", type=number(1, MAX_EFFECTS, integer=True), default=3,
                   help=f"most effects added, 1 to {MAX_EFFECTS} (default 3)")
    p.add_argument("--pitch", type=number(0, 1e3, low_open=True, unit="m"),
                   help="the known fundamental period, m, of forces periodic in position (a pole "
                   "pitch, a screw lead) for position_ripple and position_friction (default: "
                   "found from the log)")
    p.add_argument("--sensor-delay", action="store_true",
                   help="also consider a delay between the logged motion and the current "
                   "(sensor_delay; off by default: on short closed-loop logs a delay of a sample "
                   "or two also fits what the model misses of an axis without one)")
    p.add_argument("--saturation", action="store_true",
                   help="also consider a force constant that falls as the current grows "
                   "(actuator_saturation; off by default: close to a force-constant or mass "
                   "error, it takes their place among the sets a step tries)")
    p.add_argument("--presliding", action="store_true",
                   help="also consider the contact's pre-sliding, LuGre bristles on the model's "
                   "curve (presliding: named, it becomes the model's bristles, emitted as NAME_step; "
                   "off by default: for a log with reversals of an axis suspected of it)")
    add_output(p, "folder for model.json, report.md and plots",
               force_also=", and over files in it that diagnose did not write")
    add_export_options(p)
    add_json(p, "print the summary as one JSON object")
    p.add_argument("--verbose", action="store_true",
                   help="list every refused candidate set with its reason (default: their count)")
    p.set_defaults(run=run)


def asked_for(args):
    """The effects off by default that the flags ask for (``ASKED_FOR``)."""
    return [name for name, flag in (("sensor_delay", args.sensor_delay),
                                    ("actuator_saturation", args.saturation),
                                    ("presliding", args.presliding)) if flag]


def drive_columns(columns: dict, force_constant):
    """The columns as a log of current reads them, and the force constant they ask for: a
    ``force`` column (N) is the current i of a force constant of 1 N/A, and a log without v
    gets v = dx/dt by central differences; with one line for each."""
    notes = []
    if "i" not in columns and "force" in columns:
        if force_constant is not None:
            raise UsageError("--force-constant applies to a current column i; the log's force "
                             "column is in N already")
        columns = {**columns, "i": columns["force"]}
        del columns["force"]
        force_constant = 1.0
        notes.append("the log's force (N) is read as the drive force: phi = 1 N/A")
    if "v" not in columns and {"t", "x"} <= set(columns) and columns["t"].size > 2:
        columns = {**columns, "v": np.gradient(columns["x"], columns["t"])}
        notes.append("v = dx/dt by central differences (the log has no v)")
    return columns, force_constant, notes


def with_axis_offset(model: FrictionModel):
    """``model`` with its axis record's offset (the constant force its curves leave out,
    compensated apart: ``training.axis.offset``) held as a ``constant_load`` effect, so that the
    diagnosis does not name again what training identified; and a line saying so. The model
    as it is when it records none or carries a load already."""
    offset = offset_left_out(model)
    if offset is None:
        return model, []
    return with_effects(model, [ConstantLoad(load=offset)]), [
        f"offset from the model's axis: o = {offset:.4g} {model.units.force}, held as a "
        "constant_load (a change of it is named as one)"]


def asymmetry_notes(model: FrictionModel, d) -> list:
    """Lines where the diagnosis names a constant_load: beside a load the model held, that it is
    the change of it (model.json holds their sum); for a symmetric model, that while the axis
    moves the load is also a friction level that differs by direction, which the log cannot
    tell apart from it."""
    notes = []
    held = [e.load for e in model_effects(model) if e.name == ConstantLoad.name]
    named = [s for s in d.effects_ if s.effect == ConstantLoad.name]
    if held and named:
        total = [e.load for e in model_effects(d.model_) if e.name == ConstantLoad.name]
        notes.append(f"the constant_load named is the change of the load the model held ("
                     f"{sum(held):.4g} {d.units_.force}): model.json holds their sum, "
                     f"{sum(total):.4g} {d.units_.force}")
    if model.symmetric and named:
        notes.append("while the axis moves, a constant_load is the same force as a friction whose "
                     "level is higher one way by twice the load: the log does not tell them apart "
                     "(train --asymmetric holds the latter in its curves)")
    return notes


def nominal_axis(model: FrictionModel, mass, force_constant):
    """The nominal mass and force constant: the options, else the model's axis record; and
    one line per value taken from the record. ``UsageError`` when neither gives one."""
    axis = model.axis
    notes = []
    if mass is None:
        if axis is None or axis.mass is None:
            raise UsageError("--mass is required: the model's axis record gives no mass "
                             f"({'it has none' if axis is None else 'it was trained on a sweep'})")
        mass = axis.mass
        notes.append(f"mass from the model's axis: {axis.mass_text(model.units.mass)}")
    if force_constant is None:
        if axis is None or axis.force_constant is None:
            raise UsageError("--force-constant is required: the model's axis record gives none")
        force_constant = axis.force_constant
        notes.append(f"force constant from the model's axis: phi = {force_constant:.4g} N/A")
    return mass, force_constant, notes


def run(args) -> int:
    with data_warnings(args):
        return _run(args)


def _run(args) -> int:
    inputs = [args.model, args.log] + ([args.merge] if args.merge else [])
    check_folder(args.output, [args.model], args.force)
    model = load_model(args.model, "diagnose")
    if model.cogging_map is not None:
        raise UsageError(f"{args.model} holds a cogging map, which diagnose does not model yet: it "
                         "would name the cogging again as position_ripple; diagnose the model trained "
                         "without --cogging")
    if model.presliding is not None:
        if any(e.name == FrictionalLag.name for e in model_effects(model)):
            raise UsageError(f"{args.model} holds both bristles (pre-sliding) and a frictional lag: "
                             "two friction memories, which diagnose does not combine")
    columns = read_data(args, args.log, lambda c: MIN_SAMPLES, drop_text=True)
    columns, force_constant, drive_notes = drive_columns(columns, args.force_constant)
    mass, force_constant, notes = nominal_axis(model, args.mass, force_constant)
    with named_data(source_name(args.log, args.merge)):
        operating = missing_dependence(model, columns, mass, force_constant)
    columns = without_load(columns, force_constant)
    model, offset_notes = with_axis_offset(model)
    notes = drive_notes + notes + offset_notes
    if model.presliding is not None:
        notes.append(f"the model's bristles (LuGre, sigma0 {model.presliding.stiffness:.4g}, sigma1 "
                     f"{model.presliding.damping:.4g}) are in the residual and the held-out "
                     f"simulations, driven by the log's velocity; {FrictionalLag.name} is not "
                     "considered (the bristles are the friction's memory)"
                     + ("; --presliding asks for nothing more: the model has its bristles"
                        if args.presliding else ""))
    source = source_name(args.log, args.merge)
    log = log_from_columns(columns, source, None if args.merge or args.columns else
                           header_cells(args.log, args.skip))
    for note in notes:
        say("fricgen: " + note)
    with named_data(source):
        d = Diagnoser(max_effects=args.max_effects, pitch=args.pitch,
                      candidates=candidates_with(*asked_for(args))).fit(log, model, mass, force_constant)
    files = render_files(d, log, Path(args.log).name)
    targets = check_targets(args, files, inputs, folder_of=[args.model])  # before any result is printed
    check_overwrite(targets.values(), args.force, written=written_by_diagnose)
    say_data_warnings(args)
    for note in range_notes(model_effects(model), log) + asymmetry_notes(model, d):
        say("fricgen: note: " + note)
    if operating is not None:
        named, gap, undetermined = named_lines(operating, d.units_.force)
    if args.json:
        summary = d.summary()
        if operating is not None:
            summary["operating_point"] = {"missing": named, "gap": gap, "undetermined": undetermined}
        out(json.dumps(summary))
    else:
        lines = []
        for j, s in enumerate(d.effects_, 1):
            lines.append(f"effect {j}   {s.effect} ({p_text(s.p_value)}, {s.share:.0%} of the held-out "
                         f"residual, gap {s.gap_before:.4g} -> {s.gap_after:.4g} {d.units_.speed})")
            lines.append("parameters " + ", ".join(f"{k} = {format_value(v)}"
                                                  for k, v in s.fitted.parameters().items()))
        if not d.effects_:
            lines.append(f"effect     none (best candidate {p_text(d.p_value_)})")
        refused = d.refused()
        if args.verbose:
            lines += [f"refused    {s.label}: {s.reason}" for s in refused]
        elif refused:
            lines.append(f"refused    {len(refused)} candidate sets (--verbose lists them; report.md "
                         "gives each reason)")
        hint = service_hint(d)
        if hint:
            lines.append(f"in service {hint}")
        lines.append(f"where      before the effects: {d.where_}")
        if d.effects_:
            lines.append(f"           after them: {d.where_after_}")
        lines.append(f"gap        {d.gap_before_:.4g} -> {d.gap_after_:.4g} {d.units_.speed} "
                     f"({d.gap_metric_})")
        if operating is not None:
            lines += [f"missing    {line}" for line in named] or ["missing    no load nor temperature "
                                                                 "dependence (the held-out blocks ask for none)"]
            if gap:
                lines.append(f"           {gap}")
            lines += [f"not told   {line}" for line in undetermined]
            if named:
                lines.append("           retrain with the log's load and temperature columns "
                             "(fricgen train LOG --columns load=...,temperature=...)")
        refined = refinement_note(d)
        if refined:
            lines.append(f"refined    {refined}")
        out("\n".join(lines))
    write_folder(args, files, inputs, folder_of=[args.model])
    if not any(name.endswith(".png") for name in files):
        say("fricgen: matplotlib not installed; no plots written")
    say(f"wrote {', '.join(sorted(files))} to {args.output}")
    return 0
