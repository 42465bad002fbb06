"""Read back what the firmware adapted: the text ``fric_adapt_export`` writes, turned into a
model.json that ``eval``, ``emit`` and ``diagnose`` accept.

The dump (``fric_adapt.h``) is three lines::

    fricgen-adapt-dump 1
    model <the hash of the model the firmware was emitted from>
    theta <8 hex digits per parameter: the float32 bits of theta[0 .. n-1]>

theta is the model's output parameters (``fricgen.control.regressor``: beta_k and B of an ELM,
a_k, c and B of the grey-box [F1]); the hidden layer, the Stribeck velocities, the slope and
the scaling are the model's own. The hex bits carry every float exactly.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Tuple

import numpy as np

from ..errors import DataError, ModelError
from ..model import FrictionModel
from .regressor import parameter_names, trained_parameters, with_parameters

#: The first line of a dump, with its format version.
MAGIC = "fricgen-adapt-dump 1"


def dump_text(model_hash: str, theta) -> str:
    """The dump ``fric_adapt_export`` writes for float32 parameters ``theta``."""
    words = " ".join(f"{int(u):08x}" for u in np.asarray(theta, dtype=np.float32).view(np.uint32))
    return f"{MAGIC}\nmodel {model_hash}\ntheta {words}\n"


def parse_dump(text: str) -> Tuple[str, np.ndarray]:
    """(model hash, theta as float32) of a dump; ``DataError`` naming the first problem."""
    lines = [line.strip() for line in text.strip().splitlines()]
    if not lines or lines[0] != MAGIC:
        raise DataError(f"not an adaptation dump: the first line must be {MAGIC!r}, got "
                        f"{(lines[0] if lines else '')[:40]!r}")
    if len(lines) != 3 or not lines[1].startswith("model ") or not lines[2].startswith("theta"):
        raise DataError("adaptation dump: expected the lines 'model <hash>' and 'theta <hex> ...'")
    words = lines[2].split()[1:]
    if not words:
        raise DataError("adaptation dump: the theta line holds no parameter")
    bad = next((w for w in words if len(w) != 8 or any(c not in "0123456789abcdefABCDEF" for c in w)), None)
    if bad is not None:
        raise DataError(f"adaptation dump: {bad[:20]!r} is not 8 hex digits (the bits of a float)")
    theta = np.array([int(w, 16) for w in words], dtype=np.uint32).view(np.float32)
    if not np.all(np.isfinite(theta)):
        k = int(np.flatnonzero(~np.isfinite(theta))[0])
        raise DataError(f"adaptation dump: theta[{k}] is {theta[k]}, not a finite number")
    return lines[1].split(None, 1)[1].strip(), theta


def model_from_dump(model: FrictionModel, text: str) -> FrictionModel:
    """``model`` with the adapted parameters of a dump (``with_parameters``), its training record
    without the trained parameters' errors and with ``adapted_from``, the model's hash;
    ``ModelError`` when the dump belongs to another model or holds another number of parameters."""
    model_hash, theta = parse_dump(text)
    if model_hash != model.model_hash:
        raise ModelError(f"the dump was adapted from model {model_hash[:16]}, not from this one "
                         f"({model.model_hash[:16]}): read it back with the model.json it was "
                         "emitted from")
    n = trained_parameters(model).size
    if theta.size != n:
        raise ModelError(f"the dump holds {theta.size} parameters, this model adapts {n} "
                         f"({', '.join(parameter_names(model))})")
    adapted = with_parameters(model, theta.astype(float))
    # the training's errors describe the trained parameters, not these: the record says whence
    training = {k: v for k, v in model.training.items() if k != "metrics"}
    return replace(adapted, training={**training, "adapted_from": model.model_hash})
