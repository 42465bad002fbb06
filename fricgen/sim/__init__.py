"""Simulated axes: the motor axis of [C1] and its integrators (``axis``), its
force law from a friction curve and named effects (``effect_law``), references and synthesized
motion logs."""
from __future__ import annotations

from .axis import MotorAxis
from .logsynth import LogSpec, synthesize_log
from .scenarios import Scenario, make_scenario

__all__ = ["MotorAxis", "LogSpec", "synthesize_log", "Scenario", "make_scenario"]
