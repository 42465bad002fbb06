"""``fricgen train LOG --dynamic``: the default static model of a log, then the LuGre bristles
on its curve (``fit.presliding``) where the log determines them; where it does not, the
static model alone and one line that says why."""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable, Mapping, Tuple

import numpy as np

from ..errors import DataError, ModelError, UsageError
from ..fit.presliding import identify_presliding, settled_rows
from ..model import FrictionModel
from ..units import units_of
from .report import FitReport
from .with_cogging import log_force


#: How often the static curve is fitted again on the rows where the bristles have settled.
STATIC_PASSES = 2


@dataclass(frozen=True)
class DynamicReport:
    """The model (static curve, bristles where determined), the report's text and notes."""

    model: FrictionModel
    text: str
    warnings: Tuple[str, ...]


def train_dynamic(columns: Mapping[str, np.ndarray], *, rotary: bool, force_constant,
                  train_friction: Callable[[Mapping[str, np.ndarray]], FitReport]) -> DynamicReport:
    """The static fit (``train_friction(columns, use=None)``, ``use`` a mask of the rows to
    identify it on), then its bristles (see the module)."""
    if "x" not in columns or "t" not in columns:
        raise UsageError("--dynamic needs a motion log with time t and position x (the bristles "
                         "deflect over distances of encoder counts)")
    units = units_of(rotary)
    report = train_friction(columns)
    ident = report.identification
    force = log_force(columns, force_constant if force_constant is not None else
                      (ident.force_constant[0] if ident.force_constant else None))
    dt = ident.sample_time

    def bristles_of(static: FitReport, falling: bool = False):
        return identify_presliding(columns["t"], columns["x"], force, static.model,
                                   mass=static.identification.body.mass,
                                   window=static.identification.window, falling=falling)
    fit = bristles_of(report, falling=True)
    for _ in range(STATIC_PASSES):          # the static curve again, on the settled rows only
        if fit.bristles is None:
            break
        use = settled_rows(columns["x"], report.model, fit.bristles, dt, ident.window,
                           fit.position_window)
        try:
            settled = train_friction(columns, use=use)
        except (DataError, ModelError):     # too few settled rows: the curve of all rows stays
            break
        report, fit = settled, bristles_of(settled)
    stiffness_unit = f"{units.force}/{units.position}"
    lines = [f"pre-sliding: {fit.presliding_rows} rows within the pre-sliding distance after a "
             f"reversal; residual RMS {fit.rms_dynamic:.4g} {units.force} with bristles, "
             f"{fit.rms_static:.4g} with the static curve"]
    record = {"stiffness": fit.stiffness, "stiffness_se": fit.stiffness_se,
              "presliding_rows": fit.presliding_rows}
    model = report.model
    if fit.bristles is None:
        lines.append(f"pre-sliding: not identified: {fit.reason}; the model is static")
        record = {"left_out": fit.reason, "presliding_rows": fit.presliding_rows}
    else:
        b = fit.bristles
        lines.append(f"pre-sliding: stiffness sigma0 = {b.stiffness:.4g} +- {fit.stiffness_se:.2g} "
                     f"{stiffness_unit} (pre-sliding distance "
                     f"{b.presliding_distance(float(model.stribeck(0.0))):.3g} {units.position})")
        record.update(damping=b.damping, damping_se=fit.damping_se if b.damping > 0 else None,
                      damping_speed=b.damping_speed)
        if b.damping > 0:
            fades = ("constant" if b.damping_speed is None else
                     f"fading beyond v_d = {b.damping_speed:.3g} {units.speed}")
            lines.append(f"pre-sliding: damping sigma1 = {b.damping:.4g} +- {fit.damping_se:.2g} "
                         f"{units.viscous} at rest, {fades}")
        else:
            lines.append(f"pre-sliding: damping sigma1 not determined by this log ({fit.damping:.3g} "
                         f"+- {fit.damping_se:.2g}: {fit.damping_reason}): left at 0")
        model = replace(model, presliding=b)
    model = replace(model, training={**model.training, "presliding": record})
    return DynamicReport(model=model, text=report.text + "\n" + "\n".join(lines),
                         warnings=tuple(report.warnings))
