"""Named physical effects a friction model may miss, and tables for what no named effect explains:
each defined once (force law, parameters, JSON, fit, C expression) and carried in model.json's
``effects`` list."""
from __future__ import annotations

from .library import (EFFECTS, PLAUSIBLE_FACTOR, VOCABULARY, ConstantLoad, DirectionAsymmetry, Effect,
                      ExtraFrictionSource, ForceConstantMismatch, FrictionalLag, InertiaMismatch,
                      PositionRipple, ThermalDrift, effect_from_dict, force_xv, model_effects,
                      validate_effects, with_effects)
from .signals import FrictionCurve, Signals
from .tables import TABLES, TableEffect, range_notes

__all__ = ["EFFECTS", "PLAUSIBLE_FACTOR", "VOCABULARY", "Effect", "PositionRipple", "DirectionAsymmetry",
           "ConstantLoad", "InertiaMismatch", "ForceConstantMismatch", "ExtraFrictionSource",
           "FrictionalLag", "ThermalDrift", "FrictionCurve", "Signals", "effect_from_dict", "force_xv",
           "model_effects", "validate_effects", "with_effects", "TABLES", "TableEffect", "range_notes"]
