"""Trained networks, the AIM of [F3]: each kind evaluates itself and owns its JSON.

``KINDS`` maps model.json's ``aim.kind`` to the class; ``network_from_dict`` dispatches on it.
"""
from __future__ import annotations

from typing import Any, Dict

from ..errors import ModelError
from .anfis import AnfisNetwork
from .elm import ElmNetwork
from .stribeck import StribeckCurve

#: The network kinds model.json may hold, by ``aim.kind``.
KINDS: Dict[str, Any] = {cls.kind: cls for cls in (ElmNetwork, AnfisNetwork, StribeckCurve)}


def network_from_dict(d: Any):
    """The validated network of model.json's ``aim`` object, by its ``kind`` (``KINDS``).

    Parameters
    ----------
    d : dict
        The ``aim`` object: ``kind`` and that kind's fields.

    Returns
    -------
    ElmNetwork, AnfisNetwork or StribeckCurve
        ``ModelError`` naming the field when ``d`` is invalid.

    Examples
    --------
    >>> from fricgen.networks import StribeckCurve, network_from_dict
    >>> curve = StribeckCurve("gauss", offset=0.5, amplitudes=[0.5], stribeck=[0.2])
    >>> network_from_dict(curve.to_dict()).to_dict() == curve.to_dict()
    True
    """
    if not isinstance(d, dict):
        raise ModelError("missing or invalid field 'aim' (an object)")
    kind = d.get("kind")
    if not isinstance(kind, str) or kind not in KINDS:
        raise ModelError(f"aim.kind must be one of {sorted(KINDS)}, got {kind!r}"[:200])
    return KINDS[kind].from_dict(d)


__all__ = ["KINDS", "network_from_dict", "ElmNetwork", "AnfisNetwork", "StribeckCurve"]
