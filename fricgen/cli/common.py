"""What every command shares: the argument parser, the flags that mean the same everywhere,
and where messages go (results to stdout; progress and "wrote ..." to stderr)."""
from __future__ import annotations

import argparse
import math
import re
import sys

from ..errors import UsageError


class ArgumentParser(argparse.ArgumentParser):
    """argparse that reports a usage problem as a ``UsageError`` (one line, exit 2) instead of
    printing a usage block."""

    def error(self, message):
        # argparse says "argument --mass: must be > 0, got 0"; the option leads the line instead
        raise UsageError(re.sub(r"^argument ([^:]+): ", r"\1: ", message))


def say(msg: str) -> None:
    """A progress or "wrote ..." line: stderr, so stdout carries results only."""
    print(msg, file=sys.stderr, flush=True)


def positive_float(text: str) -> float:
    """An argparse type: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number > 0, got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def add_output(p, help: str, required: bool = True, default=None) -> None:
    """``-o/--output`` (``--out`` is an alias): the file or folder a command writes."""
    p.add_argument("-o", "--output", "--out", dest="output", required=required and default is None,
                   default=default, help=help)


def add_model(p, required: bool = True, help: str = "model.json of the friction model") -> None:
    """``--model``: a model.json that is not the command's main input."""
    p.add_argument("--model", required=required, help=help)


def add_seed(p) -> None:
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")


def add_json(p, help: str = "print the result as one JSON object") -> None:
    p.add_argument("--json", action="store_true", help=help)
