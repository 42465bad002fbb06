"""``fricgen train``: fit a friction model to a sweep or a motion log CSV and write model.json."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..data.inverse_dynamics import MIN_LOG_ROWS, describe_missing, identify_log, is_log
from ..data.sweep import MIN_ROWS, sweep_from_columns
from ..data.table import header_cells
from .._validate import ACCEPT_UNUSUAL, MAX_HIDDEN, USUAL_MAX, physical_problem, unusual
from ..data.outliers import OUTLIER_SIGMAS
from ..data.training_set import SAT_FACTOR
from ..codegen.cost import cortex_m4f_instructions, host_ns
from ..codegen.parity import float32_problem
from ..errors import DataError, ModelError, UsageError
from ..fit import (DEFAULT_ELM, DefaultRegressor, ELMRegressor, StribeckRegressor,
                   default_elm, default_estimator)
from ..fit.directions import CV_FOLDS, fit_friction
from ..fit.stribeck import XS_MAX
from ..fit.elm import SCHEMES, SOLVERS, EnlargedScheme
from ..metrics import rmse
from ..model import DEFAULT_MODEL_NAME, FrictionModel, check_model_name
from ..networks.elm import ACTIVATIONS
from .._io import check_destination, named_data
from .inputs import add_export_options, data_warnings, read_data, say_data_warnings
from .inputs import source_name as common_source_name
from .common import (add_output, add_seed, number, out, positive_float,
                     say, write_file)

#: Options of an explicitly configured ELM (``--method elm``), with their defaults.
_ELM_OPTIONS = {"neurons": DEFAULT_ELM["n_hidden"], "activation": DEFAULT_ELM["activation"],
                "scheme": "enlarged", "w_max": DEFAULT_ELM["scheme"].w_max,
                "solver": DEFAULT_ELM["solver"], "C": None}


def _estimator(args):
    """The automatic ELM (default), or the ELM the explicit options describe (``--method elm``,
    implied by any of --neurons/--activation/--scheme/--w-max/--solver/--C)."""
    given = [k for k in _ELM_OPTIONS if getattr(args, k) is not None]
    flags = ", ".join("--" + k.replace("_", "-") for k in given)
    args.method = args.method or ("elm" if given else "auto")
    if args.method != "elm":
        if given:
            raise UsageError(f"{flags} configure --method elm, not --method {args.method}")
        if args.method == "stribeck":
            if args.max_neurons is not None:
                raise UsageError("--max-neurons caps the ELM of --method auto or elm_auto; "
                                 "--method stribeck has no neurons")
            return StribeckRegressor()
        make = default_estimator if args.method == "auto" else default_elm
        return make(args.seed, max_neurons=args.max_neurons)
    if args.max_neurons is not None:
        raise UsageError("--max-neurons caps --method auto and elm_auto; --neurons sets the size "
                         "of --method elm")
    for k, default in _ELM_OPTIONS.items():
        if getattr(args, k) is None:
            setattr(args, k, default)
    if args.solver == "ridge" and args.C is None:
        raise UsageError("--solver ridge needs --C")
    if args.C is not None and args.solver != "ridge":
        raise UsageError(f"--C sets the C of --solver ridge; --solver {args.solver} chooses its own")
    try:
        scheme = EnlargedScheme(w_max=args.w_max) if args.scheme == "enlarged" else args.scheme
    except ValueError as exc:
        raise UsageError(f"--w-max: {exc}") from None
    return ELMRegressor(n_hidden=args.neurons, activation=args.activation, scheme=scheme,
                        solver=args.solver, C=args.C, random_state=args.seed)


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


def fit_report(model: FrictionModel, dataset, estimator, errors=None) -> str:
    """The text ``fricgen train`` prints: data, model and errors (of one curve)."""
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
    if isinstance(estimator, DefaultRegressor):
        lines += [f"chose     {estimator.why()}", f"outliers  {estimator.outlier_note()}"]
        estimator = estimator.chosen_
    if isinstance(estimator, StribeckRegressor):
        lines += greybox_lines(estimator, dataset)
    else:
        lines += [f"model     {estimator.n_hidden} {estimator.activation} neurons, "
                  f"{estimator.scheme}, C = {estimator.C_:.3g}",
                  f"weights   ||beta|| = {estimator.beta_norm_:.4g}, log10 cond(H^T H) = "
                  f"{estimator.log10_cond_:.2f}"]
    lines.append(error_line(errors))
    if not isinstance(estimator, StribeckRegressor):
        lines.append(call_cost(estimator.n_hidden, estimator.activation))
    return "\n".join(lines)


def greybox_lines(estimator: StribeckRegressor, dataset) -> list:
    """The grey-box model of eq. (1) in SI units, each parameter +- its standard error."""
    net, se = estimator.network_, estimator.standard_errors_
    k_in, k_out = dataset.scaling.k_in, dataset.scaling.k_out
    broad = "" if estimator.xs_max_ <= XS_MAX else f", v_s up to {estimator.xs_max_ / k_in:.4g} m/s"
    lines = [f"model     grey-box eq. (1): {net.n_sources} {net.shape} source(s){broad}, chosen by "
             f"AIC among {len(estimator.candidates_)} fits",
             f"coulomb   sum f_c = {_estimate(net.offset / k_out, se['offset'] / k_out, 'N')}"]
    for k in range(net.n_sources):
        lines.append(f"source {k + 1:<2d} f_s - f_c = "
                     f"{_estimate(net.amplitudes[k] / k_out, se['amplitudes'][k] / k_out, 'N')}, "
                     f"v_s = {_estimate(net.stribeck[k] / k_in, se['stribeck'][k] / k_in, 'm/s')}")
    return lines


def _estimate(value: float, se: float, unit: str) -> str:
    """'value +- se unit', or a word where the data do not determine the parameter."""
    return (f"{value:.5g} +- {se:.2g} {unit}" if math.isfinite(se) else
            f"{value:.5g} {unit} (not determined by the data)")


def validation_error(estimator) -> tuple:
    """The kind and value of the error on held-out points that the fit report prints."""
    if isinstance(estimator, DefaultRegressor):
        return "cross-validated", estimator.cv_rmse_[estimator.choice_]
    if isinstance(estimator, StribeckRegressor):
        return "cross-validated", estimator.cv_rmse_
    return "leave-one-out", estimator.loo_rmse_


def _errors(dataset, estimator) -> dict:
    """The errors of the report; E_train over the points fitted (the gross outliers the default
    sets aside are not)."""
    fitted = estimator.inliers_ if isinstance(estimator, DefaultRegressor) else slice(None)
    e_train = rmse(estimator.predict(dataset.x[fitted]), dataset.t[fitted])
    kind, e_validation = validation_error(estimator)
    return {"e_train": e_train, "e_train_newton": e_train / dataset.scaling.k_out,
            "e_loo": e_validation, "e_loo_newton": e_validation / dataset.scaling.k_out,
            "e_validation_kind": kind}


def _curve_training(fit) -> dict:
    """model.json's training record of one fitted curve: what was chosen and its errors."""
    estimator = fit.estimator
    chosen = estimator.chosen_ if isinstance(estimator, DefaultRegressor) else estimator
    entry = {"activation": chosen.activation, "n_hidden": chosen.n_hidden}
    if isinstance(estimator, DefaultRegressor):
        entry.update(choice=estimator.choice_, choice_reason=estimator.why(),
                     n_outliers_rejected=estimator.n_outliers_)
    if isinstance(chosen, StribeckRegressor):
        se, s = chosen.standard_errors_, fit.dataset.scaling
        entry.update(shape=chosen.shape_, n_sources=chosen.n_sources_, standard_errors={
            "amplitudes_newton": (se["amplitudes"] / s.k_out).tolist(),
            "stribeck_m_per_s": (se["stribeck"] / s.k_in).tolist()})
    else:
        entry["C"] = chosen.C_
    entry["metrics"] = _errors(fit.dataset, estimator)
    return entry


def read_columns(args):
    """The input's columns by fricgen's names, read with the vendor-export options
    (``common.read_data``): a merge needs the rows of a log or of a sweep."""
    return read_data(args, args.sweep, lambda c: MIN_LOG_ROWS if is_log(c) else MIN_ROWS)


def source_name(args) -> str:
    """The input as messages name it: the file, or both files of a merge ("a.csv + b.csv")."""
    return common_source_name(args.sweep, args.merge)


def training_data(args):
    """The sweep to fit and, for a motion log, its identification (``data.inverse_dynamics``)."""
    columns = read_columns(args)
    source = source_name(args)
    if is_log(columns):
        with named_data(source):
            ident = identify_log(columns, args.mass, args.force_constant, progress=say)
        return ident.sweep, ident
    if not {"v", "f"} <= set(columns):
        written = None if args.merge else header_cells(args.sweep, args.skip)
        raise DataError(f"{source}: {describe_missing(columns, written)}")
    if args.mass is not None or args.force_constant is not None:
        raise UsageError(f"--mass and --force-constant apply to a motion log; {source} is a sweep (v, f)")
    return sweep_from_columns(columns, source), None


def stribeck_warning(ident, fits) -> str:
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


def axis_record(sweep, ident, asymmetric: bool) -> dict:
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


def run(args) -> int:
    with data_warnings(args):
        return _run(args)


def _run(args) -> int:
    inputs = [args.sweep] + ([args.merge] if args.merge else [])
    check_destination(args.output, inputs, args.force)
    name = check_model_name(args.name, "--name")
    sweep, ident = training_data(args)
    estimator = _estimator(args)
    with named_data(source_name(args)):
        fitted = fit_friction(sweep, estimator, None, ident, vs_max=args.vs_max,
                              asymmetric=args.asymmetric, seed=args.seed, progress=say)
    first = fitted.fits[0]
    options = {"scheme": args.method} if args.method != "elm" else {
        "scheme": args.scheme, "w_max": args.w_max, "solver": args.solver}
    curves = [_curve_training(f) for f in fitted.fits]
    training = {"method": args.method, **options, "seed": args.seed,
                "source": Path(args.sweep).name,
                "vs_max_estimated": first.dataset.vs_max_estimated, **curves[0]}
    if fitted.asymmetric:
        training["negative"] = curves[1]
    if fitted.cv_rmse is not None:
        training["cv_rmse_newton"] = dict(zip(("symmetric", "asymmetric"), fitted.cv_rmse))
    training["axis"] = axis_record(sweep, ident, fitted.asymmetric)
    if args.accept_unusual:
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
        raise DataError(f"{source_name(args)}: the fitted model is no friction model: {exc}") from None
    check_fitted(model, ident, source_name(args), args.accept_unusual, float(np.max(np.abs(sweep.v))))
    reports = [] if ident is None else [ident.summary(), ident.offset_line(fitted.asymmetric)]
    reports.append(_choice_line(fitted))
    for label, f, curve in zip(("v > 0:", "v < 0:") if fitted.asymmetric else ("",), fitted.fits, curves):
        text = fit_report(model, f.dataset, f.estimator, curve["metrics"])
        reports.append(text if not label else f"{label}\n" + "\n".join("  " + t for t in text.splitlines()))
    problem = float32_problem(model)
    if problem:
        reports.append(f"float32   {problem}; emit refuses it")
    say_data_warnings(args)
    out("\n".join(r for r in reports if r))
    if ident is not None:
        warning = stribeck_warning(ident, fitted.fits)
        if warning:
            say(warning)
    write_file(args, model.to_json(), inputs)
    say(f"wrote {args.output} (model {model.model_hash})")
    return 0


def check_fitted(model: FrictionModel, ident, source: str, accept_unusual: bool, fastest: float) -> None:
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
            say(f"fricgen: warning: {source}: {note}")
            break
    if ident is not None and ident.body.mass_identified:
        problems.append(physical_problem("mass", "the identified mass", ident.body.mass))
    for problem in filter(None, problems):
        if not accept_unusual:
            raise DataError(f"{source}: {problem}; are the units SI ({ACCEPT_UNUSUAL} to keep it)?")
        say(f"fricgen: warning: {source}: {problem}; kept ({ACCEPT_UNUSUAL})")


def _choice_line(fitted) -> str:
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


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("sweep", help="CSV with columns v (m/s) and f (N) (a sweep), or t (s), v (m/s) "
                   "or x (m), and force (N) or i (A) (a motion log); or a MATLAB .mat "
                   "file, its vectors the columns")
    add_output(p, "model.json to write (default model.json)", default="model.json")
    p.add_argument("--vs-max", type=positive_float, help="bound on the Stribeck velocities, m/s "
                   "(default: chosen by cross-validation from the data)")
    p.add_argument("--method", choices=["auto", "elm_auto", "stribeck", "elm"],
                   help="auto: the grey-box eq. (1) or the automatic ELM, whichever has the "
                   "smaller cross-validated error (default); elm_auto: the automatic ELM; "
                   "stribeck: the grey-box eq. (1); elm: the ELM the options below describe "
                   "(default when any of them is given)")
    p.add_argument("--max-neurons", type=number(1, MAX_HIDDEN, integer=True),
                   help="(auto, elm_auto) at most this many hidden units, e.g. for a firmware budget")
    p.add_argument("--neurons", type=number(1, MAX_HIDDEN, integer=True),
                   help=f"(elm) default {_ELM_OPTIONS['neurons']}")
    p.add_argument("--activation", choices=sorted(ACTIVATIONS),
                   help=f"(elm) default {_ELM_OPTIONS['activation']}")
    p.add_argument("--scheme", choices=sorted(SCHEMES), help="(elm) default enlarged")
    p.add_argument("--w-max", type=number(0, 1e4, low_open=True), help="(elm) input-weight range of the enlarged "
                   f"scheme, eq. (16)-(17), default {_ELM_OPTIONS['w_max']:g}")
    p.add_argument("--solver", choices=sorted(SOLVERS), help=f"(elm) default {_ELM_OPTIONS['solver']}")
    p.add_argument("--C", type=positive_float, help="regularization C of eq. (15) for --solver ridge")
    add_seed(p)
    symmetry = p.add_mutually_exclusive_group()
    symmetry.add_argument("--asymmetric", dest="asymmetric", action="store_const", const=True,
                          help="one curve per direction of motion (default: chosen by cross-validation)")
    symmetry.add_argument("--symmetric", dest="asymmetric", action="store_const", const=False,
                          help="one curve for both directions, F(-v) = -F(v)")
    log = p.add_argument_group("motion logs (inverse dynamics, eq. 18: F = force - m dv/dt)")
    log.add_argument("--mass", type=number(0, 1e6, low_open=True, unit="kg"),
                     help="moving mass of the axis, kg (default: identified from the log by inverse "
                     "dynamics; with a current log and no --force-constant, K is identified instead)")
    log.add_argument("--force-constant", type=number(0, 1e6, low_open=True, unit="N/A"),
                     help="force constant, N/A, for a log with current i instead of force")
    add_export_options(p)
    p.add_argument("--name", default=DEFAULT_MODEL_NAME,
                   help=f"model name, a C identifier not beginning with fric_ (default {DEFAULT_MODEL_NAME})")
    p.set_defaults(run=run)
