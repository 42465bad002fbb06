"""``fricgen eval MODEL``: forces (N) for velocities read from stdin, one per line, streamed:
F(v) of [F3] plus the axis's identified offset (``FrictionModel.force_with_offset``), or F(v)
alone with ``--no-offset``."""
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


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("model", help="model.json")
    p.add_argument("--no-offset", action="store_true",
                   help="F(v) alone, without the constant force training identified on the axis")
    p.set_defaults(run=run)


def _velocities(stream):
    """The velocity of every non-blank line of a binary (or text) stream."""
    for n, raw in enumerate(stream, start=1):
        try:
            text = (raw.decode("utf-8-sig") if isinstance(raw, bytes) else raw).strip()
        except UnicodeDecodeError:
            raise UsageError(f"stdin line {n}: not UTF-8 text") from None
        if not text:
            continue
        try:
            value = plain_float(text)
        except ValueError:
            raise UsageError(f"stdin line {n}: not a number: {text[:40]!r}") from None
        if not math.isfinite(value):
            raise UsageError(f"stdin line {n}: velocity must be finite, got {text[:40]}")
        yield value


def run(args) -> int:
    model = load_model(args.model)
    stdin = getattr(sys.stdin, "buffer", sys.stdin)
    if stdin is None or stdin.closed:
        raise UsageError("stdin: closed; pipe velocities into fricgen eval, one per line")
    if model.effects:
        names = ", ".join(e.get("effect", "?") for e in model.effects)
        say(f"fricgen: note: eval gives F(v) of [F3] alone; the model's effects ({names}) "
            "need x, t or i and are not applied")
    force = model.force
    if model.axis_offset and not args.no_offset:
        say(f"fricgen: note: the forces include the axis's offset {model.axis_offset:.6g} "
            "(identified in training); --no-offset for F(v) alone")
        force = model.force_with_offset
    velocities = _velocities(stdin)
    while chunk := list(itertools.islice(velocities, CHUNK)):
        out("\n".join(repr(f) for f in force(np.array(chunk)).tolist()))
    return 0
