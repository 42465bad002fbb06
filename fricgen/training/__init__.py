"""Training as a library call: a sweep or a motion log in, a ``FrictionModel`` and its fit report
out (``trainer``). The report (``report``) is what ``fricgen train`` prints, and its ``training``
record (``record``) what model.json keeps (``fricgen.cli.train`` only formats and writes them).
"""
from __future__ import annotations

from .report import FitReport
from .trainer import train

__all__ = ["FitReport", "train"]
