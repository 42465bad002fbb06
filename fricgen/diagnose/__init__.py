"""Where simulation and measurement disagree: the force residual, the effects (named, or tables
without a name) that explain it, selected forward under a calibrated held-out test, the held-out
gap before and after, and the report."""
from __future__ import annotations

from .diagnoser import Diagnoser, diagnose
from .report import render_files, report_markdown

__all__ = ["Diagnoser", "diagnose", "render_files", "report_markdown"]
