"""fricgen: train friction models, emit them as C, simulate, reproduce the paper, diagnose.

Every command is one module of this package with ``register(parser)``, which adds its
arguments, and ``run(args) -> int``. Only the module of the command being run is imported, so
``fricgen --version`` and ``fricgen --help`` load no numerics. Every command reports bad input
as one line ``fricgen: error: ...`` on stderr, exits with code 2, and leaves no output file;
Ctrl-C is one line and exit code 130, and leaves no output file either.
"""
from __future__ import annotations

import importlib
import os
import sys
import warnings

from .. import __version__
from .._blas import thread_count
from ..errors import FricgenError, UsageError
from .common import ArgumentParser, say

#: The commands, in the order ``fricgen --help`` lists them: name -> (module, one-line help).
COMMANDS = {
    "demo": ("demo", "paper benchmark -> the paper's ELMs and elm_auto -> C -> measured parity"),
    "synth": ("synth", "write a measured-style friction sweep (CSV v,f)"),
    "train": ("train", "fit a friction model to a sweep or motion-log CSV; write model.json"),
    "eval": ("eval", "forces (N, or Nm on a rotary axis) for velocities read from stdin, one per line"),
    "emit": ("emit", "write NAME.h, NAME.c and the C runtime into a folder"),
    "readback": ("readback", "turn the parameters the firmware adapted (emit --adapt) back into "
                             "model.json"),
    "simulate": ("simulate", "closed-loop position control with friction compensation "
                             "(adaptive backstepping, section 6)"),
    "reproduce": ("reproduce", "run every experiment of the paper; write results.json, report.md "
                               "and figures"),
    "synth-log": ("synth_log", "write a closed-loop motion log (t,x,v,i) of the paper's friction "
                               "with one hidden effect"),
    "fleet": ("fleet", "identify every axis of a manifest of logs on Dask; flag drifting friction"),
    "diagnose": ("diagnose", "name the effects a model misses in a measured log (t,x,v,i), add them, "
                             "show the gap shrink"),
}


def command_module(name: str):
    """The module of command ``name`` (imported on first use)."""
    return importlib.import_module(f"{__name__}.{COMMANDS[name][0]}")


def build_parser(argv=None) -> ArgumentParser:
    """The ``fricgen`` parser; the arguments of the command named in ``argv`` (default: every
    command's) are registered, the others only listed."""
    wanted = [a for a in (sys.argv[1:] if argv is None else argv) if a in COMMANDS][:1]
    parser = ArgumentParser(prog="fricgen", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"fricgen {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, (_, help_text) in COMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        if name in wanted:
            command_module(name).register(p)
    return parser


#: The exit code of a command interrupted by Ctrl-C (128 + SIGINT, as a shell reports it).
INTERRUPTED = 130

#: The environment variables that set the BLAS thread count when numpy loads.
BLAS_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def blas_env(environ=os.environ) -> dict:
    """The BLAS variables of a worker process: one thread, or ``FRICGEN_BLAS_THREADS``."""
    return {key: environ.get("FRICGEN_BLAS_THREADS", "1") for key in BLAS_VARIABLES}


def pin_blas_threads(environ=os.environ) -> None:
    """Set the BLAS thread count before numpy loads (with the command's module): one thread, as
    fricgen's factorizations are small (thousands x tens) and extra threads only contend for a
    shared machine's cores; ``FRICGEN_BLAS_THREADS=N`` asks for N threads instead. A variable of
    ``BLAS_VARIABLES`` the user set is kept unless ``FRICGEN_BLAS_THREADS`` is set."""
    wanted = environ.get("FRICGEN_BLAS_THREADS")
    if wanted is None:
        for key in BLAS_VARIABLES:
            environ.setdefault(key, "1")
        return
    count = thread_count(wanted)
    if count is None:
        raise UsageError(f"FRICGEN_BLAS_THREADS must be an integer from 1 to 1024, got {wanted[:40]!r}")
    for key in BLAS_VARIABLES:
        environ[key] = str(count)


def main(argv=None) -> int:
    """Run one command; any problem is one stderr line and exit code 2 (Ctrl-C: one line, 130). Warnings of the
    numerics (a rank-deficient fit, an overflow the checks already handle) stay silent.
    Numerics run on one BLAS thread unless FRICGEN_BLAS_THREADS says otherwise (set before
    numpy loads with the command's module; in a process that imported numpy before, the
    thread count is numpy's)."""
    try:
        pin_blas_threads()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            args = build_parser(argv).parse_args(argv)
            return args.run(args)
    except FricgenError as exc:
        say(f"fricgen: error: {exc}")
        return 2
    except OSError as exc:
        where = f"{exc.filename}: " if exc.filename else ""
        say(f"fricgen: error: {where}{exc.strerror or exc}")
        return 2
    except KeyboardInterrupt:
        # files are written all or nothing (``_io.write_files`` undoes a write it was in)
        say("fricgen: interrupted; nothing written")
        return INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
