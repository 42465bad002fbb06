"""Read back what the firmware adapted: the text ``fric_adapt_export`` writes, turned into a
model.json that ``eval``, ``emit`` and ``diagnose`` accept.

The dump (``fric_adapt.h``) is four lines::

    fricgen-adapt-dump 2
    model <the hash of the model the firmware was emitted from>
    theta <8 hex digits per parameter: the float32 bits of theta[0 .. n-1]>
    scale <8 hex digits: the float32 bits of the controller's k_hat>

theta is the model's output parameters (``fricgen.control.regressor``: beta_k and B of an ELM,
a_k, c and B of the grey-box [F1], then the axis's offset where the model records its axis);
the hidden layer, the Stribeck velocities, the slope and
the scaling are the model's own. The loop applies k_hat F(v) [C9]: k_hat scales the
compensation, so it and theta trade against each other (only their product is determined), and
the model read back is k_hat F, the friction the loop applies. A dump of version 1 (three
lines, no scale) reads as k_hat = 1. The hex bits carry every float exactly.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Tuple

import numpy as np

from ..errors import DataError, ModelError
from ..model import FrictionModel
from .regressor import parameter_names, trained_parameters, with_offset, with_parameters

#: The first line of a dump, with its format version; and that of the version before (no scale).
MAGIC = "fricgen-adapt-dump 2"
MAGIC_1 = "fricgen-adapt-dump 1"


def _words(values) -> str:
    return " ".join(f"{int(u):08x}" for u in np.asarray(values, dtype=np.float32).view(np.uint32))


def dump_text(model_hash: str, theta, scale: float = 1.0) -> str:
    """The dump ``fric_adapt_export`` writes for float32 parameters ``theta`` and k_hat ``scale``."""
    return f"{MAGIC}\nmodel {model_hash}\ntheta {_words(theta)}\nscale {_words([scale])}\n"


def _floats(line: str, name: str) -> np.ndarray:
    """The float32 values of a line ``name <hex> ...``; ``DataError`` naming the first problem."""
    words = line.split()[1:]
    if not words:
        raise DataError(f"adaptation dump: the {name} line holds no parameter")
    bad = next((w for w in words if len(w) != 8 or any(c not in "0123456789abcdefABCDEF" for c in w)), None)
    if bad is not None:
        raise DataError(f"adaptation dump: {bad[:20]!r} is not 8 hex digits (the bits of a float)")
    values = np.array([int(w, 16) for w in words], dtype=np.uint32).view(np.float32)
    if not np.all(np.isfinite(values)):
        k = int(np.flatnonzero(~np.isfinite(values))[0])
        raise DataError(f"adaptation dump: {name}[{k}] is {values[k]}, not a finite number")
    return values


def parse_dump(text: str) -> Tuple[str, np.ndarray, float]:
    """(model hash, theta as float32, k_hat) of a dump; ``DataError`` naming the first problem."""
    lines = [line.strip() for line in text.strip().splitlines()]
    if not lines or lines[0] not in (MAGIC, MAGIC_1):
        raise DataError(f"not an adaptation dump: the first line must be {MAGIC!r}, got "
                        f"{(lines[0] if lines else '')[:40]!r}")
    scaled = lines[0] == MAGIC
    if len(lines) != 3 + scaled or not lines[1].startswith("model ") or \
            not lines[2].startswith("theta") or (scaled and not lines[3].startswith("scale")):
        raise DataError("adaptation dump: expected the lines 'model <hash>', 'theta <hex> ...'"
                        + (" and 'scale <hex>'" if scaled else ""))
    theta = _floats(lines[2], "theta")
    scale = 1.0
    if scaled:
        values = _floats(lines[3], "scale")
        if values.size != 1 or not values[0] > 0:
            raise DataError(f"adaptation dump: the scale (the controller's k_hat) must be one number "
                            f"> 0, got {' '.join(str(x) for x in values)[:40]}: at k_hat <= 0 the "
                            "loop applies no friction model")
        scale = float(values[0])
    return lines[1].split(None, 1)[1].strip(), theta, scale


def model_from_dump(model: FrictionModel, text: str) -> FrictionModel:
    """``model`` with the adapted parameters of a dump (``with_parameters``) times its scale
    (``scaled``: the friction the loop applies), its training record
    without the trained parameters' errors and with ``adapted_from``, the model's hash;
    ``ModelError`` when the dump belongs to another model or holds another number of parameters."""
    model_hash, theta, scale = parse_dump(text)
    if model_hash != model.model_hash:
        raise ModelError(f"the dump was adapted from model {model_hash[:16]}, not from this one "
                         f"({model.model_hash[:16]}): read it back with the model.json it was "
                         "emitted from")
    n = trained_parameters(model).size
    if theta.size != n:
        raise ModelError(f"the dump holds {theta.size} parameters, this model adapts {n} "
                         f"({', '.join(parameter_names(model))})")
    adapted = scaled(with_parameters(model, theta.astype(float)), scale)
    # the training's errors describe the trained parameters, not these: the record says whence
    training = {k: v for k, v in adapted.training.items() if k != "metrics"}
    return replace(adapted, training={**training, "adapted_from": model.model_hash})


def scaled(model: FrictionModel, k: float) -> FrictionModel:
    """``model`` whose force is k F(v) (k > 0): [F3]'s K_out divided by k, B times k (each
    direction's of an asymmetric model), and the axis's offset times k (the loop applies k_hat
    times it too)."""
    if k == 1.0:
        return model
    negative = model.negative
    if negative is not None:
        negative = replace(negative, scaling=replace(negative.scaling, k_out=negative.scaling.k_out / k),
                           viscous=negative.viscous * k)
    if model.axis is not None and model.axis.offset is not None:
        model = with_offset(model, model.axis.offset * k)
    return replace(model, scaling=replace(model.scaling, k_out=model.scaling.k_out / k),
                   viscous=model.viscous * k, negative=negative, recorded_hash=None)
