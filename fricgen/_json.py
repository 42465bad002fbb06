"""Strict JSON for untrusted files: the one reading that refuses what ``json`` accepts silently
(NaN and Infinity, a key twice, a file too large or nested too deep, text not UTF-8), each in
one ``ModelError`` line that names the file, and the writing of non-finite numbers as null."""
from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, Union

from .errors import ModelError


def _reject_constant(name: str):
    raise ValueError(f"{name} is not a JSON number")


def _unique_keys(pairs) -> dict:
    """A JSON object's dict; ``ModelError`` when a key appears twice (JSON keeps the last
    silently, so a hand-edited value could be lost)."""
    d = {}
    for key, value in pairs:
        if key in d:
            raise ModelError(f"key {key!r} appears twice in one object"[:200])
        d[key] = value
    return d


def read_json(path: Union[str, Path], max_bytes: int, what: str) -> Any:
    """The JSON value of the file ``path`` (at most ``max_bytes``; a UTF-8 byte order mark
    allowed); else ``ModelError`` naming ``path`` (``what``: the kind of file, for the message)."""
    try:
        if Path(path).stat().st_size > max_bytes:
            raise ModelError(f"{path}: larger than {max_bytes} bytes; not {what}")
        text = Path(path).read_text(encoding="utf-8-sig")
    except OSError as exc:
        raise ModelError(f"{path}: cannot read ({exc.strerror})") from None
    except UnicodeDecodeError as exc:
        raise ModelError(f"{path}: not UTF-8 text (byte 0x{exc.object[exc.start]:02x} at "
                         f"offset {exc.start})") from None
    try:
        return json.loads(text, parse_constant=_reject_constant, object_pairs_hook=_unique_keys)
    except ModelError as exc:
        raise ModelError(f"{path}: {exc}") from None
    except json.JSONDecodeError as exc:
        raise ModelError(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno})") from None
    except RecursionError:
        raise ModelError(f"{path}: not {what} (nested too deeply)") from None
    except ValueError as exc:          # e.g. an integer of more than 4300 digits
        raise ModelError(f"{path}: not valid JSON ({str(exc).split(':')[0]})") from None


def finite_or_null(value):
    """``value`` with every non-finite float (at any depth) replaced by None."""
    if isinstance(value, dict):
        return {k: finite_or_null(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite_or_null(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
