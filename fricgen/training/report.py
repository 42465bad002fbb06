"""The fit report: ``FitReport``, a trained model with the text ``fricgen train`` prints (the
data, the symmetry chosen, each curve's model, errors and C cost, and warnings on the data).

What the report says of an estimator is registered per estimator type (``functools.singledispatch``):
a new estimator adds its functions here rather than a branch to a chain.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import singledispatch
from typing import Optional, Tuple

from ..codegen.cost import ADAPT_MAX_PARAMS as MAX_PARAMS
from ..codegen.cost import adapt_instructions, cortex_m4f_instructions, host_ns
from ..codegen.parity import float32_problem
from ..data.identification import COMPENSATED, Identification
from ..data.outliers import OUTLIER_SIGMAS
from ..data.sweep import Sweep
from ..data.training_set import SAT_FACTOR
from ..fit import DefaultRegressor, StribeckRegressor
from ..fit.directions import CV_FOLDS, TEXTBOOK_ASYMMETRY, DirectionsFit
from ..fit.law_choice import LawChoice
from ..fit.load_temperature import DependenceFit
from ..fit.textbook import TextbookRegressor
from ..units import LINEAR
from ..fit.stribeck import XS_MAX
from ..model import FrictionModel
from .with_inputs import dependence_lines


@dataclass(frozen=True)
class FitReport:
    """A trained friction model with its fit report.

    ``str(report)`` is the text ``fricgen train`` prints; ``report.training`` is the record
    model.json keeps (``report.model.training``).

    Parameters
    ----------
    model : FrictionModel
        The fitted model [F3], symmetric or one curve per direction.
    fit : DirectionsFit
        The fitted curves, each with its [F9] training set and fitted estimator, and how the
        symmetry was chosen.
    identification : Identification or None
        For a motion log, how its friction samples were obtained by inverse dynamics
        [C1]: rows kept, smoothing, the mass and constant force with standard
        errors; None for a sweep.
    sweep : Sweep or None
        The friction samples fitted: the sweep given, or those a log's inverse dynamics gave.
    warnings : tuple of str
        Notes on the data that do not stop training (a log too fast to show the Stribeck region).
    law : LawChoice or None
        How the default chose its law among the textbook laws and the multi-source fit
        (``fricgen.fit.law_choice``); None when an estimator was given.
    inputs : DependenceFit or None
        For a log with load or temperature columns, the dependence tried on them
        (``fricgen.fit.load_temperature``): the form kept, its estimates and standard errors,
        what the data do not determine; None otherwise.

    Examples
    --------
    >>> import fricgen
    >>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
    >>> report = fricgen.train(sweep, vs_max=0.02, estimator=fricgen.StribeckRegressor())
    >>> print(str(report).splitlines()[0])
    data      202 training points in [0, v_sat], v_sat = 0.06 m/s
    >>> report.training["method"], report.model.v_sat
    ('stribeck', 0.06)
    """

    model: FrictionModel
    fit: DirectionsFit
    identification: Optional[Identification] = None
    sweep: Optional[Sweep] = None
    warnings: Tuple[str, ...] = field(default=())
    #: How the default chose its law (``fit.law_choice``); None for an estimator given.
    law: Optional[LawChoice] = None
    #: The load and temperature dependence tried, for a log with those columns
    #: (``fit.load_temperature``); None otherwise.
    inputs: Optional[DependenceFit] = None

    @property
    def training(self) -> dict:
        """model.json's ``training`` record: method, seed, source, the choice and its errors."""
        return self.model.training

    @property
    def text(self) -> str:
        """The report ``fricgen train`` prints: data, symmetry, each curve's model and errors."""
        ident, fitted = self.identification, self.fit
        units = self.model.units
        reports = [] if ident is None else [ident.summary(units), ident.offset_line(fitted.asymmetric, units)]
        axis = self.training.get("axis") or {}
        if ident is None and axis.get("offset") is not None:
            reports.append(f"offset    {axis['offset']:.4g} +- {axis['offset_se']:.2g} {units.force}: a constant "
                           f"{units.effort} beside the friction (a sensor's zero, an incline, a cable): "
                           "one direction's points reach v = 0 below 0, where no friction pushes the "
                           f"axis; the curves are fitted to the {units.effort} less it ({COMPENSATED})")
        if (self.training.get("log") or {}).get("force_held"):
            reports.insert(1, f"{units.effort:10s}held over each sample (a set-point): taken as the mean of "
                              "each row and the row before, at the motion's sample times")
        if self.law is not None:
            reports.append(self.law.line(units.force))
        if fitted.chosen_by != "textbook":
            reports.append(choice_line(fitted, log=ident is not None, unit=units.force))
        curves = [self.training] + ([self.training["negative"]] if fitted.asymmetric else [])
        labels = ("v > 0:", "v < 0:") if fitted.asymmetric else ("",)
        for label, f, curve in zip(labels, fitted.fits, curves):
            text = curve_report(f.dataset, f.estimator, curve["metrics"], units)
            reports.append(text if not label else
                           f"{label}\n" + "\n".join("  " + t for t in text.splitlines()))
        if self.inputs is not None:
            reports.extend(dependence_lines(self.inputs, units))
        problem = float32_problem(self.model)
        if problem:
            reports.append(f"float32   {problem}; emit refuses it")
        return "\n".join(r for r in reports if r)

    def __str__(self) -> str:
        return self.text


@singledispatch
def model_lines(estimator, dataset, units=LINEAR) -> list:
    """The report's lines on the fitted model (an ELM's size, C and weights by default), its
    quantities in ``units``."""
    return [f"model     {estimator.n_hidden} {estimator.activation} neurons, "
            f"{estimator.scheme}, C = {estimator.C_:.3g}",
            f"weights   ||beta|| = {estimator.beta_norm_:.4g}, log10 cond(H^T H) = "
            f"{estimator.log10_cond_:.2f}",
            ]


@model_lines.register
def _(estimator: DefaultRegressor, dataset, units=LINEAR) -> list:
    return ([f"chose     {estimator.why()}", f"outliers  {estimator.outlier_note()}"]
            + model_lines(estimator.chosen_, dataset, units))


@model_lines.register
def _(estimator: StribeckRegressor, dataset, units=LINEAR) -> list:
    """The grey-box model of [F1] in the axis's units, each parameter +- its standard error."""
    net, se = estimator.network_, estimator.standard_errors_
    k_in, k_out = dataset.scaling.k_in, dataset.scaling.k_out
    broad = ("" if estimator.xs_max_ <= XS_MAX else
             f", a broad source allowed beyond vs_max (v_s up to {estimator.xs_max_ / k_in:.4g} "
             f"{units.speed})")
    lines = [f"model     grey-box [F1]: {net.n_sources} {net.shape} source(s){broad}, "
             f"{_origin(estimator)}",
             f"coulomb   sum f_c = {_estimate(net.offset / k_out, se['offset'] / k_out, units.force)}"]
    for k in range(net.n_sources):
        lines.append(f"source {k + 1:<2d} f_s - f_c = "
                     f"{_estimate(net.amplitudes[k] / k_out, se['amplitudes'][k] / k_out, units.force)}, "
                     f"v_s = {_estimate(net.stribeck[k] / k_in, se['stribeck'][k] / k_in, units.speed)}")
    return lines


@singledispatch
def cost_lines(estimator) -> list:
    """The C cost per call of an ELM (``fricgen.codegen.cost``, fitted to ELM kernels), and per
    update of its online adaptation."""
    return [call_cost(estimator.n_hidden, estimator.activation), adapt_cost(estimator.n_hidden)]


@cost_lines.register
def _(estimator: DefaultRegressor) -> list:
    return cost_lines(estimator.chosen_)


@cost_lines.register
def _(estimator: StribeckRegressor) -> list:
    return []


@cost_lines.register
def _(estimator: TextbookRegressor) -> list:
    return []


def call_cost(n_hidden: int, activation: str) -> str:
    """The report's line on the C cost per ``NAME_force`` call (``fricgen.codegen.cost``)."""
    units = "" if activation == "sigmoid" else " (cost model measured on sigmoid units)"
    return (f"C cost    about {cortex_m4f_instructions(n_hidden):.0f} instructions per call on "
            f"Cortex-M4F ({cortex_m4f_instructions(n_hidden, 'fast'):.0f} with --activation-impl "
            f"fast), {host_ns(n_hidden):.0f} ns on the reference x86-64 host{units}")


def adapt_cost(n_hidden: int) -> str:
    """The report's line on the cost of ``emit --adapt`` per update (``fricgen.codegen.cost``)."""
    if n_hidden + 2 > MAX_PARAMS:                     # B and the axis's offset
        return (f"adapt     emit --adapt holds at most {MAX_PARAMS - 2} neurons "
                f"(--max-neurons {MAX_PARAMS - 2})")
    return (f"adapt     emit --adapt: about {adapt_instructions(n_hidden):.0f} instructions per "
            f"update on Cortex-M4F (Lyapunov; RLS {adapt_instructions(n_hidden, 'rls'):.0f}), "
            "beside the controller step")


def error_line(errors: dict, unit: str = "N") -> str:
    """The training and validation errors (normalized, and in N) to four significant digits:
    a fixed number of decimals would print a fit to clean data as 0.0000 N."""
    return (f"errors    E_train = {errors['e_train']:.4g} ({errors['e_train_newton']:.4g} {unit}), "
            f"{errors['e_validation_kind']} = {errors['e_loo']:.4g} ({errors['e_loo_newton']:.4g} {unit})")


def curve_report(dataset, estimator, errors: dict, units=LINEAR) -> str:
    """The report of one fitted curve: its data, B, the [F9] scaling, the model, the errors
    (a textbook law's in ``units``)."""
    s = dataset.scaling
    chosen = dataset.stribeck_range
    vs_note = " (vs_max chosen from the data; pass --vs-max to set it)" if chosen else ""
    joint = chosen is not None and not chosen.linear_region
    if isinstance(estimator, TextbookRegressor):
        return "\n".join([f"data      {dataset.x.size} points, fastest {dataset.v_sat:.6g} {units.speed}",
                           f"model     {estimator.law_.describe(units)}",
                           error_line(errors, units.force)])
    lines = [
        f"data      {dataset.x.size} training points in [0, v_sat], v_sat = {dataset.v_sat:.6g} {units.speed}"
        f"{vs_note}" + (f"; the {dataset.n_rows} rows there averaged in bins of equal count"
                        if dataset.binned else ""),
    ] + ([f"vs_max    {chosen.describe(units)}"] if chosen else []) + [
        f"viscous   B = {dataset.viscous:.6g} {units.viscous} "
        + ("fitted with the Stribeck sources (no linear high-speed region)" if joint else
           f"from {dataset.n_high_speed} high-speed points")
        + (f" ({dataset.n_outliers} rejected as gross outliers, > {OUTLIER_SIGMAS:g} robust sd "
           "off the line)" if dataset.n_outliers else ""),
        f"scaling   K_in = {s.k_in:.6g} 1/({units.speed}), K_out = {s.k_out:.6g} 1/{units.force}",
    ]
    return "\n".join(lines + model_lines(estimator, dataset, units) + [error_line(errors, units.force)]
                     + cost_lines(estimator))


def _origin(estimator: StribeckRegressor) -> str:
    """Where the grey-box curve comes from: the best fit by AICc, or the average of the close ones."""
    n, (shape, s, _) = len(estimator.weights_), estimator.best_
    if n == 1:
        return f"chosen by AICc among {len(estimator.candidates_)} fits"
    return (f"matching the AICc-weighted average of {n} close fits among "
            f"{len(estimator.candidates_)} (best alone: {s} {shape}, weight "
            f"{estimator.weights_[estimator.best_]:.2f})")


def _estimate(value: float, se: float, unit: str) -> str:
    """'value +- se unit', or a word where the data do not determine the parameter."""
    return (f"{value:.5g} +- {se:.2g} {unit}" if math.isfinite(se) else
            f"{value:.5g} {unit} (not determined by the data)")


def choice_line(fitted: DirectionsFit, log: bool = False, unit: str = "N") -> str:
    """How the model's symmetry was chosen (nothing for a sweep of one direction, as the
    paper's; a ``log`` that moves one way is told that its curve is mirrored)."""
    kind = "asymmetric (one curve per direction)" if fitted.asymmetric else "symmetric"
    if fitted.chosen_by == "one direction only":
        return ("symmetry symmetric: the log moves one way only; its curve is mirrored to the "
                "other direction, which the data do not show" if log else "")
    if fitted.chosen_by.startswith("asymmetric model not fittable"):
        return f"symmetry {kind}: the {fitted.chosen_by}"
    if fitted.chosen_by == TEXTBOOK_ASYMMETRY:
        return (f"symmetry {kind}: the textbook laws per direction beat their symmetric twins "
                "beyond the noise")
    if fitted.cv_rmse is None:
        return f"symmetry {kind}, as asked"
    sym, asym = fitted.cv_rmse
    return (f"symmetry {kind} by {CV_FOLDS}-fold {fitted.chosen_by}: held-out RMS "
            f"{sym:.4g} {unit} symmetric, {asym:.4g} {unit} asymmetric")


#: A weight of the position that leaves at most this share of the law's residual is warned of
#: (the report's gravity line names any that leaves at most WEIGHT_SHARE).
WEIGHT_WARNING = 0.5


def gravity_warning(ident: Identification, units=LINEAR) -> str:
    """One line when a joint's log (x in rad) trained without --gravity holds a weight of the
    position that explains most of what the friction law leaves (``Identification.weight``):
    the friction samples then carry the link's weight, a model off by about its amplitude."""
    if ident.weight is None or units.position != "rad":
        return ""
    without, with_weight = ident.weight
    if with_weight > WEIGHT_WARNING * without:
        return ""
    return (f"warning: a weight G_s sin x + G_c cos x of the position leaves {with_weight:.3g} "
            f"{units.force} RMS of the force unexplained where the friction law alone leaves "
            f"{without:.3g}: the friction samples hold a link's weight; train --gravity takes it out")


def rising_warning(fits, units=LINEAR) -> str:
    """One line when a log's law rises from its static level F_s to F_c (F_s below F_c by more
    than RISE_SIGMAS standard errors of either): a force that passes a reversal through 0
    smoothly, as the bristles of pre-sliding carry it, read by a static curve of v as a
    friction that vanishes at rest (a new user's LuGre axis, F_s 1.6 Nm, got F_s 0 and 0.56 Nm
    at 0.01 rad/s where it has 1.58, with no word of --dynamic)."""
    for f in fits:
        law = getattr(f.estimator, "law_", None)
        if law is None or not law.stribeck:
            continue
        se = max(law.standard_errors.get("static", math.inf), law.standard_errors.get("coulomb", math.inf))
        if law.coulomb - law.static > RISE_SIGMAS * se:
            return (f"warning: the friction rises from {law.static:.3g} {units.force} at rest to "
                    f"{law.coulomb:.3g} {units.force} by {law.v_s:.3g} {units.speed}: a force that "
                    "passes each reversal smoothly, as pre-sliding (bristles) carries it, which a "
                    "curve of v reads as no friction at rest; train --dynamic models it")
    return ""


#: Standard errors by which F_s below F_c is a rise (``rising_warning``).
RISE_SIGMAS = 3.0


def stribeck_warning(ident: Identification, fits, units=LINEAR) -> str:
    """One line when a log's slowest speed in a direction exceeds half of that direction's
    vs_max: the Stribeck region (velocity weakening below vs_max) is then hardly in the data;
    or when the force still falls at its fastest speed (``StribeckRange.falling``)."""
    for sign, f in zip((1, -1), fits):
        chosen = f.dataset.stribeck_range
        if chosen is not None and chosen.falling:
            return (f"warning: the force still falls at the log's fastest speed "
                    f"({f.dataset.v_sat:.3g} {units.speed}): the Stribeck drop goes on beyond the data, B "
                    f"is not in them ({chosen.viscous:.3g} {units.viscous} fitted with it), and beyond that "
                    "speed the model holds its last level plus B v (log faster motion)")
        vs_max = f.dataset.v_sat / SAT_FACTOR
        speeds = ident.sweep.folded().v if len(fits) == 1 else ident.sweep.direction(sign).v
        slowest = float(speeds.min())
        if slowest > 0.5 * vs_max:
            return (f"warning: the log's slowest speed ({slowest:.3g} {units.speed}) is above vs_max / 2 = "
                    f"{0.5 * vs_max:.3g} {units.speed}; too narrow a velocity range to identify the Stribeck "
                    f"region (log slower steady motion: rows within half a smoothing window, "
                    f"{500 * ident.window * ident.sample_time:.3g} ms, of a reversal or a stop are left "
                    "out, their smoothed force mixing both directions)")
    return ""
