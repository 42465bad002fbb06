"""The operating point a one-input model leaves out: with a log's ``load`` or ``temperature``
column, ``fricgen diagnose`` fits the dependence of the log's friction on them beside the
model's curve (``fit.load_temperature``, chosen by blocked cross-validation as training
chooses it) and names each dependence the held-out blocks ask for; the load is then taken out
of the drive force, so that the re-simulated diagnosis sees the friction alone."""
from __future__ import annotations

from typing import Dict, List, Optional, Tuple

import numpy as np

from ..data.inverse_dynamics import CONDITIONS, identify_log
from ..fit.directions import BLOCK_WINDOWS
from ..fit.load_temperature import DependenceFit, fit_dependence


def missing_dependence(model, columns: Dict[str, np.ndarray], mass: float,
                       force_constant: float) -> Optional[DependenceFit]:
    """The dependence on the log's load and temperature that ``model`` (without inputs) leaves
    out, identified with the axis's ``mass`` (``data.inverse_dynamics``, the current ``i``
    times ``force_constant``); None for a log without those columns."""
    if not any(c in columns for c in CONDITIONS):
        return None
    log = {k: columns[k] for k in ("t", "x", "v", *CONDITIONS) if k in columns}
    ident = identify_log({**log, "force": force_constant * columns["i"]}, mass=mass)
    friction = ident.sweep.f - (ident.body.offset or 0.0)
    return fit_dependence(model, ident.sweep.v, friction, ident.conditions.get("load"),
                          ident.conditions.get("temperature"), ident.independent / ident.n_kept,
                          BLOCK_WINDOWS * ident.window)


def without_load(columns: Dict[str, np.ndarray], force_constant: float) -> Dict[str, np.ndarray]:
    """The columns with the load taken out of the current (i - L / K) and the operating-point
    columns dropped."""
    out = {k: c for k, c in columns.items() if k not in CONDITIONS}
    if "load" in columns:
        out["i"] = columns["i"] - columns["load"] / force_constant
    return out


def named_lines(dependence: DependenceFit, unit: str) -> Tuple[List[str], str, List[str]]:
    """The report's lines on what the log asks for (each dependence named, +- its standard
    error, the held-out RMS friction error without and with it alone), the gap with all of them
    ('' for none), and what the log does not determine."""
    cv = {name: float(np.sqrt(mse)) for name, mse in dependence.cv_mse.items()}
    named, gap = [], ""
    if dependence.inputs is not None:
        est = dependence.estimates
        if dependence.inputs.load is not None:
            d, b = est["load_driving"], est["load_back_driving"]
            named.append(f"load_dependence: levels x (1 + s |L|), s = {d[0]:.3g} +- {d[1]:.2g} driving, "
                         f"{b[0]:.3g} +- {b[1]:.2g} back-driving /{unit} (alone: held-out friction RMS "
                         f"{cv['velocity only']:.4g} -> {cv['load']:.4g} {unit})")
        if dependence.inputs.temperature is not None:
            c, v = est["temperature_levels"], est["temperature_viscous"]
            named.append(f"temperature_dependence: exp(-k dT), k = {c[0]:.3g} +- {c[1]:.2g} levels, "
                         f"{v[0]:.3g} +- {v[1]:.2g} viscous /degC (alone: {cv['velocity only']:.4g} -> "
                         f"{cv['temperature']:.4g} {unit})")
        gap = (f"held-out friction RMS {cv['velocity only']:.4g} -> {cv[dependence.chosen]:.4g} {unit} "
               f"with {dependence.chosen}")
    return named, gap, [f"{name}: {why}" for name, why in dependence.undetermined.items()]
