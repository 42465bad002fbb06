"""fricgen: train friction models, emit them as C, simulate, reproduce the paper, diagnose.

Every command is one module of this package with ``register(subparsers)`` and ``run(args)``.
Every command reports bad input as one line ``fricgen: error: ...`` on stderr, exits with code
2, and leaves no output file behind.
"""
from __future__ import annotations

import sys

from .. import __version__
from ..errors import FricgenError
from . import demo, diagnose, emit, eval, reproduce, simulate, synth, synth_log, train
from .common import ArgumentParser, say

#: The commands, in the order ``fricgen --help`` lists them.
COMMANDS = (demo, synth, train, eval, emit, simulate, reproduce, synth_log, diagnose)


def build_parser() -> ArgumentParser:
    parser = ArgumentParser(prog="fricgen", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"fricgen {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in COMMANDS:
        command.register(sub)
    return parser


def main(argv=None) -> int:
    try:
        args = build_parser().parse_args(argv)
        return args.run(args)
    except FricgenError as exc:
        say(f"fricgen: error: {exc}")
        return 2
    except OSError as exc:
        say(f"fricgen: error: {exc.filename or ''}: {exc.strerror}")
        return 2


if __name__ == "__main__":
    sys.exit(main())
