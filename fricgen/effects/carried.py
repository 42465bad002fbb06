"""The effects a model carries: model.json's ``effects`` list validated by kind, the force
of eq. (3) with the effects in (v, x), and a model with effects added."""
from __future__ import annotations

from dataclasses import replace
from typing import Any, Dict, List, Sequence, Type

import numpy as np

from ..errors import ModelError
from .base import Effect
from .library import EFFECTS
from .signals import Signals

#: Every kind model.json's ``effects`` may hold: the named effects and the tables without a
#: physical name (``fricgen.effects.tables`` adds those when the package is imported).
KNOWN: Dict[str, Type[Effect]] = dict(EFFECTS)


def effect_from_dict(d: Any) -> Effect:
    """One validated effect of model.json's ``effects`` list."""
    if not isinstance(d, dict):
        raise ModelError(f"effects: each effect must be an object, got {type(d).__name__}")
    name = d.get("effect")
    if not isinstance(name, str) or name not in KNOWN:
        raise ModelError(f"effects: unknown effect {name!r}; known: {', '.join(KNOWN)}"[:200])
    unknown = sorted(set(d) - {"effect", "parameters"})
    if unknown:
        raise ModelError(f"effects[{name}]: unknown field {unknown[0]!r}"[:200])
    return KNOWN[name].from_dict(d)


def validate_effects(items: Any) -> List[dict]:
    """model.json's ``effects`` list, each entry validated and normalized (``to_dict``)."""
    if not isinstance(items, list):
        raise ModelError("effects must be a list")
    return [effect_from_dict(d).to_dict() for d in items]


def model_effects(model) -> List[Effect]:
    """The effects a model carries, as objects."""
    return [effect_from_dict(d) for d in model.effects]


def force_xv(model, v, x) -> np.ndarray:
    """F(v) plus every effect that is a function of (v, x): what NAME_force_xv computes."""
    v, x = np.broadcast_arrays(np.asarray(v, dtype=float), np.asarray(x, dtype=float))
    sig = Signals(model, x=x, v=v)
    total = model.force(v)
    for e in model_effects(model):
        if e.in_xv:
            total = total + e.force(sig)
    return total


def with_effects(model, effects: Sequence[Effect]):
    """A copy of ``model`` whose effects list is extended by ``effects``."""
    return replace(model, effects=tuple(model.effects) + tuple(e.to_dict() for e in effects))
