"""``fricgen simulate``: the closed loop of section 6 with each friction compensation variant.

Without ``--model`` the truth is the paper benchmark friction (Table 1) and the variants are
none, exact (the true friction), elm (fricgen's default model trained on the paper data) and
fuzzy (the ANFIS baseline). With ``--model`` the variants
are none, exact and that model.

The plant is the built-in 2 kg axis, unless the model's axis record (``training.axis``) gives a
mass, or ``--mass`` does: then the plant is that axis, with the model as its friction and the
record's offset as a constant force, and the variants are none and the model (exact
compensation is the model's). A model with a speed range keeps the reference within it;
``--reference`` replaces the reference by the user's move (a CSV of t and x), ``--k1`` and
``--k2`` set the controller's gains of [C3] and [C11].
"""
from __future__ import annotations

import json
from dataclasses import replace

import numpy as np

from ..control.backstepping import DEFAULT_TS, AdaptiveBackstepping
from ..control.c_abi import FRICTION_INPUT, LAW
from ..control.c_controller import c_controllers
from ..control.loop import (DEFAULT_DURATION, builtin_plant, compensations, model_plant,
                            peak_force, simulate)
from ..data.table import read_table_csv
from ..errors import DataError, UsageError
from .._progress import Progress
from ..sim.bristle_axis import MAX_SUBSTEPS, BristleAxis
from ..sim.trajectory import TabulatedTrajectory
from ..model import FrictionModel
from .._io import check_files, check_folder
from .._plot import png, pyplot
from .inputs import load_model
from .common import add_json, add_model, number, out, say, write_targets


def register(p) -> None:
    """The arguments of this command."""
    add_model(p, required=False, help="model.json to compensate with (default: fricgen's default "
              "model trained on the paper benchmark, plus the fuzzy baseline)")
    p.add_argument("--mass", type=number(0, 1e6, low_open=True, unit="kg"),
                   help="simulate the model's axis with this mass, kg (default: the mass of the "
                   "model's axis record, if any; else the built-in 2 kg axis)")
    p.add_argument("--law", choices=LAW.keys, default="c", help="adaptation law of [C14]")
    p.add_argument("--ts", type=number(1e-6, 0.1, unit="s"), default=DEFAULT_TS,
                   help="sampling time, s (default 1e-3)")
    p.add_argument("--duration", type=number(0, 3600, low_open=True, unit="s"),
                   help=f"simulated time, s (default {DEFAULT_DURATION:g}, or the --reference's span)")
    p.add_argument("--reference", metavar="CSV",
                   help="the move to follow: a CSV with columns t (s) and x (m, or rad for a "
                   "rotary model), positions taken relative to the first (the axis starts at rest "
                   "there); x_d is the cubic spline through them, at rest at both ends")
    p.add_argument("--k1", type=number(0, 1e6, low_open=True, unit="1/s"), default=80.0,
                   help="position gain of [C3], 1/s (default 80)")
    p.add_argument("--k2", type=number(0.5, 1e6, low_open=True, unit="A s/m"), default=40.0,
                   help="velocity-error gain of [C11], > 1/2 [C16] (default 40)")
    p.add_argument("--friction-input", choices=FRICTION_INPUT.keys, default="v",
                   help="evaluate the friction model at the measured v (paper), at v_d = xd' + "
                   "k1 e1, or at the reference velocity xd' (default v)")
    p.add_argument("--backend", choices=("python", "c"), default="python",
                   help="run the Python controller or the emitted C one (through cffi)")
    add_json(p, "print the figures as JSON")
    p.add_argument("--plot", metavar="DIR", help="draw e1, i and A_hat per variant into DIR")
    p.set_defaults(run=run)


#: Most controller samples one run simulates (about a minute of Python per 100000).
MAX_SAMPLES = 200_000


def run(args) -> int:
    if args.plot:
        check_folder(args.plot, [args.model], option="--plot")
    reference = read_reference(args.reference) if args.reference else None
    from_reference = args.duration is None and reference is not None
    if args.duration is None:
        args.duration = reference.duration if reference is not None else DEFAULT_DURATION
    if args.duration > MAX_SAMPLES * args.ts:
        lasting = (f"the reference {args.reference} lasts {args.duration:g} s (is its t in ms?), "
                   f"which at --ts {args.ts:g} s" if from_reference else
                   f"--duration {args.duration:g} s at --ts {args.ts:g} s")
        raise UsageError(f"{lasting} is {args.duration / args.ts:.3g} samples; at most {MAX_SAMPLES} "
                         "are simulated")
    if args.duration < 10 * args.ts:
        raise UsageError(f"--duration must cover at least 10 samples of --ts, got {args.duration:g} s")
    model = load_model(args.model, "simulate") if args.model else None
    if model is not None and model.cogging_map is not None:
        say(f"fricgen: note: the simulation leaves out {args.model}'s cogging map (its plant has "
            "friction only)")
    plant = choose_plant(model, args.mass)
    if reference is not None:
        plant = replace(plant, trajectory=reference, text=plant.text.rsplit("; reference", 1)[0]
                        + f"; reference {args.reference} ({reference.duration:.4g} s)")
    axis = plant.axis
    if isinstance(axis, BristleAxis) and axis.substeps(args.ts) >= MAX_SUBSTEPS:
        say(f"fricgen: note: the bristles' stiffness ({axis.bristles.stiffness:.3g}) on this mass needs "
            f"more than {MAX_SUBSTEPS} integration steps a sample at --ts {args.ts:g} s; the plant takes "
            f"{MAX_SUBSTEPS} (stable, but the contact's oscillation is not resolved, and the run is slow)")
    settings = AdaptiveBackstepping(law=args.law, ts=args.ts, friction_input=args.friction_input,
                                    phi_n=plant.phi_n, i_max=plant.i_max, k1=args.k1, k2=args.k2)
    try:
        settings.validate()
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    variants = compensations(axis, model, ts=args.ts)
    if args.plot:
        targets = check_files(args.plot, [plot_name(v) for v in variants], [args.model], option="--plot")
    if args.backend == "c":
        say("emitting the models and fric_ctrl as C and compiling them with cffi ...")
        ctrls = c_controllers(variants, settings)
    else:
        ctrls = {name: settings.clone(compensation=comp) for name, comp in variants.items()}
    thrust = axis.law.force_constant * axis.law.i_max
    needed = peak_force(plant, args.duration, args.ts)
    if needed > thrust:
        say(f"fricgen: warning: the reference needs up to {needed:.4g} N, more than the simulated "
            f"motor's {thrust:.4g} N: the current saturates")
    progress = Progress(say)
    runs = dict(zip(ctrls, simulate(axis, list(ctrls.values()), plant.trajectory, duration=args.duration,
                                    on_sample=lambda t: progress(f"simulate: {t:.4g} of {args.duration:g} s "
                                                                 f"of {len(ctrls)} variants"))))
    warn_saturation(runs, settings.i_max, args.ts)
    report = {"plant": plant.text, "units": "linear" if model is None else model.units.kind,
              "law": args.law, "ts": args.ts, "duration": args.duration,
              "k1": args.k1, "k2": args.k2,
              "backend": args.backend, "friction_input": args.friction_input,
              "variants": {name: run.metrics() for name, run in runs.items()}}
    if args.backend == "c":
        for name, ctrl in ctrls.items():
            report["variants"][name]["friction_in"] = (
                "c" if ctrl.c_friction else "none" if variants[name] is None else "python")
    out(json.dumps(report, indent=1) if args.json else table(report))
    if args.plot:
        pngs = plot_runs(runs)
        write_targets(targets, pngs)
        say(f"wrote {', '.join(sorted(pngs)) or 'no plots'} to {args.plot}")
    return 0


#: A run whose current sits at its limit in more than this share of the samples is named.
SATURATED_SHARE = 0.2


def warn_saturation(runs: dict, i_max: float, ts: float = DEFAULT_TS) -> None:
    """One warning line per variant whose current sits at +-i_max in more than SATURATED_SHARE
    of the samples: the loop then follows no law of [C11], whatever the gains say. Beyond the
    default sample time the line names it too: a sample too long for the gains makes the
    discrete loop unstable, and its current swings between the limits."""
    slow = f", or the sample time --ts {ts:g} s is too long for the gains" if ts > DEFAULT_TS else ""
    for name, run in runs.items():
        share = float(np.mean(np.abs(run.i) >= (1.0 - 1e-6) * i_max))
        if share > SATURATED_SHARE:
            say(f"fricgen: warning: with {name} the current sits at its limit of +-{i_max:g} A in "
                f"{share:.0%} of the samples: the gains (--k1, --k2) or the reference ask more than "
                f"the motor gives{slow}")


def read_reference(path: str) -> TabulatedTrajectory:
    """``--reference``: the move of a CSV with columns t and x; ``DataError`` naming the file."""
    columns = read_table_csv(path, ("t", "x"))
    try:
        return TabulatedTrajectory(columns["t"], columns["x"])
    except ValueError as exc:
        raise DataError(f"{path}: {exc}") from None


def choose_plant(model, mass=None):
    """The plant ``simulate`` runs: the model's axis when ``mass`` (``--mass``) or the model's
    axis record gives a mass, else the built-in axis; the reference within the model's speeds."""
    if model is None:
        if mass is not None:
            raise UsageError("--mass sets the mass of the model's axis: it needs --model")
        return builtin_plant("the paper benchmark")
    record = model.axis
    speed_max = record.speed_max if record is not None else None
    offset = (record.offset or 0.0) if record is not None else 0.0
    phi = record.force_constant if record is not None else None
    if mass is not None:
        return model_plant(model, mass, offset, speed_max,
                           f"m = {mass:.4g} {model.units.mass} (--mass)", phi)
    if record is not None and record.mass is not None:
        return model_plant(model, record.mass, offset, speed_max,
                           record.mass_text(model.units.mass), phi)
    why = ("the model carries no axis" if record is None else
           "the model's axis has no mass (trained on a sweep); --mass simulates that axis")
    return builtin_plant(why, speed_max)


def table(report: dict) -> str:
    """The variant table: rms and max tracking error, rms current, final adaptive parameters
    (in mm and per m, or on a rotary axis, ``report["units"]``, in mrad and per rad)."""
    milli, per = ("mrad", "rad") if report.get("units") == "rotary" else ("mm", "m")
    lines = [report["plant"],
             f"law ({report['law']}), k1 = {report['k1']:g} 1/s, k2 = {report['k2']:g} A s/{per}, "
             f"Ts = {report['ts']:g} s, {report['duration']:g} s simulated, "
             f"{report['backend']} controller, friction model at {report['friction_input']}",
             f"{'variant':8s} {f'rms_e1 {milli}':>11s} {f'max_e1 {milli}':>11s} {'rms_i A':>8s} "
             f"{'max_i A':>8s} {f'm_o_hat A s^2/{per}':>17s} {'k_hat':>7s}  (k_hat: no unit)"]
    for name, m in report["variants"].items():
        note = "" if m["finite"] else "  (unstable: diverged)"
        if m.get("friction_in") == "python":
            note += "  (friction computed in Python)"
        lines.append(f"{name:8s} {1e3 * m['rms_e1']:11.4f} {1e3 * m['max_e1']:11.4f} "
                     f"{m['rms_i']:8.3f} {m['max_i']:8.3f} {m['m_o_hat']:17.4f} {m['k_hat']:7.4f}{note}")
    return "\n".join(lines)


def plot_name(variant: str) -> str:
    """The file of a variant's figure."""
    return f"simulate_{variant}.png"


def plot_runs(runs: dict) -> dict:
    """One figure per variant (tracking error, current and adaptive parameters over time) as
    PNG bytes by file name; {} without matplotlib."""
    plt = pyplot()
    if plt is None:
        say("--plot skipped: matplotlib is not installed (pip install fricgen[plot])")
        return {}
    pngs = {}
    for name, run in runs.items():
        fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 7))
        axes[0].plot(run.t, 1e3 * run.e1)
        axes[0].set_ylabel("e1 = x_d - x (mm)")
        axes[1].plot(run.t, run.i)
        axes[1].set_ylabel("current i (A)")
        axes[2].plot(run.t, run.m_o_hat, label="m_o_hat")
        axes[2].plot(run.t, run.k_hat, label="k_hat")
        axes[2].set_ylabel("adaptive parameters")
        axes[2].legend()
        axes[2].set_xlabel("t (s)")
        axes[0].set_title(f"compensation: {name}")
        fig.tight_layout()
        pngs[plot_name(name)] = png(fig)
    return pngs
