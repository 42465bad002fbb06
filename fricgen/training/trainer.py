"""Training as a library call: a sweep or a motion log in, a ``FrictionModel`` and its fit report
(``report.FitReport``) out, with model.json's ``training`` record (``record``)."""
from __future__ import annotations

import math
import re
import warnings
from dataclasses import replace
from typing import Callable, Mapping, Optional, Tuple, Union

import numpy as np

from .._validate import ACCEPT_UNUSUAL, physical_problem, rotary_axis, unusual, usual_max
from ..units import units_of
from .._blas import blas_threads, wanted_threads
from .._io import named_data
from ..c_names import check_model_name
from ..data.export import by_quantity, names_rotary_axis
from ..data.inverse_dynamics import FRICTION_Z, describe_missing, identify_log, is_log, velocity_resolution
from ..data.motionlog import without_lagging_velocity
from ..data.plausibility import check_columns
from ..data.sweep import Sweep, sweep_from_columns
from ..data.training_set import check_friction_sign, magnitudes_hint, repeated_speeds_note
from ..data.wrapping import unwrapped
from ..errors import DataError, ModelError
from ..fit import DefaultRegressor, default_estimator
from ..fit.directions import BLOCK_WINDOWS, fit_friction
from ..fit.law_choice import (STRUCTURE_POINTS, Scored, asymmetry_evident, choose_law, shows_structure,
                              testable, textbook_outliers)
from ..fit.textbook_laws import point_weights, rest_levels
from ..model import DEFAULT_MODEL_NAME, FrictionModel
from .record import axis_record, curve_record, method_record
from .report import FitReport, gravity_warning, rising_warning, stribeck_warning
from .with_inputs import dependence_record, fit_inputs


def check_fitted(model: FrictionModel, ident, source: str, accept_unusual: bool, fastest: float,
                 warn: Callable[[str], None], hint: str = "") -> None:
    """The fitted curves and the identified mass within the physical bounds of a real axis
    (``Direction.check_physical``, ``_validate.PHYSICAL``): refused, or with ``accept_unusual``
    one warning line each; a v_sat beyond ``USUAL_MAX`` and beyond the data's fastest speed
    ``fastest`` is one warning line (one within the data's speeds is as usual as they are, which
    ``data.plausibility`` judged: a textbook law's v_sat is the fastest speed). A mass that
    speeding up and braking give apart, or smoothing windows that explain the force equally well,
    or a mass given that the log's accelerations contradict (``RigidBody.doubts``), is one
    warning line each. ``hint``: words a refusal adds (``magnitudes_hint``)."""
    problems = []
    for curve in model.directions:
        try:
            curve.check_physical()
        except ModelError as exc:
            problem = str(exc).split(" (a digit")[0]
            problems.append(f"the fitted model's {problem[4:] if problem.startswith('the ') else problem}")
    said = fastest > usual_max("speed")            # the data's speed was warned about already
    for curve in model.directions:
        judged = any(problems) or said or curve.v_sat <= fastest
        note = "" if judged else unusual("v_sat", "the fitted model's v_sat", curve.v_sat)
        if note:
            warn(f"fricgen: warning: {source}: {note}")
            break
    if ident is not None and (unused := ident.acceleration_doubt(model.units)) is not None:
        warn(f"fricgen: warning: {source}: {unused}")
    if ident is not None and (runs := ident.body.runs_doubt()) is not None:
        warn(f"fricgen: warning: {source}: {runs}")
    for doubt in [] if ident is None else ident.body.doubts(model.units.mass):
        which = ("identified" if ident.body.mass_identified else
                 "given" if ident.body.mass_source == "given" else "cogging map's")
        warn(f"fricgen: warning: {source}: the {which} {model.units.inertia_name}: {doubt}")
    if ident is not None and ident.body.mass_identified and ident.body.mass_determined:
        problems.append(physical_problem("mass", f"the identified {model.units.inertia_name}",
                                         ident.body.mass))
    for problem in filter(None, problems):
        if not accept_unusual:
            raise DataError(f"{source}: {problem}; are the units SI ({ACCEPT_UNUSUAL} to keep it){hint}?")
        warn(f"fricgen: warning: {source}: {problem}; kept ({ACCEPT_UNUSUAL})")


def _check_error(fitted) -> Optional[ModelError]:
    """Why a fitted curve fails ``Direction.check`` (one that holds a load larger than its
    direction's friction pushes the axis), or None."""
    try:
        for f in fitted.fits:
            f.curve.check()
    except ModelError as exc:
        return exc
    return None


def _fit_multi_source(sweep, estimator, ident, **options):
    """``fit_friction``, refitted with the log's offset a load (``Identification.as_load``) where
    the asymmetric curves that hold it would push the axis; the fit, identification and sweep."""
    fitted = fit_friction(sweep, estimator, None, ident, **options)
    if fitted.asymmetric and ident is not None and ident.body.offset is not None \
            and _check_error(fitted) is not None:
        ident = ident.as_load()
        sweep = ident.friction
        fitted = fit_friction(sweep, estimator, None, ident, **options)
    return fitted, ident, sweep


#: A sweep's columns beside v and f that weight its points: each one's standard deviation and count.
SPREAD_COLUMNS = ("f_std", "n")


def sweep_spread(columns: Mapping[str, np.ndarray]) -> Tuple[Optional[np.ndarray], Optional[np.ndarray]]:
    """A sweep's per-point standard deviation ``f_std`` and count ``n`` where it has them (None
    where not); ``DataError`` for one that is not finite and > 0."""
    out = []
    for name in SPREAD_COLUMNS:
        values = None
        if name in columns:
            values = np.asarray(columns[name], dtype=float)
            if not np.all(np.isfinite(values) & (values > 0)):
                raise DataError(f"column {name} must be finite and > 0 in every row (it weights "
                                "the sweep's points)")
        out.append(values)
    return out[0], out[1]


def _friction_data(data, mass, force_constant, source, progress, use=None, gravity=False,
                   held=False):
    """The sweep to fit and, for a motion log, its identification (``data.inverse_dynamics``)."""
    if isinstance(data, Sweep):
        columns = {"v": np.asarray(data.v, float), "f": np.asarray(data.f, float)}
    elif isinstance(data, Mapping):
        columns = {k: np.asarray(v, dtype=float) for k, v in data.items()}
    else:
        raise ValueError(f"data must be a Sweep or a mapping of columns, got {type(data).__name__}")
    if is_log(columns):
        with named_data(source):
            ident = identify_log(columns, mass, force_constant, progress=progress, use=use,
                                 gravity=gravity, held=held)
        return ident.sweep, ident
    if not {"v", "f"} <= set(columns):
        raise DataError(f"{source}: {describe_missing(columns)}")
    if mass is not None or force_constant is not None or gravity or held:
        raise ValueError(f"mass, force_constant, gravity and force_held apply to a motion log; "
                         f"{source} is a sweep (v, f)")
    return sweep_from_columns(columns, source), None


def _fit_default(sweep, estimator, ident, spread, vs_max, asymmetric, seed, progress, outliers=None):
    """The default's fit (``fit.law_choice``): the textbook laws and, where the data allow, the
    multi-source fit, the simplest within the noise of the best kept. Returns the fit, the
    identification (its offset made a load where the multi-source curves would push the
    axis) and the choice. ``outliers``: a sweep's gross outliers where found already."""
    rich, reason, evident = None, "", False
    known = None if outliers is None else Scored(outliers, {})
    weight = point_weights(sweep, *spread)
    if ident is None and not shows_structure(sweep, weight):
        reason = ("multi-source fit: not tried, the textbook law's residuals run along the speed "
                  "as chance does and are no larger than the points' from their neighbours (no "
                  "curve left for it to find)" if testable(sweep) else
                  f"multi-source fit: not tried, no curve has the {STRUCTURE_POINTS} points "
                  "a test of the textbook law's residuals needs")
    else:
        # a sweep whose textbook laws already tell the directions apart: the multi-source
        # curves per direction, without cross-validating their symmetry
        if asymmetric is None and ident is None:
            evident, known = asymmetry_evident(sweep, weight, seed, outliers)
        try:
            rich, ident, sweep = _fit_multi_source(sweep, estimator, ident, vs_max=vs_max,
                                                   asymmetric=asymmetric, seed=seed,
                                                   progress=progress, evident=evident)
        except (DataError, ValueError) as exc:  # ValueError: the estimator found no admissible fit
            reason = f"multi-source fit: {exc}"
    error = None if rich is None else _check_error(rich)
    # a curve that pushes the axis is no candidate; one whose negative B turns the force against
    # the motion stays one, for train's own check to refuse by name when it is kept
    if error is not None and "must oppose the motion" not in str(error):
        rich, reason = None, "multi-source fit: its curve would push the axis"
    log = {} if ident is None else dict(independence=ident.independent / ident.n_kept,
                                        offset=ident.offset_in_friction,
                                        blocks=BLOCK_WINDOWS * ident.window)
    choice = choose_law(sweep, weight, rich, reason, seed=seed,
                        asymmetric=asymmetric, known=known,
                        reversals=None if ident is None else ident.reversal_friction, **log)
    if choice.fit.chosen_by == "textbook" and choice.fit.asymmetric and ident is not None \
            and ident.offset_in_friction:
        ident = ident.as_load("textbook")   # the textbook curves leave the offset out
    return choice.fit, ident, choice


def train(data: Union[Sweep, Mapping], *, estimator=None, vs_max: Optional[float] = None,
          asymmetric: Optional[bool] = None, mass: Optional[float] = None,
          force_constant: Optional[float] = None, seed: int = 0, name: str = DEFAULT_MODEL_NAME,
          source: str = "data", file: Optional[str] = None, accept_unusual: bool = False,
          progress: Optional[Callable[[str], None]] = None,
          warn: Optional[Callable[[str], None]] = None, rotary: bool = False,
          checks: bool = True, velocity_resolution: Optional[float] = None,
          use: Optional[np.ndarray] = None, gravity: bool = False,
          force_held: bool = False, mass_source: str = "given") -> FitReport:
    """Fit a friction model to a sweep or a motion log, as ``fricgen train`` does.

    Parameters
    ----------
    data : Sweep or mapping of str to array_like
        A sweep (velocity ``v`` in m/s, force ``f`` in N), or the columns of a motion log:
        ``t`` (s, uniformly sampled), ``v`` (m/s) or ``x`` (m), and ``force`` (N) or ``i`` (A).
    estimator : estimator, optional
        What fits each curve's [F9] training set; default ``default_estimator(seed)``: the
        grey-box [F1], or the automatic ELM where it cross-validates clearly better.
    vs_max : float, optional
        Bound on the Stribeck velocities, m/s (v_sat = 3 vs_max); default: chosen by
        cross-validation from the data.
    asymmetric : bool, optional
        One curve per direction (True) or one for both (False); default: chosen by
        cross-validation when the data move both ways.
    mass : float, optional
        Moving mass of a log's axis, kg; default: identified by inverse dynamics [C1].
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
    rotary : bool, default False
        A rotary axis: the data are in rad, rad/s, Nm (and the inertia in kg m^2); the report,
        the physical bounds and ``training.units`` say so.
    checks : bool, default True
        The plausibility checks of ``fricgen train``'s data reader (``data.plausibility``:
        swapped columns, values beyond a real axis such as a current in mA read as A), refusing
        as it does (warnings through ``warn`` with ``accept_unusual``); False skips them.
    velocity_resolution : float, optional
        The smallest speed the controller's velocity resolves, m/s (rad/s): the band below
        which ``model.compensation`` is 0 (``velocity_band``). Default: a log's own
        (RESOLUTION_COUNTS encoder steps per sample, or RESOLUTION_SIGMAS of its velocity noise); none
        for a sweep.
    use : array of bool, optional
        The rows of a log to identify the friction on (default all): ``train --dynamic`` leaves
        out those where the bristles are still building up.
    gravity : bool, default False
        A log of a joint whose force holds its link's weight: G_s sin x + G_c cos x of the
        position ``x`` (rad) identified beside the inertia and taken out of the friction
        samples (the report prints it; the model stays the friction). Needs ``x``.
    force_held : bool, default False
        A log whose force (or current) is the drive's set-point, held over the sample after the
        one it is logged at: brought to the motion's sample times first
        (``identify_friction``'s ``held``), recorded as ``training.log.force_held``.
    mass_source : str, default "given"
        Where ``mass`` came from, which the doubts of it name: "given", or "cogging" (the
        inertia a cogging calibration's map identified).

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
    Each curve is fitted on the normalized data of [F9],

    .. math:: x = K_{in} v, \\qquad t = K_{out} (F - B v),

    and the model is [F3]: :math:`F(v) = \\mathrm{AIM}(K_{in} |v|) / K_{out} + B v`.
    A log's friction samples are :math:`F = f - m \\dot v` [C1]. The numerics run on
    ``FRICGEN_BLAS_THREADS`` BLAS threads (default 1) as the command line's do, restored after.

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
    warn = warn or (lambda line: warnings.warn(line, stacklevel=4))
    if isinstance(data, Mapping):
        rotary = rotary or names_rotary_axis([str(k) for k in data])
        data = unwrapped(quantities(data, source), warn)
    with rotary_axis(rotary), blas_threads(wanted_threads()):
        if checks:
            _check_data(data, source, accept_unusual, warn)
        if isinstance(data, Mapping):
            data = without_lagging_velocity(data, warn)
        report = _train(data, estimator, vs_max, asymmetric, mass, force_constant, seed, name,
                        source, file, accept_unusual, progress, warn, rotary, use, gravity, force_held,
                        mass_source)
        return with_velocity_band(report, data, velocity_resolution)


def quantities(columns: Mapping, source: str) -> dict:
    """A mapping's columns by fricgen's quantities, as a file's header is read: the names in
    lower case, a joint's and a drive's (q, dq, tau, current, ...) read as x, v, force, i
    (``data.export.by_quantity``)."""
    named = {}
    for key, values in columns.items():
        name = str(key).strip().lower()
        if name in named:
            raise DataError(f"{source}: two columns are named {name!r} once read in lower case")
        named[name] = values
    return by_quantity(named)


def with_velocity_band(report: FitReport, data, given: Optional[float]) -> FitReport:
    """The report's model with its ``velocity_band``: ``given``, else the log's resolution
    (``data.inverse_dynamics.velocity_resolution``); unchanged for a sweep without one."""
    ident = report.identification
    if given is not None:
        if not (isinstance(given, (int, float)) and 0 < given < math.inf):
            raise ValueError(f"velocity_resolution must be a number > 0, got {given!r}")
        band, source = float(given), "given to train"
    elif ident is not None:
        columns = data if isinstance(data, Mapping) else {}
        x, v = (None if columns.get(k) is None else np.asarray(columns[k], dtype=float)
                for k in ("x", "v"))
        band = velocity_resolution(x, ident.velocity_noise, ident.sample_time, v)
        source = "the training log's velocity resolution"
        if not band > 0:                    # a noise-free velocity: nothing to tell from rest
            return report
    else:
        return report
    training = {**report.model.training, "velocity_band_from": source}
    return replace(report, model=replace(report.model, velocity_band=band, training=training))


def _check_data(data, source: str, accept_unusual: bool, warn) -> None:
    """The data reader's plausibility checks (``data.plausibility.check_columns``) on the
    columns of ``data``; columns that are no numbers are left for the fit to name."""
    try:
        columns = ({"v": data.v, "f": data.f} if isinstance(data, Sweep) else
                   {str(k): np.asarray(v, dtype=float) for k, v in data.items()})
    except (TypeError, ValueError, AttributeError):
        return
    if all(c.ndim == 1 for c in columns.values()):
        check_columns(columns, source, is_log(columns), accept_unusual, warn)


def sweep_offset(sweep: Sweep, spread, units) -> Tuple[Optional[Tuple[float, float]], np.ndarray]:
    """(o, its standard error) of a sweep whose force pushes the axis at rest in one direction
    (``fit.textbook_laws.rest_levels``) while the two directions' together oppose it: a
    constant force beside the friction (a sensor's zero, an incline, a cable), the mean of the
    directions' values at v = 0 (a new user's sweep of sgn(v) 0.2 + 8 v less 0.3 N had its
    forward F_c clamped at 0, F_v 4 % low, 8 times the textbook fit's error at its points).
    ``DataError`` where no constant explains it: a sweep of one direction (which cannot tell
    one from friction), or both directions pushing (a force that vanishes at a speed > 0: v and
    f swapped had trained a curve that pushes below 0.2 "m/s"). None where none pushes. Beside
    it, the sweep's gross outliers (``textbook_outliers``, left out of the levels), which the
    law choice reuses where no offset changes the sweep: on a sweep of 1M points they take
    6 s."""
    check_friction_sign(sweep.folded())       # a sign flipped is named as such, not as a push
    weight = point_weights(sweep, *spread) if any(c is not None for c in spread) else np.ones(len(sweep))
    kept = ~textbook_outliers(sweep)          # a gross outlier row is no level at rest
    levels = rest_levels(Sweep(sweep.v[kept], sweep.f[kept]), weight[kept])
    if levels is None:
        return None, ~kept
    said = " and ".join(f"{level:.3g} +- {se:.2g}" for level, se in levels)
    if len(levels) == 1:
        raise DataError(f"the force extrapolated to v = 0 is {said} {units.force}, pushing "
                        "the axis: a constant force beside the friction (a sensor's zero, an incline), "
                        "which a sweep of one direction cannot tell from friction (sweep both "
                        "directions, or take it out of f)")
    (forward, se_f), (backward, se_b) = levels
    if forward + backward <= 0:
        raise DataError(f"the force's magnitude extrapolated to v = 0 is {said} {units.force} "
                        "(v > 0, v < 0): it vanishes at a speed above 0 in both directions, as no "
                        f"friction does (are the columns v and f swapped{magnitudes_hint(sweep)}?)")
    return ((forward - backward) / 2, float(np.hypot(se_f, se_b)) / 2), ~kept


def check_sweep_friction(curves: list, source: str, units, hint: str = "") -> None:
    """``DataError`` where a sweep's Coulomb + viscous curves hold no friction: in every curve
    neither F_c nor F_v stands FRICTION_Z standard errors from 0 (a one-way Stribeck sweep with
    v and f swapped, its slowest "speed" 59 % of its fastest, had trained F_c 0.064 +- 0.17 N
    and F_v 0 +- 0.24 N s/m, a model that explains nothing; a log's is
    ``data.inverse_dynamics.check_friction_found``)."""
    laws = [c for c in curves if "coulomb" in c and "static" not in c]
    if len(laws) != len(curves):
        return
    if all(abs(c[k]) <= FRICTION_Z * c["standard_errors"][k] for c in laws for k in ("coulomb", "viscous")):
        said = "; ".join(f"F_c = {c['coulomb']:.3g} +- {c['standard_errors']['coulomb']:.2g} {units.force}, "
                         f"F_v = {c['viscous']:.3g} +- {c['standard_errors']['viscous']:.2g} {units.viscous}"
                         for c in laws)
        raise DataError(f"{source}: the sweep holds no friction: its force follows neither sgn(v) nor v "
                        f"({said}, none {FRICTION_Z:g} standard errors from 0): are the columns v and f "
                        f"swapped, or of two axes{hint}?")


def _train(data, estimator, vs_max, asymmetric, mass, force_constant, seed, name, source, file,
           accept_unusual, progress, warn, rotary, use=None, gravity=False,
           held=False, mass_source="given") -> FitReport:
    if vs_max is not None and not (isinstance(vs_max, (int, float)) and 0 < vs_max < math.inf):
        raise ValueError(f"vs_max must be a number > 0, got {vs_max!r}")
    check_model_name(name, "name")
    sweep, ident = _friction_data(data, mass, force_constant, source, progress, use, gravity, held)
    if ident is not None and mass is not None:
        ident = replace(ident, body=replace(ident.body, mass_source=mass_source))
    hint = magnitudes_hint(sweep) if ident is None else ""
    repeats = repeated_speeds_note(sweep, units_of(rotary)) if ident is None else ""
    spread = sweep_spread(data) if ident is None and isinstance(data, Mapping) else (None, None)
    estimator = default_estimator(seed) if estimator is None else estimator
    offset = outliers = None
    if ident is None:
        with named_data(source):
            offset, outliers = sweep_offset(sweep, spread, units_of(rotary))
    if offset is not None:
        sweep = Sweep(sweep.v, sweep.f - offset[0])
    if offset is not None or np.any(sweep.v == 0):
        outliers = None     # found again on what the law choice scores: the moving points less o

    def fit_curves(sweep, ident, outliers=None):
        with named_data(source):
            if isinstance(estimator, DefaultRegressor):
                fitted, ident, choice = _fit_default(sweep, estimator, ident, spread, vs_max,
                                                     asymmetric, seed, progress, outliers)
                return fitted, ident, (sweep if ident is None else ident.friction), choice
            fitted, ident, sweep = _fit_multi_source(sweep, estimator, ident, vs_max=vs_max,
                                                     asymmetric=asymmetric, seed=seed,
                                                     progress=progress)
            return fitted, ident, sweep, None

    fitted, ident, sweep, choice = fit_curves(sweep, ident, outliers)
    shapes, dependence = [f.curve for f in fitted.fits], None
    if ident is not None and ident.conditions:
        fitted, ident, sweep, choice, shapes, dependence = fit_inputs(
            fitted, ident, sweep, choice, fit_curves, progress)
    first = fitted.fits[0]
    curves = [curve_record(f) for f in fitted.fits]
    if ident is None:
        check_sweep_friction(curves, source, units_of(rotary), hint)
    training = {**method_record(estimator), "seed": seed, "source": source if file is None else file,
                "vs_max_estimated": first.dataset.vs_max_estimated, **curves[0]}
    if fitted.asymmetric:
        training["negative"] = curves[1]
    if fitted.cv_rmse is not None:
        training["cv_rmse_newton"] = dict(zip(("symmetric", "asymmetric"), fitted.cv_rmse))
    if choice is not None:
        training["law"] = {"chosen": choice.name, "cv_rmse_newton": dict(choice.cv_rmse),
                           "left_out": list(choice.left_out)}
    # the speed range of the points fitted: a gross outlier's speed is not the axis'
    training["axis"] = axis_record(sweep if choice is None else choice.kept, ident, fitted.asymmetric)
    if offset is not None:
        training["axis"].update(offset=offset[0], offset_se=offset[1])
    training["units"] = units_of(rotary).kind
    if accept_unusual:
        training["accept_unusual"] = True
    if ident is not None:
        training["log"] = {"window": ident.window, "rows": ident.n_rows, "kept": ident.n_kept,
                           "sample_time": ident.sample_time,
                           "independent": ident.independent,
                           "slowest": [float(ident.sweep.direction(s).v.min(initial=float("inf")))
                                       for s in (1, -1)], **({"force_held": True} if held else {})}
    if dependence is not None:
        training["inputs"] = dependence_record(dependence)
    model = FrictionModel.from_directions(*shapes, name=name, training=training)
    if dependence is not None and dependence.inputs is not None:
        model = replace(model, inputs=dependence.inputs)
    try:
        for curve in model.directions:
            curve.check()
    except ModelError as exc:           # a fit is no hand-edited file: the loader's hint is not said
        said = re.sub(r" \((an edited|was one of them edited)[^)]*\)", "", str(exc))
        advice = ("" if isinstance(estimator, DefaultRegressor) else
                  "; the default method (without --method) keeps only laws that oppose the motion")
        raise DataError(f"{source}: the fitted model is no friction model: {said}{advice}{hint}") from None
    check_fitted(model, ident, source, accept_unusual, float(np.max(np.abs(sweep.v))), warn, hint)
    notes = (stribeck_warning(ident, fitted.fits, model.units), rising_warning(fitted.fits, model.units),
             gravity_warning(ident, model.units)) if ident is not None else (repeats,)
    return FitReport(model=model, fit=fitted, identification=ident, sweep=sweep,
                     warnings=tuple(n for n in notes if n), law=choice, inputs=dependence)
