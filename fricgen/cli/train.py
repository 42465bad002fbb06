"""``fricgen train``: fit a friction model to a sweep or a motion log CSV and write model.json.
The fit and its report are the library's (``fricgen.train``); this command reads and writes."""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from ..c_names import check_model_name
from ..data.inverse_dynamics import CONDITIONS, MIN_LOG_ROWS, describe_missing, is_log
from ..data.sweep import MIN_SWEEP_POINTS
from ..data.export import assignments, names_rotary_axis
from ..data.header_units import is_rotary_unit
from ..data.matfile import is_matfile
from ..data.plausibility import refuse_or_warn, top_speed, whole_numbers
from ..data.table import header_cells
from .._validate import MAX_HIDDEN, rotary_axis
from ..errors import DataError, UsageError
from ..fit import DEFAULT_ELM, ELMRegressor, StribeckRegressor, default_elm, default_estimator
from ..fit.elm import SCHEMES, SOLVERS, EnlargedScheme
from ..model import DEFAULT_MODEL_NAME
from ..networks.elm import ACTIVATIONS
from ..training import FitReport, train
from ..training.trainer import SPREAD_COLUMNS
from ..training.with_cogging import less_position_force, train_with_cogging
from ..unit_sizes import size
from ..training.with_dynamic import train_dynamic
from .._io import check_destination
from .inputs import add_export_options, data_warnings, load_model, read_data, say_data_warnings
from .inputs import source_name as common_source_name
from .common import (ArgumentParser, add_output, add_seed, number, out, positive_float, say,
                     write_file)

#: Options of an explicitly configured ELM (``--method elm``), with their defaults.
_ELM_OPTIONS = {"neurons": DEFAULT_ELM["n_hidden"], "activation": DEFAULT_ELM["activation"],
                "scheme": "enlarged", "w_max": DEFAULT_ELM["scheme"].w_max,
                "solver": DEFAULT_ELM["solver"], "C": None}


def _estimator(args):
    """The estimator the options describe: the default (``--method auto``), ``elm_auto``, the
    grey-box [F1] (``stribeck``), or the ELM of the explicit options (``--method elm``,
    implied by any of --neurons/--activation/--scheme/--w-max/--solver/--C)."""
    given = {k: getattr(args, k) for k in _ELM_OPTIONS if getattr(args, k) is not None}
    flags = ", ".join("--" + k.replace("_", "-") for k in given)
    method = args.method or ("elm" if given else "auto")
    if method != "elm":
        if given:
            raise UsageError(f"{flags} configure --method elm, not --method {method}")
        if method == "stribeck":
            if args.max_neurons is not None:
                raise UsageError("--max-neurons caps the ELM of --method auto or elm_auto; "
                                 "--method stribeck has no neurons")
            return StribeckRegressor()
        make = default_estimator if method == "auto" else default_elm
        return make(args.seed, max_neurons=args.max_neurons)
    if args.max_neurons is not None:
        raise UsageError("--max-neurons caps --method auto and elm_auto; --neurons sets the size "
                         "of --method elm")
    o = {**_ELM_OPTIONS, **given}
    if o["solver"] == "ridge" and o["C"] is None:
        raise UsageError("--solver ridge needs --C")
    if o["C"] is not None and o["solver"] != "ridge":
        raise UsageError(f"--C sets the C of --solver ridge; --solver {o['solver']} chooses its own")
    try:
        scheme = EnlargedScheme(w_max=o["w_max"]) if o["scheme"] == "enlarged" else o["scheme"]
    except ValueError as exc:
        raise UsageError(f"--w-max: {exc}") from None
    return ELMRegressor(n_hidden=o["neurons"], activation=o["activation"], scheme=scheme,
                        solver=o["solver"], C=o["C"], random_state=args.seed)


def read_columns(args):
    """The input's columns by fricgen's names, read with the vendor-export options
    (``common.read_data``): a merge needs the rows of a log or of a sweep."""
    return read_data(args, args.sweep, lambda c: MIN_LOG_ROWS if is_log(c) else MIN_SWEEP_POINTS,
                     drop_text=True)


def source_name(args) -> str:
    """The input as messages name it: the file, or both files of a merge ("a.csv + b.csv")."""
    return common_source_name(args.sweep, args.merge)


#: Column names that look like a log's load or temperature (``training_columns`` warns when
#: one is left unmapped).
OPERATING_NAME = re.compile(r"load|grav|temp")
#: The columns a sweep's fit uses.
SWEEP_COLUMNS = ("v", "f", *SPREAD_COLUMNS)


def training_columns(args) -> dict:
    """The columns to train on: a motion log's, or a sweep's ``v`` and ``f`` (refused, naming the
    header as written, when neither is there)."""
    columns = read_columns(args)
    if is_log(columns):
        unmapped = [c for c in columns if c not in CONDITIONS and OPERATING_NAME.search(c)]
        for condition in (c for c in CONDITIONS if c not in columns):
            named = [c for c in unmapped if condition[:4] in c or (condition == "load" and "grav" in c)]
            if named:
                say(f"fricgen: warning: {source_name(args)}: column {named[0]!r} is not used; "
                    f"--columns {condition}={named[0]} makes the friction depend on it")
        if "force" in columns and "i" in columns:
            say(f"fricgen: {source_name(args)}: trained on the force column; the current i is not "
                "used (without a force column, --force-constant makes the current a force)")
        return columns
    if not {"v", "f"} <= set(columns):
        written = None if args.merge else header_cells(args.sweep, args.skip)
        raise DataError(f"{source_name(args)}: {describe_missing(columns, written)}")
    if args.mass is not None or args.force_constant is not None:
        raise UsageError(f"--mass and --force-constant apply to a motion log; {source_name(args)} is a sweep (v, f)")
    unused = [c for c in columns if c not in SWEEP_COLUMNS]
    if unused:
        say(f"fricgen: warning: {source_name(args)}: column {unused[0]!r} is not used (a sweep's "
            "columns are v, f, F_std: each point's standard deviation, and n: its count)")
    return columns


def is_rotary(args) -> bool:
    """``--rotary``, or a header or ``--columns`` that names a robot joint's columns (q, dq,
    tau, ...)."""
    mapped = [name for name, *_ in assignments(args.columns)]
    return bool(args.rotary) or names_rotary_axis(mapped) or names_rotary_axis(_header(args))


def writes_rotary_unit(args) -> bool:
    """Whether the header or ``--columns`` writes a rotary unit ("Speed [rpm]"): its speeds are
    read in that unit, not asked about as a joint's in degrees."""
    mapped = [value for _, _, value, _ in assignments(args.columns)]
    return any(is_rotary_unit(c) for c in [*_header(args), *mapped])


def _header(args) -> list:
    """The data file's header cells as written; none for a MATLAB file."""
    return [] if is_matfile(args.sweep) else header_cells(args.sweep, args.skip)


def fed_forward(args, rotary: bool):
    """The cogging map and friction ripple of ``--fed-forward MODEL`` (None, None without it),
    of a model of the same kind of axis (rotary or linear) as the log's."""
    if args.fed_forward is None:
        return None, None
    model = load_model(args.fed_forward)
    if model.cogging_map is None:
        raise UsageError(f"--fed-forward {args.fed_forward}: the model has no cogging map to have fed "
                         "forward (train the first calibration with --cogging)")
    if (model.units.kind == "rotary") != rotary:
        raise UsageError(f"--fed-forward {args.fed_forward}: a {model.units.kind} axis's map (period "
                         f"{model.cogging_map.period:.6g} {model.units.position}); this log is a "
                         f"{'rotary' if rotary else 'linear'} axis's" + ("" if rotary else " (--rotary?)"))
    return model.cogging_map, model.cogging_friction


def run(args) -> int:
    with data_warnings(args):
        return _run(args)


def fit(args, progress=say, warn=say, position_force: bool = False):
    """The fit the arguments describe (``fricgen.train`` on the columns they read; with
    ``--cogging``, ``train_with_cogging``). ``position_force``: a motion log's default fit is
    made again without the position force the log holds (``less_position_force``)."""
    name = check_model_name(args.name, "--name")
    rotary = is_rotary(args)
    for option, value in (("--pitch", args.pitch), ("--fed-forward", args.fed_forward)):
        if value is not None and not args.cogging:
            raise UsageError(f"{option} is for --cogging's map; give --cogging too")
    if args.cogging and args.dynamic:
        raise UsageError("--cogging and --dynamic are trained from different logs (a slow move over "
                         "the travel; small reversals): train one, then the other")
    with rotary_axis(rotary):                  # the data checks' bounds too
        columns = training_columns(args)
        given = [c for c in CONDITIONS if c in columns]
        if args.gravity:
            check_gravity(args, columns, rotary)
        if args.force_held:
            check_force_held(args, columns)
        if rotary and not args.rotary and not writes_rotary_unit(args):
            check_joint_speed(args, columns, warn)
        if given and (args.dynamic or args.cogging):
            raise UsageError(f"--{'dynamic' if args.dynamic else 'cogging'} models the friction of v "
                             f"(and x) alone; the log has a {' and a '.join(given)} column: train the "
                             "load and temperature dependence without it")

        def fit_friction(data, mass=args.mass, force_constant=args.force_constant, use=None,
                         mass_source="given"):
            return train(data, estimator=_estimator(args), vs_max=args.vs_max, use=use,
                         asymmetric=args.asymmetric, mass=mass, force_constant=force_constant,
                         seed=args.seed, name=name, source=source_name(args),
                         file=Path(args.sweep).name, accept_unusual=args.accept_unusual,
                         progress=progress, warn=warn, rotary=rotary, checks=False,
                         velocity_resolution=args.velocity_resolution, gravity=args.gravity,
                         force_held=args.force_held, mass_source=mass_source)
        if args.dynamic:
            return train_dynamic(columns, rotary=rotary, force_constant=args.force_constant,
                                 train_friction=fit_friction)
        if not args.cogging:
            report = fit_friction(columns)
            return (less_position_force(columns, report, lambda data: fit_friction(data, force_constant=None))
                    if position_force else report)
        return train_with_cogging(columns, pitch=args.pitch, rotary=rotary, inertia=args.mass,
                                  force_constant=args.force_constant, fed_forward=fed_forward(args, rotary),
                                  train_friction=lambda data, mass, source: fit_friction(
                                      data, mass=mass, force_constant=None, mass_source=source),
                                  name=name, symmetric=args.asymmetric is False)


def train_argv(argv) -> FitReport:
    """``fit`` of ``fricgen train``'s arguments ``argv``, silent, without the log's position
    force (a fleet's worker task: a change of the cogging is not a change of the friction)."""
    parser = ArgumentParser(prog="fricgen train")
    register(parser)
    return fit(parser.parse_args(argv), progress=None, warn=lambda line: None, position_force=True)


def _run(args) -> int:
    inputs = [args.sweep] + [extra for extra in (args.merge, args.fed_forward) if extra]
    check_destination(args.output, inputs, args.force)
    report = fit(args)
    payload = report.model.checked_json()       # never one that load refuses, nor its report
    say_data_warnings(args)
    out(report.text)
    band = report.model.velocity_band
    if band is not None and report.model.inputs is None:     # a model with inputs emits no band
        speed, effort = report.model.units.speed, report.model.units.effort
        out(f"zero      NAME_compensation is 0 up to |v| = {band:.3g} {speed}, the {effort} from twice it "
            f"({report.model.training.get('velocity_band_from', 'model.json')})")
        fastest = (report.model.training.get("axis") or {}).get("speed_max")
        if fastest is not None and band >= fastest:
            say(f"fricgen: warning: NAME_compensation is 0 up to |v| = {band:.3g} {speed}, at or "
                f"above the log's fastest speed {fastest:.3g} {speed}: it compensates nothing at "
                "the speeds trained (the velocity the log resolves is coarser than its motion: "
                "give the firmware's velocity estimate's resolution with --velocity-resolution, "
                "or log a finer encoder or a faster move)")
    for warning in report.warnings:
        say(f"fricgen: {warning}")
    write_file(args, payload, inputs)
    say(f"wrote {args.output} (model {report.model.model_hash})")
    return 0


def check_gravity(args, columns, rotary: bool) -> None:
    """``UsageError`` where ``--gravity`` cannot apply: not a joint, no position, a sweep, or
    beside --dynamic or --cogging (whose once-per-turn term holds the weight already)."""
    if args.dynamic or args.cogging:
        raise UsageError(f"--gravity with --{'dynamic' if args.dynamic else 'cogging'}: "
                         + ("the cogging map's once-per-turn term holds the weight already; leave "
                            "--gravity out" if args.cogging else "the bristles are identified "
                            "from the force with no gravity term; train them without --gravity"))
    if not is_log(columns):
        raise UsageError("--gravity applies to a motion log (t, q, dq, tau): a sweep's points "
                         "hold no position")
    if not rotary:
        raise UsageError("--gravity is for a rotary axis (a joint, --rotary or q/dq/tau columns): "
                         "on a linear axis the weight is constant and the offset takes it")
    if "x" not in columns:
        raise UsageError("--gravity needs the position (a column q or x, in rad): the gravity "
                         "torque is a function of the joint's angle")


#: The speed, rad/s, beyond which a log named as a robot joint's (q, dq, tau) is likely in degrees:
#: joints of arms turn at a few rad/s; a motor shaft, faster, is said with --rotary.
JOINT_SPEED_MAX = 20.0


#: A degree in rad, the --scale that reads a position or speed logged in degrees.
DEGREE = size("deg")


def degrees_scale(columns) -> str:
    """The --scale value that reads the log's position and speed (those it has) from degrees."""
    return ",".join(f"{name}={DEGREE:.6g}" for name in ("x", "v") if name in columns)


def check_joint_speed(args, columns, warn=say) -> None:
    """A log named as a joint's that moves faster than JOINT_SPEED_MAX (``data.plausibility.
    top_speed``) is refused in one line, or with --accept-unusual warned: q and dq in degrees,
    dq in rpm, or q in encoder counts (whole numbers), read as rad, would train a model whose
    every number is wrong (a joint's q in degrees had trained F_v 57 times too small)."""
    top = (top_speed(columns) or ("", 0.0))[1]
    if not top > JOINT_SPEED_MAX:               # (NaN: the readers name the row)
        check_joint_span(args, columns, warn)
        return
    if "x" in columns and whole_numbers(columns["x"]):
        unit = "is q in encoder counts (--scale x= 2 pi over the counts per turn)"
    else:
        scale = degrees_scale(columns)
        rpm = "" if "x" in columns else f" or in rpm (--scale v={size('rpm'):.6g})"
        unit = (f"{'are its position and speed' if ',' in scale else 'is it'} in degrees (--scale "
                f"{scale}){rpm}")
    refuse_or_warn(f"{source_name(args)}: the joint's speed reaches {top:.4g} rad/s (99th "
                   f"percentile), beyond the {JOINT_SPEED_MAX:g} rad/s of robot joints: {unit}? "
                   "A motor shaft this fast, not a joint: --rotary says so", args.accept_unusual, warn)


#: The span of a joint's position, rad, beyond which a log named as a joint's is likely in
#: degrees: an arm's joint turns within a turn each way (the robot joints' logs here, of the
#: UR10e, Panda and Kinova Gen3, span at most 6.5 rad); one that turns on says so with --rotary.
JOINT_SPAN_MAX = 4 * math.pi


def check_joint_span(args, columns, warn=say) -> None:
    """One warning where a log named as a joint's, slower than JOINT_SPEED_MAX, has a position
    spanning more than JOINT_SPAN_MAX: q and dq in degrees read as rad (a slow joint's log in
    degrees had trained every number 57 times off without a word). A warning, not a refusal:
    a joint may turn on."""
    span = float(np.ptp(columns["x"])) if "x" in columns else 0.0
    if span > JOINT_SPAN_MAX:
        scale = degrees_scale(columns)
        warn(f"fricgen: warning: {source_name(args)}: the joint's position spans {span:.4g} rad "
             f"({span / (2 * math.pi):.3g} turns), more than the {JOINT_SPAN_MAX / (2 * math.pi):g} "
             f"turns of robot joints: {'are q and dq' if ',' in scale else 'is q'} in degrees "
             f"(--scale {scale})? A joint that turns on, or a motor shaft: --rotary says so")


def check_force_held(args, columns) -> None:
    """``UsageError`` where ``--force-held`` cannot apply: a sweep, or beside --dynamic or
    --cogging (slow moves, whose acceleration barely turns within a sample)."""
    if args.dynamic or args.cogging:
        raise UsageError(f"--force-held with --{'dynamic' if args.dynamic else 'cogging'}: its log "
                         "is a slow move, where half a sample of the force's timing does not show; "
                         "leave --force-held out")
    if not is_log(columns):
        raise UsageError("--force-held applies to a motion log (t, x or v, force or i): a sweep's "
                         "points have no sample times")


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("sweep", help="CSV with columns v (m/s) and f (N) (a sweep), or t (s), v (m/s) "
                   "or x (m), and force (N) or i (A) (a motion log); or a MATLAB .mat "
                   "file, its vectors the columns")
    add_output(p, "model.json to write (default model.json)", default="model.json")
    p.add_argument("--vs-max", type=positive_float, help="the Stribeck range, m/s (rad/s): "
                   "v_sat = 3 vs_max, and the bound on the Stribeck velocities except a broad "
                   "source the grey-box may place up to v_sat, which the report names "
                   "(default: chosen by cross-validation from the data)")
    p.add_argument("--method", choices=["auto", "elm_auto", "stribeck", "elm"],
                   help="auto: the grey-box [F1], or the automatic ELM where its "
                   "cross-validated error is smaller by more than one standard error (default); "
                   "elm_auto: the automatic ELM; "
                   "stribeck: the grey-box [F1]; elm: the ELM the options below describe "
                   "(default when any of them is given)")
    p.add_argument("--max-neurons", type=number(1, MAX_HIDDEN, integer=True),
                   help="(auto, elm_auto) at most this many hidden units, e.g. for a firmware budget")
    p.add_argument("--neurons", type=number(1, MAX_HIDDEN, integer=True),
                   help=f"(elm) default {_ELM_OPTIONS['neurons']}")
    p.add_argument("--activation", choices=sorted(ACTIVATIONS),
                   help=f"(elm) default {_ELM_OPTIONS['activation']}")
    p.add_argument("--scheme", choices=sorted(SCHEMES), help="(elm) default enlarged")
    p.add_argument("--w-max", type=number(0, 1e4, low_open=True), help="(elm) input-weight range of the enlarged "
                   f"scheme, [F16]-[F17], default {_ELM_OPTIONS['w_max']:g}")
    p.add_argument("--solver", choices=sorted(SOLVERS), help=f"(elm) default {_ELM_OPTIONS['solver']}")
    p.add_argument("--C", type=positive_float, help="regularization C of [F15] for --solver ridge")
    add_seed(p)
    symmetry = p.add_mutually_exclusive_group()
    symmetry.add_argument("--asymmetric", dest="asymmetric", action="store_const", const=True,
                          help="one curve per direction of motion (default: chosen by cross-validation)")
    symmetry.add_argument("--symmetric", dest="asymmetric", action="store_const", const=False,
                          help="one curve for both directions, F(-v) = -F(v)")
    log = p.add_argument_group("motion logs (inverse dynamics, [C1]: F = force - m dv/dt)")
    log.add_argument("--mass", type=number(0, 1e6, low_open=True, unit="kg"),
                     help="moving mass of the axis, kg (its inertia, kg m^2, on a rotary axis) "
                     "(default: identified from the log by inverse dynamics; with a current log "
                     "and no --force-constant, K is identified instead)")
    log.add_argument("--force-constant", type=number(0, 1e6, low_open=True, unit="N/A"),
                     help="force constant, N/A (Nm/A on a rotary axis), for a log with current i "
                     "instead of force")
    log.add_argument("--gravity", action="store_true",
                     help="a joint whose torque holds its link's weight: identify G_s sin q + G_c cos q "
                     "of the position (rad) beside the inertia and take it out of the friction "
                     "(a rotary axis with its position column)")
    log.add_argument("--force-held", action="store_true",
                     help="the force (or current) column is the drive's set-point, held over the "
                     "sample after the one it is logged at (a command, not a measurement): each row "
                     "is taken as the mean of its value and the row before's, at the motion's "
                     "sample times")
    add_export_options(p)
    cogging = p.add_argument_group("cogging (a slow move over the travel, e.g. 2 revolutions each way)")
    cogging.add_argument("--cogging", action="store_true",
                         help="also identify the cogging map (the position force: cogging, unbalance) "
                         "and the position-dependent friction; emit writes NAME_cogging(x), "
                         "NAME_cogging_q15(phase) and NAME_cogging_q31(phase)")
    cogging.add_argument("--fed-forward", metavar="MODEL",
                         help="the log is a second calibration, made with MODEL's cogging map fed "
                         "forward (its current holds the whole cogging): the map is identified "
                         "again, its harmonics chosen among MODEL's")
    cogging.add_argument("--pitch", type=positive_float,
                         help="the map's period: a pole pitch or screw lead, m (default: one "
                         "revolution, 2 pi rad, on a rotary axis; on a linear axis the wavelength of "
                         "the strongest position harmonic in the log)")
    slow = p.add_argument_group("slow speeds and reversals")
    slow.add_argument("--dynamic", action="store_true",
                      help="also identify pre-sliding (LuGre bristles: stiffness, damping) from a log "
                      "with small reversals or a slow force ramp at rest; emit writes NAME_step")
    slow.add_argument("--velocity-resolution", type=positive_float,
                      help="the smallest speed the controller's velocity resolves, m/s (rad/s): "
                      "NAME_compensation is 0 up to it and ramps to the force at twice it (default: the "
                      "log's, 3 encoder counts per sample or 4 standard deviations of its velocity noise)")
    p.add_argument("--rotary", action="store_true",
                   help="a rotary axis (a joint, a shaft): v in rad/s, force in Nm, inertia in kg m^2 "
                   "in every report and record (default: a linear axis, unless the header names a "
                   "joint's columns q, dq, qd, tau, effort or torque)")
    p.add_argument("--name", default=DEFAULT_MODEL_NAME,
                   help=f"model name, a C identifier not beginning with fric_ (default {DEFAULT_MODEL_NAME})")
    p.set_defaults(run=run)
