"""Fleets of axes on Dask: identify every axis of a manifest (``manifest``) from its log
(``identification``), keep each result (``store``), and flag the axes whose friction changed by
more than the identification's own uncertainty (``drift``); a run (``run``) rewrites the table,
report.md and plots (``report``) from all the results. Dask (``distributed``) and pyarrow are the
optional extra ``fricgen[fleet]`` (``extra``), imported only when a fleet runs.
"""
from __future__ import annotations

from .drift import MIN_CHANGE, MONITORED, SIGMAS, drift_table
from .identification import friction_parameters, identify
from .manifest import Entry, read_manifest
from .run import FleetRun, run_fleet
from .store import result_key

__all__ = ["Entry", "FleetRun", "SIGMAS", "MIN_CHANGE", "MONITORED", "drift_table",
           "friction_parameters", "identify", "read_manifest", "result_key", "run_fleet"]
