"""Named physical effects a friction model may miss, and tables for what no named effect explains:
each defined once (force law, parameters, JSON, fit, C expression) and carried in model.json's
``effects`` list."""
from __future__ import annotations

from .actuator import ActuatorSaturation
from .base import PLAUSIBLE_FACTOR, Effect
from .cogging_map import CoggingMap
from .carried import (effect_from_dict, force_xv, model_effects, offset_left_out, validate_effects,
                      with_effects)
from .friction_changes import DirectionAsymmetry, ExtraFrictionSource, FrictionalLag, ThermalDrift
from .contact import Presliding
from .library import EFFECTS, MEMORIES, VOCABULARY
from .mechanical import ConstantLoad, ForceConstantMismatch, InertiaMismatch
from .position_series import PositionFriction, PositionRipple, PositionSeries
from .signals import FrictionCurve, Signals
from .timing import SensorDelay
from .tables import TABLES, TableEffect, range_notes

__all__ = ["EFFECTS", "PLAUSIBLE_FACTOR", "VOCABULARY", "Effect", "ActuatorSaturation", "PositionRipple", "PositionFriction",
           "PositionSeries", "DirectionAsymmetry",
           "ConstantLoad", "InertiaMismatch", "ForceConstantMismatch", "ExtraFrictionSource",
           "FrictionalLag", "ThermalDrift", "SensorDelay", "FrictionCurve", "Signals", "effect_from_dict",
           "force_xv", "model_effects", "offset_left_out", "validate_effects", "with_effects", "TABLES",
           "TableEffect", "range_notes", "CoggingMap", "MEMORIES", "Presliding"]
