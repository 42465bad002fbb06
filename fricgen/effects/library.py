"""The named physical effects (the diagnosis' vocabulary), by name: those of the axis's
mechanics (``mechanical``) and those that change its friction (``friction_changes``), each with
its force law, fit from a force residual and C expression."""
from __future__ import annotations

from typing import Dict, Type

from .base import Effect
from .friction_changes import DirectionAsymmetry, ExtraFrictionSource, FrictionalLag, ThermalDrift
from .mechanical import ConstantLoad, ForceConstantMismatch, InertiaMismatch, PositionRipple

#: The effect library, by the exact names of the diagnosis vocabulary.
EFFECTS: Dict[str, Type[Effect]] = {cls.name: cls for cls in (
    PositionRipple, DirectionAsymmetry, ConstantLoad, InertiaMismatch, ForceConstantMismatch,
    ExtraFrictionSource, FrictionalLag, ThermalDrift)}
#: The vocabulary: "none" and every effect name.
VOCABULARY = ("none",) + tuple(EFFECTS)
