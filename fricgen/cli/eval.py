"""``fricgen eval MODEL``: forces (N) for velocities read from stdin, one per line."""
from __future__ import annotations

import sys

import numpy as np

from ..errors import UsageError
from ..model import FrictionModel


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("model", help="model.json")
    p.set_defaults(run=run)


def run(args) -> int:
    model = FrictionModel.load(args.model)
    values = []
    for n, line in enumerate(sys.stdin, start=1):
        text = line.strip()
        if not text:
            continue
        try:
            value = float(text)
        except ValueError:
            raise UsageError(f"stdin line {n}: not a number: {text[:40]!r}") from None
        if not np.isfinite(value):
            raise UsageError(f"stdin line {n}: velocity must be finite, got {text[:40]}")
        values.append(value)
    forces = model.force(np.array(values, dtype=float))
    sys.stdout.write("".join(f"{f!r}\n" for f in forces.tolist()))
    return 0
