"""The effects a model carries: model.json's ``effects`` list validated by kind, the force
of [F3] with the effects in (v, x), and a model with effects added."""
from __future__ import annotations

from dataclasses import replace
from typing import Any, Dict, List, Optional, Sequence, Type

import numpy as np

from ..errors import ModelError
from .base import Effect
from .library import EFFECTS
from .mechanical import ConstantLoad
from .signals import Signals

#: Every kind model.json's ``effects`` may hold: the named effects but the contact's (a
#: pre-sliding is the model's ``presliding``) and the tables without a physical name
#: (``fricgen.effects.tables`` adds those when the package is imported).
KNOWN: Dict[str, Type[Effect]] = {name: cls for name, cls in EFFECTS.items() if not cls.via_contact}


def effect_from_dict(d: Any) -> Effect:
    """One validated effect of model.json's ``effects`` list.

    Parameters
    ----------
    d : dict
        ``{"effect": name, "parameters": {...}}``.

    Returns
    -------
    Effect
        ``ModelError`` naming the field when ``d`` is invalid.

    Examples
    --------
    >>> from fricgen.effects import ConstantLoad, effect_from_dict
    >>> effect_from_dict(ConstantLoad(load=5.0).to_dict())
    ConstantLoad(load=5.0)
    """
    if not isinstance(d, dict):
        raise ModelError(f"effects: each effect must be an object, got {type(d).__name__}")
    name = d.get("effect")
    if isinstance(name, str) and name in EFFECTS and EFFECTS[name].via_contact:
        raise ModelError(f"effects: {name} is carried as the model's 'presliding' (its bristles), "
                         "not among its effects")
    if not isinstance(name, str) or name not in KNOWN:
        raise ModelError(f"effects: unknown effect {name!r}; known: {', '.join(KNOWN)}"[:200])
    unknown = sorted(set(d) - {"effect", "parameters"})
    if unknown:
        raise ModelError(f"effects[{name}]: unknown field {unknown[0]!r}"[:200])
    return KNOWN[name].from_dict(d)


def validate_effects(items: Any) -> List[dict]:
    """model.json's ``effects`` list, each entry validated and normalized (``to_dict``).

    Parameters
    ----------
    items : list of dict
        The list as read.

    Returns
    -------
    list of dict

    Examples
    --------
    >>> from fricgen.effects import validate_effects
    >>> validate_effects([{"effect": "constant_load", "parameters": {"load": 5}}])[0]["effect"]
    'constant_load'
    """
    if not isinstance(items, list):
        raise ModelError("effects must be a list")
    return [effect_from_dict(d).to_dict() for d in items]


def model_effects(model) -> List[Effect]:
    """The effects a model carries, as objects.

    Parameters
    ----------
    model : FrictionModel
        The model.

    Returns
    -------
    list of Effect

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.effects import ConstantLoad
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5, random_state=0))
    >>> from fricgen.effects import model_effects, with_effects
    >>> model_effects(with_effects(model, [ConstantLoad(load=5.0)]))
    [ConstantLoad(load=5.0)]
    """
    return [effect_from_dict(d) for d in model.effects]


def force_xv(model, v, x) -> np.ndarray:
    """F(v) of [F3] plus every effect that is a function of (v, x): what the emitted
    NAME_force_xv computes.

    Parameters
    ----------
    model : FrictionModel
        The model and its effects.
    v : array_like
        Velocity (m/s).
    x : array_like
        Position (m), broadcast with ``v``.

    Returns
    -------
    ndarray
        Force (N).

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.effects import ConstantLoad
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5, random_state=0))
    >>> from fricgen.effects import force_xv, with_effects
    >>> loaded = with_effects(model, [ConstantLoad(load=5.0)])
    >>> round(float(force_xv(loaded, 0.03, 0.0) - model.force(0.03)), 6)
    5.0
    """
    v, x = np.broadcast_arrays(np.asarray(v, dtype=float), np.asarray(x, dtype=float))
    sig = Signals(model, x=x, v=v)
    total = model.force(v)
    for e in model_effects(model):
        if e.in_xv:
            total = total + e.force(sig)
    return total


def with_effects(model, effects: Sequence[Effect]):
    """A copy of ``model`` whose effects list is extended by ``effects``; a pre-sliding
    (``contact.Presliding``) becomes the model's ``presliding``, its bristles, and a
    ``constant_load`` beside one the model holds is the change of that load: the model holds
    one load, their sum.

    Parameters
    ----------
    model : FrictionModel
        The model.
    effects : sequence of Effect
        Effects to add.

    Returns
    -------
    FrictionModel

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.effects import ConstantLoad
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5, random_state=0))
    >>> from fricgen.effects import with_effects
    >>> len(with_effects(model, [ConstantLoad(load=5.0)]).effects), len(model.effects)
    (1, 0)
    """
    contact = [e for e in effects if e.via_contact]
    model = replace(model, presliding=contact[-1].bristles) if contact else model
    added = [e for e in effects if not e.via_contact]
    held = list(model.effects)
    at = next((k for k, d in enumerate(held) if d.get("effect") == ConstantLoad.name), None)
    change = [e for e in added if e.name == ConstantLoad.name]
    if at is not None and change:
        load = effect_from_dict(held[at]).load
        held[at] = ConstantLoad(load=sum((e.load for e in change), load)).to_dict()
        added = [e for e in added if e.name != ConstantLoad.name]
    return replace(model, effects=tuple(held) + tuple(e.to_dict() for e in added))


def offset_left_out(model) -> Optional[float]:
    """The constant force of the model's axis record that no ``constant_load`` effect carries.

    Parameters
    ----------
    model : FrictionModel
        The model.

    Returns
    -------
    float or None
        ``training.axis.offset`` (N: the constant force a symmetric curve leaves out, or a load
        taken out of the curves), or None when the record holds none or an effect carries one.

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.effects import offset_left_out
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> offset_left_out(fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5)))
    """
    axis = model.axis
    if axis is None or axis.offset is None or \
            any(e.name == ConstantLoad.name for e in model_effects(model)):
        return None
    return axis.offset
