"""Friction data: sweeps, motion logs, B identification and the [F9] normalization, and the
paper's benchmark."""
from __future__ import annotations

from ..errors import DataError
from .benchmark import Benchmark, synthesize_benchmark
from .motionlog import MotionLog, log_csv_text, read_log, read_log_csv
from .stribeck_range import StribeckRange, choose_vs_max
from .training_set import SAT_FACTOR, Dataset, identify_viscous, prepare
from .sweep import MIN_ROWS, Sweep, read_sweep_csv, sweep_csv_text

__all__ = ["DataError", "Benchmark", "synthesize_benchmark", "MotionLog", "log_csv_text",
           "read_log", "read_log_csv", "SAT_FACTOR", "Dataset", "StribeckRange", "choose_vs_max", "identify_viscous",
           "prepare", "MIN_ROWS", "Sweep", "read_sweep_csv", "sweep_csv_text"]
