"""Adaptive backstepping position control with friction compensation (section 6), in Python and
as the C runtime through cffi, and the closed loops that compare compensation variants."""
from __future__ import annotations

from .backstepping import AdaptiveBackstepping
from .c_controller import CController, build_controller, c_controllers
from .loop import ClosedLoop, compare, compensations, default_axis, simulate

__all__ = ["AdaptiveBackstepping", "CController", "build_controller", "c_controllers",
           "ClosedLoop", "compare", "compensations", "default_axis", "simulate"]
