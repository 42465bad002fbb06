"""What every command shares: the argument parser, the flags that mean the same everywhere,
and where messages go (results to stdout; progress and "wrote ..." to stderr)."""
from __future__ import annotations

import argparse
import math
import re
import sys
from pathlib import Path
from typing import Dict

from .._io import check_destination, check_files, plain_float, plain_int, write_atomic, write_files
from ..errors import UsageError


class ArgumentParser(argparse.ArgumentParser):
    """argparse that reports a usage problem as a ``UsageError`` (one line, exit 2) instead of
    printing a usage block."""

    def error(self, message):
        # argparse says "argument --mass: must be > 0, got 0"; the option leads the line instead
        raise UsageError(re.sub(r"^argument ([^:]+): ", r"\1: ", message))


def say(msg: str) -> None:
    """A progress or "wrote ..." line: stderr, so stdout carries results only (nothing when
    stderr is closed)."""
    if sys.stderr is not None:
        try:
            print(msg, file=sys.stderr, flush=True)
        except OSError:
            pass


def number(low: float = -math.inf, high: float = math.inf, low_open: bool = False,
           integer: bool = False, unit: str = ""):
    """An argparse type: a finite number (an integer with ``integer``) in [low, high], or in
    (low, high] with ``low_open``, written plainly (``plain_float``); the error says the range."""
    kind = "an integer" if integer else "a finite number"
    show = (lambda x: str(int(x))) if integer else (lambda x: f"{x:g}")
    bounds = [f"{'>' if low_open else '>='} {show(low)}"] if low > -math.inf else []
    bounds += [f"<= {show(high)}"] if high < math.inf else []
    wanted = f"{kind} {' and '.join(bounds)}{' ' + unit if unit and bounds else ''}".strip()

    def parse(text: str):
        try:
            value = plain_int(text) if integer else plain_float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be {wanted}, got {text[:40]!r}") from None
        ok = math.isfinite(value) and value <= high and (value > low if low_open else value >= low)
        if not ok:
            raise argparse.ArgumentTypeError(f"must be {wanted}, got {text[:40]}")
        return value

    return parse


#: A finite number > 0.
positive_float = number(0.0, low_open=True)


#: What ``--force`` also overwrites in a command that emits C (``fricgen.codegen.check_overwrite``).
FORCE_C = ", and over C files fricgen did not write"


def add_output(p, help: str, required: bool = True, default=None, force_also: str = "") -> None:
    """``-o/--output`` (``--out`` is an alias): the file or folder a command writes, and
    ``--force`` to overwrite an input or a read-only file or write through a symbolic link (and
    ``force_also``)."""
    p.add_argument("-o", "--output", "--out", dest="output", required=required and default is None,
                   default=default, help=help)
    p.add_argument("--force", action="store_true",
                   help="write even where -o is one of the inputs (or, for diagnose, the model's "
                   "folder), a read-only file, or a symbolic link where a file goes (its target is "
                   f"written){force_also}")


def out(text: str) -> None:
    """Results on stdout, flushed now: a full disk or a closed pipe is an error before any file
    is written."""
    if sys.stdout is None:
        raise UsageError("stdout: closed; fricgen prints its results there")
    try:
        sys.stdout.write(text if text.endswith("\n") else text + "\n")
        sys.stdout.flush()
    except OSError as exc:
        raise UsageError(f"stdout: {exc.strerror or exc}") from None


def write_file(args, text, inputs=()) -> Path:
    """Write ``args.output`` (one file) all or nothing, after checking it may be written."""
    path = check_destination(args.output, inputs, args.force)
    return write_atomic(path, text)


def check_targets(args, names, inputs=(), folder_of=()) -> Dict[str, Path]:
    """The destinations of ``names`` in the folder ``args.output``, each checked (the folder not
    that of one of ``folder_of``, no destination one of ``inputs``), by name."""
    return check_files(args.output, names, inputs, folder_of, args.force)


def write_folder(args, files: Dict[str, object], inputs=(), folder_of=()) -> Path:
    """Write every file into the folder ``args.output``, all or nothing, after checking the
    folder and every destination in it (``check_targets``)."""
    write_targets(check_targets(args, files, inputs, folder_of), files)
    return Path(args.output)


def write_targets(targets: Dict[str, Path], files: Dict[str, object]) -> None:
    """Write each of ``files`` to its checked destination in ``targets`` (by name), all or nothing."""
    write_files({targets[name]: text for name, text in files.items()})


def add_model(p, required: bool = True, help: str = "model.json of the friction model") -> None:
    """``--model``: a model.json that is not the command's main input."""
    p.add_argument("--model", required=required, help=help)


def add_seed(p) -> None:
    p.add_argument("--seed", type=number(0, 2 ** 32 - 1, integer=True), default=0,
                   help="random seed, an integer >= 0 (default 0)")


def add_json(p, help: str = "print the result as one JSON object") -> None:
    p.add_argument("--json", action="store_true", help=help)

