"""``fricgen eval MODEL``: forces (N) for velocities read from stdin, one per line, streamed:
F(v) of [F3] plus the axis's identified offset (``FrictionModel.force_with_offset``), or F(v)
alone with ``--no-offset``. A model that depends on the load or the temperature reads them
after v on each line (v,load,temperature; those it uses, in that order). With ``--position``
each line ends with x and the cogging map's force C(x) is added (``FrictionModel.cogging``)."""
from __future__ import annotations

import itertools
import math
import sys

import numpy as np

from .._io import plain_float
from ..errors import UsageError
from ..model import FrictionModel
from .inputs import load_model
from .common import out, say

#: Velocities evaluated together: memory stays constant however long the input is.
CHUNK = 1 << 16
#: The coldest temperature there is, degC: a colder one is a typo, not a reading to saturate.
ABSOLUTE_ZERO = -273.15


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("model", help="model.json")
    p.add_argument("--no-offset", action="store_true",
                   help="F(v) alone, without the constant force training identified on the axis")
    p.add_argument("--position", action="store_true",
                   help="each line ends with x (comma or space between): add the cogging map C(x)")
    p.set_defaults(run=run)


def _rows(stream, names):
    """The numbers named ``names`` (velocity, the model's inputs, position) of every non-blank
    line of a binary (or text) stream."""
    columns, what = len(names), ", ".join(names)
    for n, raw in enumerate(stream, start=1):
        try:
            text = (raw.decode("utf-8-sig") if isinstance(raw, bytes) else raw).strip()
        except UnicodeDecodeError:
            raise UsageError(f"stdin line {n}: not UTF-8 text") from None
        if not text:
            continue
        fields = text.replace(",", " ").split()
        if len(fields) != columns:
            raise UsageError(f"stdin line {n}: {len(fields)} numbers, need {columns} ({what}): {text[:40]!r}")
        try:
            values = [plain_float(f) for f in fields]
        except ValueError:
            raise UsageError(f"stdin line {n}: not a number: {text[:40]!r}") from None
        if not all(math.isfinite(v) for v in values):
            raise UsageError(f"stdin line {n}: {what} must be finite, got {text[:40]}")
        if "temperature" in names and values[names.index("temperature")] < ABSOLUTE_ZERO:
            raise UsageError(f"stdin line {n}: temperature {values[names.index('temperature')]:g} "
                             f"degC is below absolute zero ({ABSOLUTE_ZERO} degC)")
        yield values


def run(args) -> int:
    model = load_model(args.model)
    stdin = getattr(sys.stdin, "buffer", sys.stdin)
    if stdin is None or stdin.closed:
        raise UsageError("stdin: closed; pipe velocities into fricgen eval, one per line")
    notes = []                      # said once the first block of input has been read
    if model.effects:
        names = ", ".join(e.get("effect", "?") for e in model.effects)
        notes.append(f"eval gives F(v) of [F3] alone; the model's effects ({names}) need x, t or i "
                     "and are not applied")
    if model.presliding is not None:
        notes.append("the model has pre-sliding, a state: eval gives its static curve (the force "
                     "of steady sliding at each v); model.stepper and NAME_step give the dynamics")
    offset = 0.0
    if model.axis_offset and not args.no_offset:
        units = model.units
        notes.append(f"the {units.effort}s include the axis's offset {model.axis_offset:.6g} "
                     f"{units.force} (identified in training); --no-offset for F(v) alone")
        offset = model.axis_offset
    if args.position and model.cogging_map is None:
        notes.append("the model has no cogging map; --position adds nothing")
    inputs = () if model.inputs is None else model.inputs.names
    names = ["velocity", *inputs] + (["position"] if args.position else [])
    rows = _rows(stdin, names)
    trained = None if model.axis is None else model.axis.speed_max
    band = model.velocity_band
    beyond = within = 0
    read = 0
    while chunk := list(itertools.islice(rows, CHUNK)):
        if not read:                # a bad first line is its one error line, without the notes
            for note in notes:
                say("fricgen: note: " + note)
        read += len(chunk)
        chunk = np.array(chunk)
        fastest = float(np.max(np.abs(chunk[:, 0])))
        if trained is not None and fastest > trained and not beyond:
            speed = model.units.speed
            say(f"fricgen: warning: |v| = {fastest:.6g} {speed} is beyond the speeds the model was "
                f"trained on (up to {trained:.4g} {speed}): it extrapolates there (are the "
                f"velocities in {speed}?)")
            beyond = 1
        moving = [] if band is None or within else np.abs(chunk[:, 0])[chunk[:, 0] != 0]
        if len(moving) and float(moving.min()) < band:
            speed = model.units.speed
            slowest = None if model.axis is None else model.axis.speed_min
            trained_there = slowest is not None and slowest <= float(moving.min())
            say(f"fricgen: warning: |v| = {float(moving.min()):.6g} {speed} is within the model's velocity "
                f"band ({band:.4g} {speed}, {model.training.get('velocity_band_from', 'velocity_band')}): "
                + (f"F(v) was trained down to {slowest:.4g} {speed}, but NAME_compensation gives 0 "
                   "there, below the speed the controller's velocity resolves" if trained_there else
                   "no speed there was resolved in training, and F(v) is the law extrapolated "
                   "(NAME_compensation gives 0 there)"))
            within = 1
        f = model.force(chunk[:, 0], **{n: chunk[:, 1 + k] for k, n in enumerate(inputs)}) + offset
        if args.position:
            f = f + model.cogging(chunk[:, -1])
        out("\n".join(repr(v) for v in f.tolist()))
    if not read:
        say("fricgen: note: stdin held no velocity: nothing evaluated")
    return 0
