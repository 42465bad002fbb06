"""Training on a log with a ``load`` or ``temperature`` column: the one-input curve, then its
dependence on them (``fit.load_temperature``) where the data determine it and it predicts
held-out blocks better; the curve is fitted again on the samples brought to the reference
operating point (L = 0, T = T_ref), and the dependence again on that curve, while that fits
the samples closer; the dependence's last fit rescales the curves (the report says by how
much)."""
from __future__ import annotations

from dataclasses import replace
from typing import Callable, Optional

import numpy as np

from ..data.sweep import Sweep
from ..direction import Direction, Scaling
from ..fit.directions import BLOCK_WINDOWS
from ..fit.load_temperature import DependenceFit, fit_dependence
from ..model import FrictionModel
from ..units import LINEAR


#: How often, at most, the curve is fitted again at the reference operating point and the
#: dependence on it: each pass is kept only while it fits the samples closer than the last (the
#: curve's fit weighs the samples at the reference point, not as measured).
PASSES = 3


def _scaled(curve: Direction, levels: float, viscous: float) -> Direction:
    """The curve with its velocity-weakening part times ``levels`` and B times ``viscous``."""
    return Direction(curve.aim, Scaling(curve.scaling.k_in, curve.scaling.k_out / levels),
                     curve.viscous * viscous, curve.v_sat)


def _at_reference(dependence: DependenceFit, model: FrictionModel, sweep: Sweep,
                  conditions) -> np.ndarray:
    """The samples brought to L = 0, T = T_ref: f_ref = (f - c_v b g_v) / g_c + c_v b, g the
    dependence's factors at each row (b = B v of ``model``)."""
    inputs = dependence.inputs
    level, viscous = inputs.factors(sweep.v, conditions.get("load"), conditions.get("temperature"))
    b = dependence.scale[1] * model.viscous_force(sweep.v)
    return (sweep.f - b * viscous) / level + b


def fit_inputs(fitted, ident, sweep: Sweep, choice, fit_curves: Callable,
               progress: Optional[Callable[[str], None]] = None):
    """The curves and dependence of a log with operating-point columns (see the module):
    ``fit_curves(sweep, ident)`` -> (fitted, ident, sweep, choice) fits the one-input curves
    as ``fricgen.train`` does. Returns (fitted, ident, sweep, choice, curves, dependence)."""
    conditions = ident.conditions
    blocks = BLOCK_WINDOWS * ident.window
    independence = ident.independent / ident.n_kept

    def curve_of(fitted) -> FrictionModel:
        return FrictionModel.from_directions(*(f.curve for f in fitted.fits))

    def dependence_of(model, samples: Sweep, form=None) -> DependenceFit:
        return fit_dependence(model, samples.v, samples.f, conditions.get("load"),
                              conditions.get("temperature"), independence, blocks, form)

    if progress:
        progress("inputs: the load and temperature dependence, cross-validated")
    first = dependence_of(curve_of(fitted), sweep)
    if first.inputs is None:
        return fitted, ident, sweep, choice, [f.curve for f in fitted.fits], first
    raw = ident.sweep.f                                 # the friction samples with the offset
    best = (fitted, ident, sweep, choice, first)
    for _ in range(PASSES):                             # kept while they fit the samples closer
        fitted, ident, sweep, choice, final = best
        reference = _at_reference(final, curve_of(fitted), sweep, conditions) + (raw - sweep.f)
        fitted, ident, _, choice = fit_curves(Sweep(sweep.v, reference),
                                              replace(ident, sweep=Sweep(sweep.v, reference)))
        ident = replace(ident, sweep=Sweep(sweep.v, raw))
        sweep = ident.friction                          # as the curves' fit takes them out
        final = dependence_of(curve_of(fitted), sweep, first.form)
        if progress:
            progress(f"inputs: the curve at the reference point, RMS about the samples "
                     f"{final.rms:.4g} (was {best[-1].rms:.4g})")
        if not final.rms < best[-1].rms:
            break
        best = (fitted, ident, sweep, choice, final)
    fitted, ident, sweep, choice, final = best
    curves = [_scaled(f.curve, *final.scale) for f in fitted.fits]
    final = replace(final, undetermined=first.undetermined, cv_mse=first.cv_mse)
    return fitted, ident, sweep, choice, curves, final


def dependence_record(dependence: DependenceFit) -> dict:
    """model.json's ``training.inputs``: the form chosen, each parameter +- its standard error,
    what the data did not determine, the held-out error of each form."""
    return {"chosen": dependence.chosen,
            "estimates": {k: {"value": v, "se": se} for k, (v, se) in dependence.estimates.items()},
            "undetermined": dict(dependence.undetermined),
            "cv_mse": dict(dependence.cv_mse)}


def dependence_lines(dependence: DependenceFit, units=LINEAR) -> list:
    """The report's lines: the form chosen and its held-out errors, each dependence +- its
    standard error, what the data do not determine."""
    cv = ", ".join(f"{name} {np.sqrt(mse):.4g}" for name, mse in dependence.cv_mse.items())
    lines = [f"inputs    {dependence.chosen}, chosen on held-out blocks beside the one-input curve"
             + (f" (RMS {units.force}: {cv})" if cv else "")
             + (f"; the model's RMS about the samples {dependence.rms:.4g} {units.force}"
                if dependence.inputs is not None else "")]
    est = dependence.estimates
    inputs = dependence.inputs
    if inputs is not None and inputs.load is not None:
        d, b = est["load_driving"], est["load_back_driving"]
        lines.append(f"load      levels x (1 + s |L|): s = {d[0]:.4g} +- {d[1]:.2g} /{units.force} driving, "
                     f"{b[0]:.4g} +- {b[1]:.2g} back-driving; |L| saturates at "
                     f"{inputs.load.largest:.4g} {units.force}")
    if inputs is not None and inputs.temperature is not None:
        t = inputs.temperature
        c, v = est["temperature_levels"], est["temperature_viscous"]
        lines.append(f"temp.     exp(-k (T - {t.reference:g} degC)): k = {c[0]:.4g} +- {c[1]:.2g} /degC "
                     f"levels, {v[0]:.4g} +- {v[1]:.2g} /degC viscous; T clipped to "
                     f"{t.span[0]:.4g} to {t.span[1]:.4g} degC")
    c_l, c_v = dependence.scale
    if inputs is not None and max(abs(c_l - 1.0), abs(c_v - 1.0)) > 1e-3:
        lines.append(f"curves    in the model, the levels above x {c_l:.4g} and B x {c_v:.4g} (the "
                     "dependence's last fit)")
    for name, why in dependence.undetermined.items():
        lines.append(f"inputs    {name}: {why}")
    return lines
