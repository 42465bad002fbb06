"""The named physical effects (the diagnosis' vocabulary), by name: those of the axis's
mechanics (``mechanical``), those periodic in position (``position_series``: cogging, and a
friction level along the travel), those that change its friction (``friction_changes``), the
log's timing (``timing``) and the actuator's saturation (``actuator``),
each with its force law, fit from a force residual and C expression."""
from __future__ import annotations

from typing import Dict, Type

from .actuator import ActuatorSaturation
from .base import Effect
from .friction_changes import DirectionAsymmetry, ExtraFrictionSource, FrictionalLag, ThermalDrift
from .mechanical import ConstantLoad, ForceConstantMismatch, InertiaMismatch
from .position_series import PositionFriction, PositionRipple
from .timing import SensorDelay

#: The effect library, by the exact names of the diagnosis vocabulary.
EFFECTS: Dict[str, Type[Effect]] = {cls.name: cls for cls in (
    PositionRipple, DirectionAsymmetry, ConstantLoad, InertiaMismatch, ForceConstantMismatch,
    ExtraFrictionSource, FrictionalLag, ThermalDrift, PositionFriction, SensorDelay,
    ActuatorSaturation)}
#: The vocabulary: "none" and every effect name.
VOCABULARY = ("none",) + tuple(EFFECTS)
