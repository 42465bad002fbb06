"""The named physical effects (the diagnosis' vocabulary), by name: those of the axis's
mechanics (``mechanical``), those periodic in position (``position_series``: cogging, and a
friction level along the travel), those that change its friction (``friction_changes``), the
log's timing (``timing``), the actuator's saturation (``actuator``) and the contact's
pre-sliding (``contact``),
each with its force law, fit from a force residual and C expression."""
from __future__ import annotations

from typing import Dict, Type

from .actuator import ActuatorSaturation
from .base import Effect
from .contact import Presliding
from .friction_changes import DirectionAsymmetry, ExtraFrictionSource, FrictionalLag, ThermalDrift
from .mechanical import ConstantLoad, ForceConstantMismatch, InertiaMismatch
from .position_series import PositionFriction, PositionRipple
from .timing import SensorDelay

#: The effect library, by the exact names of the diagnosis vocabulary.
EFFECTS: Dict[str, Type[Effect]] = {cls.name: cls for cls in (
    PositionRipple, DirectionAsymmetry, ConstantLoad, InertiaMismatch, ForceConstantMismatch,
    ExtraFrictionSource, FrictionalLag, ThermalDrift, PositionFriction, SensorDelay,
    ActuatorSaturation, Presliding)}
#: The friction memories: a set of effects, with the model's own bristles, holds at most one.
MEMORIES = frozenset({FrictionalLag.name, Presliding.name})
#: The vocabulary: "none" and every effect name.
VOCABULARY = ("none",) + tuple(EFFECTS)
