"""``fricgen synth-log``: a closed-loop motion log with one hidden effect, to try diagnose on."""
from __future__ import annotations

from .._io import check_destination
from ..data import log_csv_text
from ..errors import UsageError
from ..sim.logsynth import (HIDDEN_EFFECTS, MAX_DURATION, LogSpec, magnitude_range, synthesize_log,
                            truth_parameters)
from .common import add_output, add_seed, number, say, write_file


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("--effect", choices=HIDDEN_EFFECTS, default="none")
    bounded = [(e, magnitude_range(e, LogSpec.mass, LogSpec.force_constant)[1]) for e in HIDDEN_EFFECTS]
    p.add_argument("--magnitude", type=number(0, 100, low_open=True), default=1.0,
                   help="scale of the effect's reference size, > 0 and at most where its "
                   "parameters stay physical (" + ", ".join(f"{e} <= {hi:g}" for e, hi in bounded
                                                            if hi < 100) + "); default 1")
    add_seed(p)
    p.add_argument("--duration", type=number(0, MAX_DURATION, low_open=True, unit="s"), default=12.0,
                   help="seconds (1 kHz samples)")
    p.add_argument("--noise", type=number(0, 1e3), default=1.0, help="sensor noise scale")
    add_output(p, "the log CSV to write")
    p.set_defaults(run=run)


def run(args) -> int:
    try:
        spec = LogSpec(effect=args.effect, magnitude=args.magnitude, seed=args.seed,
                       duration=args.duration, noise=args.noise)
    except ValueError as exc:       # LogSpec names its field, this command's option
        name, _, why = str(exc).partition(" ")
        raise UsageError(f"--{name}: {why}") from None
    check_destination(args.output, (), args.force)
    write_file(args, log_csv_text(synthesize_log(spec)))
    truth = ", ".join(f"{k} = {v:g}" for k, v in truth_parameters(spec).items()) or "-"
    say(f"wrote {args.output}: {spec.duration:g} s at {spec.sample_rate:g} Hz, hidden effect "
        f"{spec.effect} ({truth}); nominal mass {spec.mass:g} kg, force constant "
        f"{spec.force_constant:g} N/A")
    return 0
