"""Training as a library call: a sweep or a motion log in, a ``FrictionModel`` and its fit report
out. The report is what ``fricgen train`` prints, and its ``training`` record what model.json
keeps (``fricgen.cli.train`` only formats and writes them).

What the report says of an estimator is registered per estimator type (``functools.singledispatch``):
a new estimator adds its functions here rather than a branch to a chain.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from functools import singledispatch
from typing import Callable, Mapping, Optional, Tuple, Union

import numpy as np

from ._validate import ACCEPT_UNUSUAL, USUAL_MAX, physical_problem, unusual
from ._io import named_data
from .c_names import check_model_name
from .codegen.cost import cortex_m4f_instructions, host_ns
from .codegen.parity import float32_problem
from .data.inverse_dynamics import Identification, describe_missing, identify_log, is_log
from .data.outliers import OUTLIER_SIGMAS
from .data.sweep import Sweep, sweep_from_columns
from .data.training_set import SAT_FACTOR
from .errors import DataError, ModelError
from .fit import (DEFAULT_ELM, AutoELMRegressor, DefaultRegressor, ELMRegressor, StribeckRegressor,
                  default_estimator)
from .fit.directions import CV_FOLDS, DirectionsFit, fit_friction
from .fit.elm import EnlargedScheme
from .fit.stribeck import XS_MAX
from .metrics import rmse
from .model import DEFAULT_MODEL_NAME, FrictionModel

__all__ = ["FitReport", "train"]


@dataclass(frozen=True)
class FitReport:
    """A trained friction model with its fit report.

    ``str(report)`` is the text ``fricgen train`` prints; ``report.training`` is the record
    model.json keeps (``report.model.training``).

    Parameters
    ----------
    model : FrictionModel
        The fitted model (eq. (3), sec. 2), symmetric or one curve per direction.
    fit : DirectionsFit
        The fitted curves, each with its eq. (9) training set and fitted estimator, and how the
        symmetry was chosen.
    identification : Identification or None
        For a motion log, how its friction samples were obtained by inverse dynamics
        (eq. (18), sec. 6): rows kept, smoothing, the mass and constant force with standard
        errors; None for a sweep.
    sweep : Sweep or None
        The friction samples fitted: the sweep given, or those a log's inverse dynamics gave.
    warnings : tuple of str
        Notes on the data that do not stop training (a log too fast to show the Stribeck region).

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

    @property
    def training(self) -> dict:
        """model.json's ``training`` record: method, seed, source, the choice and its errors."""
        return self.model.training

    @property
    def text(self) -> str:
        """The report ``fricgen train`` prints: data, symmetry, each curve's model and errors."""
        ident, fitted = self.identification, self.fit
        reports = [] if ident is None else [ident.summary(), ident.offset_line(fitted.asymmetric)]
        reports.append(choice_line(fitted))
        curves = [self.training] + ([self.training["negative"]] if fitted.asymmetric else [])
        labels = ("v > 0:", "v < 0:") if fitted.asymmetric else ("",)
        for label, f, curve in zip(labels, fitted.fits, curves):
            text = curve_report(f.dataset, f.estimator, curve["metrics"])
            reports.append(text if not label else
                           f"{label}\n" + "\n".join("  " + t for t in text.splitlines()))
        problem = float32_problem(self.model)
        if problem:
            reports.append(f"float32   {problem}; emit refuses it")
        return "\n".join(r for r in reports if r)

    def __str__(self) -> str:
        return self.text


# ---------------------------------------------------------------------------- per estimator


@singledispatch
def method_record(estimator) -> dict:
    """model.json's ``training.method`` (and the ELM's options) for ``estimator``."""
    return {"method": type(estimator).__name__, "scheme": type(estimator).__name__}


@method_record.register
def _(estimator: DefaultRegressor) -> dict:
    return {"method": "auto", "scheme": "auto"}


@method_record.register
def _(estimator: AutoELMRegressor) -> dict:
    return {"method": "elm_auto", "scheme": "elm_auto"}


@method_record.register
def _(estimator: StribeckRegressor) -> dict:
    return {"method": "stribeck", "scheme": "stribeck"}


@method_record.register
def _(estimator: ELMRegressor) -> dict:
    scheme = estimator.scheme
    if scheme == "enlarged":
        scheme = EnlargedScheme()
    enlarged = isinstance(scheme, EnlargedScheme)
    return {"method": "elm", "scheme": "enlarged" if enlarged else scheme,
            "w_max": scheme.w_max if enlarged else DEFAULT_ELM["scheme"].w_max,
            "solver": estimator.solver}


@singledispatch
def model_lines(estimator, dataset) -> list:
    """The report's lines on the fitted model (an ELM's size, C and weights by default)."""
    return [f"model     {estimator.n_hidden} {estimator.activation} neurons, "
            f"{estimator.scheme}, C = {estimator.C_:.3g}",
            f"weights   ||beta|| = {estimator.beta_norm_:.4g}, log10 cond(H^T H) = "
            f"{estimator.log10_cond_:.2f}",
            ]


@model_lines.register
def _(estimator: DefaultRegressor, dataset) -> list:
    return ([f"chose     {estimator.why()}", f"outliers  {estimator.outlier_note()}"]
            + model_lines(estimator.chosen_, dataset))


@model_lines.register
def _(estimator: StribeckRegressor, dataset) -> list:
    """The grey-box model of eq. (1) in SI units, each parameter +- its standard error."""
    net, se = estimator.network_, estimator.standard_errors_
    k_in, k_out = dataset.scaling.k_in, dataset.scaling.k_out
    broad = "" if estimator.xs_max_ <= XS_MAX else f", v_s up to {estimator.xs_max_ / k_in:.4g} m/s"
    lines = [f"model     grey-box eq. (1): {net.n_sources} {net.shape} source(s){broad}, "
             f"{_origin(estimator)}",
             f"coulomb   sum f_c = {_estimate(net.offset / k_out, se['offset'] / k_out, 'N')}"]
    for k in range(net.n_sources):
        lines.append(f"source {k + 1:<2d} f_s - f_c = "
                     f"{_estimate(net.amplitudes[k] / k_out, se['amplitudes'][k] / k_out, 'N')}, "
                     f"v_s = {_estimate(net.stribeck[k] / k_in, se['stribeck'][k] / k_in, 'm/s')}")
    return lines


@singledispatch
def cost_lines(estimator) -> list:
    """The C cost per call of an ELM (``fricgen.codegen.cost``, fitted to ELM kernels)."""
    return [call_cost(estimator.n_hidden, estimator.activation)]


@cost_lines.register
def _(estimator: DefaultRegressor) -> list:
    return cost_lines(estimator.chosen_)


@cost_lines.register
def _(estimator: StribeckRegressor) -> list:
    return []


@singledispatch
def validation_error(estimator) -> tuple:
    """The kind and value of the error on held-out points that the fit report prints."""
    return "leave-one-out", estimator.loo_rmse_


@validation_error.register
def _(estimator: DefaultRegressor) -> tuple:
    return "cross-validated", estimator.cv_rmse_[estimator.choice_]


@validation_error.register
def _(estimator: StribeckRegressor) -> tuple:
    return "cross-validated", estimator.cv_rmse_


@singledispatch
def chosen_record(estimator) -> dict:
    """model.json's training record of the model an estimator fitted (an ELM's by default)."""
    return {"activation": estimator.activation, "n_hidden": estimator.n_hidden, "C": estimator.C_}


@chosen_record.register
def _(estimator: DefaultRegressor) -> dict:
    entry = chosen_record(estimator.chosen_)
    extra = {"choice": estimator.choice_, "choice_reason": estimator.why(),
             "n_outliers_rejected": estimator.n_outliers_}
    keys = list(entry)
    return {**{k: entry[k] for k in keys[:2]}, **extra, **{k: entry[k] for k in keys[2:]}}


@chosen_record.register
def _(estimator: StribeckRegressor) -> dict:
    return {"activation": estimator.activation, "n_hidden": estimator.n_hidden,
            "shape": estimator.shape_, "n_sources": estimator.n_sources_}


@singledispatch
def fitted_rows(estimator):
    """The training points the estimator fitted (the default sets gross outliers aside)."""
    return slice(None)


@fitted_rows.register
def _(estimator: DefaultRegressor):
    return estimator.inliers_


# ---------------------------------------------------------------------------- report text


def call_cost(n_hidden: int, activation: str) -> str:
    """The report's line on the C cost per ``NAME_force`` call (``fricgen.codegen.cost``)."""
    units = "" if activation == "sigmoid" else " (cost model measured on sigmoid units)"
    return (f"C cost    about {cortex_m4f_instructions(n_hidden):.0f} instructions per call on "
            f"Cortex-M4F ({cortex_m4f_instructions(n_hidden, 'fast'):.0f} with --activation-impl "
            f"fast), {host_ns(n_hidden):.0f} ns on the reference x86-64 host{units}")


def error_line(errors: dict) -> str:
    """The training and validation errors (normalized, and in N) to four significant digits:
    a fixed number of decimals would print a fit to clean data as 0.0000 N."""
    return (f"errors    E_train = {errors['e_train']:.4g} ({errors['e_train_newton']:.4g} N), "
            f"{errors['e_validation_kind']} = {errors['e_loo']:.4g} ({errors['e_loo_newton']:.4g} N)")


def curve_report(dataset, estimator, errors: dict) -> str:
    """The report of one fitted curve: its data, B, the eq. (9) scaling, the model, the errors."""
    s = dataset.scaling
    chosen = dataset.stribeck_range
    vs_note = " (vs_max chosen from the data; pass --vs-max to set it)" if chosen else ""
    joint = chosen is not None and not chosen.linear_region
    lines = [
        f"data      {dataset.x.size} training points in [0, v_sat], v_sat = {dataset.v_sat:.6g} m/s"
        f"{vs_note}" + (f"; the {dataset.n_rows} rows there averaged in bins of equal count"
                        if dataset.binned else ""),
    ] + ([f"vs_max    {chosen.describe()}"] if chosen else []) + [
        f"viscous   B = {dataset.viscous:.6g} N s/m "
        + ("fitted with the Stribeck sources (no linear high-speed region)" if joint else
           f"from {dataset.n_high_speed} high-speed points")
        + (f" ({dataset.n_outliers} rejected as gross outliers, > {OUTLIER_SIGMAS:g} robust sd "
           "off the line)" if dataset.n_outliers else ""),
        f"scaling   K_in = {s.k_in:.6g} 1/(m/s), K_out = {s.k_out:.6g} 1/N",
    ]
    return "\n".join(lines + model_lines(estimator, dataset) + [error_line(errors)]
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


def curve_errors(dataset, estimator) -> dict:
    """The errors of the report; E_train over the points fitted (the gross outliers the default
    sets aside are not)."""
    rows = fitted_rows(estimator)
    e_train = rmse(estimator.predict(dataset.x[rows]), dataset.t[rows])
    kind, e_validation = validation_error(estimator)
    return {"e_train": e_train, "e_train_newton": e_train / dataset.scaling.k_out,
            "e_loo": e_validation, "e_loo_newton": e_validation / dataset.scaling.k_out,
            "e_validation_kind": kind}


def curve_record(fit) -> dict:
    """model.json's training record of one fitted curve: what was chosen, a grey-box curve's
    standard errors in SI units (infinite, written null, where the data do not determine a
    source: emit refuses it) and the errors."""
    entry = chosen_record(fit.estimator)
    chosen = getattr(fit.estimator, "chosen_", fit.estimator)
    if isinstance(chosen, StribeckRegressor):
        se, s = chosen.standard_errors_, fit.dataset.scaling
        entry["standard_errors"] = {"amplitudes_newton": (se["amplitudes"] / s.k_out).tolist(),
                                    "stribeck_m_per_s": (se["stribeck"] / s.k_in).tolist()}
    return {**entry, "metrics": curve_errors(fit.dataset, fit.estimator)}


def choice_line(fitted: DirectionsFit) -> str:
    """How the model's symmetry was chosen (nothing for a sweep of one direction)."""
    kind = "asymmetric (one curve per direction)" if fitted.asymmetric else "symmetric"
    if fitted.chosen_by == "one direction only":
        return ""
    if fitted.chosen_by.startswith("asymmetric model not fittable"):
        return f"symmetry {kind}: the {fitted.chosen_by}"
    if fitted.cv_rmse is None:
        return f"symmetry {kind}, as asked"
    sym, asym = fitted.cv_rmse
    return (f"symmetry {kind} by {CV_FOLDS}-fold {fitted.chosen_by}: held-out RMS "
            f"{sym:.4g} N symmetric, {asym:.4g} N asymmetric")


def stribeck_warning(ident: Identification, fits) -> str:
    """One line when a log's slowest speed in a direction exceeds half of that direction's
    vs_max: the Stribeck region (velocity weakening below vs_max) is then hardly in the data."""
    for sign, f in zip((1, -1), fits):
        vs_max = f.dataset.v_sat / SAT_FACTOR
        speeds = ident.sweep.folded().v if len(fits) == 1 else ident.sweep.direction(sign).v
        slowest = float(speeds.min())
        if slowest > 0.5 * vs_max:
            return (f"warning: the log's slowest speed ({slowest:.3g} m/s) is above vs_max / 2 = "
                    f"{0.5 * vs_max:.3g} m/s; too narrow a velocity range to identify the Stribeck "
                    "region (log slower motion)")
    return ""


def axis_record(sweep: Sweep, ident: Optional[Identification], asymmetric: bool) -> dict:
    """model.json's ``training.axis``: the mass, force constant and constant force that training
    identified or was given (null for a sweep; the offset null where the asymmetric model's
    curves hold it), and the speed range of the data."""
    speed = np.abs(sweep.v[sweep.v != 0])
    record = {"mass": None, "mass_se": None, "mass_from": None, "force_constant": None,
              "offset": None, "offset_se": None,
              "speed_min": float(speed.min()), "speed_max": float(speed.max())}
    if ident is not None:
        body = ident.body
        record.update(mass=body.mass, mass_se=body.mass_se,
                      mass_from="data" if body.mass_identified else "option")
        if not asymmetric:
            record.update(offset=body.offset, offset_se=body.offset_se)
        if ident.force_constant is not None:
            record["force_constant"] = ident.force_constant[0]
    return record


def check_fitted(model: FrictionModel, ident, source: str, accept_unusual: bool, fastest: float,
                 warn: Callable[[str], None]) -> None:
    """The fitted curves and the identified mass within the physical bounds of a real axis
    (``Direction.check_physical``, ``_validate.PHYSICAL``): refused, or with ``accept_unusual``
    one warning line each; a v_sat beyond ``USUAL_MAX`` is one warning line, unless the data's
    fastest speed ``fastest`` was (``data.plausibility``)."""
    problems = []
    for curve in model.directions:
        try:
            curve.check_physical()
        except ModelError as exc:
            problems.append(f"the fitted model's {str(exc).split(' (a digit')[0]}")
    said = fastest > USUAL_MAX["speed"]            # the data's speed was warned about already
    for curve in model.directions:
        note = "" if any(problems) or said else unusual("v_sat", "the fitted model's v_sat", curve.v_sat)
        if note:
            warn(f"fricgen: warning: {source}: {note}")
            break
    if ident is not None and ident.body.mass_identified:
        problems.append(physical_problem("mass", "the identified mass", ident.body.mass))
    for problem in filter(None, problems):
        if not accept_unusual:
            raise DataError(f"{source}: {problem}; are the units SI ({ACCEPT_UNUSUAL} to keep it)?")
        warn(f"fricgen: warning: {source}: {problem}; kept ({ACCEPT_UNUSUAL})")


# ---------------------------------------------------------------------------- train


def _friction_data(data, mass, force_constant, source, progress):
    """The sweep to fit and, for a motion log, its identification (``data.inverse_dynamics``)."""
    if isinstance(data, Sweep):
        columns = {"v": np.asarray(data.v, float), "f": np.asarray(data.f, float)}
    elif isinstance(data, Mapping):
        columns = {k: np.asarray(v, dtype=float) for k, v in data.items()}
    else:
        raise ValueError(f"data must be a Sweep or a mapping of columns, got {type(data).__name__}")
    if is_log(columns):
        with named_data(source):
            ident = identify_log(columns, mass, force_constant, progress=progress)
        return ident.sweep, ident
    if not {"v", "f"} <= set(columns):
        raise DataError(f"{source}: {describe_missing(columns)}")
    if mass is not None or force_constant is not None:
        raise ValueError(f"mass and force_constant apply to a motion log; {source} is a sweep (v, f)")
    return sweep_from_columns(columns, source), None


def train(data: Union[Sweep, Mapping], *, estimator=None, vs_max: Optional[float] = None,
          asymmetric: Optional[bool] = None, mass: Optional[float] = None,
          force_constant: Optional[float] = None, seed: int = 0, name: str = DEFAULT_MODEL_NAME,
          source: str = "data", file: Optional[str] = None, accept_unusual: bool = False,
          progress: Optional[Callable[[str], None]] = None,
          warn: Optional[Callable[[str], None]] = None) -> FitReport:
    """Fit a friction model to a sweep or a motion log, as ``fricgen train`` does.

    Parameters
    ----------
    data : Sweep or mapping of str to array_like
        A sweep (velocity ``v`` in m/s, force ``f`` in N), or the columns of a motion log:
        ``t`` (s, uniformly sampled), ``v`` (m/s) or ``x`` (m), and ``force`` (N) or ``i`` (A).
    estimator : estimator, optional
        What fits each curve's eq. (9) training set; default ``default_estimator(seed)``: the
        grey-box eq. (1) or the automatic ELM, whichever cross-validates better.
    vs_max : float, optional
        Bound on the Stribeck velocities, m/s (v_sat = 3 vs_max); default: chosen by
        cross-validation from the data.
    asymmetric : bool, optional
        One curve per direction (True) or one for both (False); default: chosen by
        cross-validation when the data move both ways.
    mass : float, optional
        Moving mass of a log's axis, kg; default: identified by inverse dynamics (eq. (18)).
    force_constant : float, optional
        Force constant, N/A, of a log with current ``i`` instead of ``force``.
    seed : int, default 0
        Random seed of the folds (and of the default estimator).
    name : str, default "friction_model"
        The model's name, a C identifier not beginning with ``fric_``.
    source : str, default "data"
        How messages name the data (a file, or both files of a merge).
    file : str, optional
        The data's file name, recorded as ``training.source``; default ``source``.
    accept_unusual : bool, default False
        Keep a fitted model beyond the physical bounds of a real axis, with a warning.
    progress : callable, optional
        Called with a line of progress on long fits.
    warn : callable, optional
        Called with each warning line; default ``warnings.warn``.

    Returns
    -------
    FitReport
        The model, its fit and the report; ``str(report)`` is the text ``fricgen train`` prints.

    Raises
    ------
    DataError
        Data that cannot give a friction model (too few rows, no motion, a falling force).
    ValueError
        A bad argument.

    Notes
    -----
    Each curve is fitted on the normalized data of eq. (9), sec. 2,

    .. math:: x = K_{in} v, \\qquad t = K_{out} (F - B v),

    and the model is eq. (3), sec. 2: :math:`F(v) = \\mathrm{AIM}(K_{in} |v|) / K_{out} + B v`.
    A log's friction samples are :math:`F = f - m \\dot v` (eq. (18), sec. 6). The plausibility
    checks of the CLI's data reader (``fricgen.data.plausibility``) are not run here.

    Examples
    --------
    >>> import fricgen
    >>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
    >>> report = fricgen.train(sweep, vs_max=0.02, estimator=fricgen.StribeckRegressor())
    >>> report.fit.asymmetric, report.training["method"]
    (False, 'stribeck')
    >>> print(report.model.force([0.05, -0.05]) > 0)    # friction opposes the motion
    [ True False]
    """
    if vs_max is not None and not (isinstance(vs_max, (int, float)) and 0 < vs_max < math.inf):
        raise ValueError(f"vs_max must be a number > 0, got {vs_max!r}")
    check_model_name(name, "name")
    sweep, ident = _friction_data(data, mass, force_constant, source, progress)
    estimator = default_estimator(seed) if estimator is None else estimator
    warn = warn or (lambda line: warnings.warn(line, stacklevel=3))
    with named_data(source):
        fitted = fit_friction(sweep, estimator, None, ident, vs_max=vs_max,
                              asymmetric=asymmetric, seed=seed, progress=progress)
    first = fitted.fits[0]
    curves = [curve_record(f) for f in fitted.fits]
    training = {**method_record(estimator), "seed": seed, "source": source if file is None else file,
                "vs_max_estimated": first.dataset.vs_max_estimated, **curves[0]}
    if fitted.asymmetric:
        training["negative"] = curves[1]
    if fitted.cv_rmse is not None:
        training["cv_rmse_newton"] = dict(zip(("symmetric", "asymmetric"), fitted.cv_rmse))
    training["axis"] = axis_record(sweep, ident, fitted.asymmetric)
    if accept_unusual:
        training["accept_unusual"] = True
    if ident is not None:
        training["log"] = {"window": ident.window, "rows": ident.n_rows, "kept": ident.n_kept,
                           "independent": ident.independent,
                           "slowest": [float(ident.sweep.direction(s).v.min(initial=float("inf")))
                                       for s in (1, -1)]}
    model = FrictionModel.from_directions(*(f.curve for f in fitted.fits), name=name,
                                          training=training)
    try:
        for curve in model.directions:
            curve.check()
    except ModelError as exc:
        raise DataError(f"{source}: the fitted model is no friction model: {exc}") from None
    check_fitted(model, ident, source, accept_unusual, float(np.max(np.abs(sweep.v))), warn)
    notes = (stribeck_warning(ident, fitted.fits),) if ident is not None else ()
    return FitReport(model=model, fit=fitted, identification=ident, sweep=sweep,
                     warnings=tuple(n for n in notes if n))
