"""``fricgen train``: fit a friction model to a sweep CSV and write model.json."""
from __future__ import annotations

from pathlib import Path

from ..data import prepare, read_sweep_csv
from .._validate import MAX_HIDDEN
from ..data.training_set import OUTLIER_SIGMAS
from ..errors import UsageError
from ..fit import (DEFAULT_ELM, DefaultRegressor, ELMRegressor, StribeckRegressor, default_elm,
                   default_estimator)
from ..fit.stribeck import XS_MAX
from ..fit.elm import SCHEMES, SOLVERS, EnlargedScheme
from ..metrics import rmse
from ..model import DEFAULT_MODEL_NAME, FrictionModel, check_model_name
from ..networks.elm import ACTIVATIONS
from .._io import check_destination
from .common import add_output, add_seed, number, out, positive_float, say, write_file

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
        return {"auto": default_estimator, "elm_auto": default_elm,
                "stribeck": lambda seed: StribeckRegressor()}[args.method](args.seed)
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


def fit_report(model: FrictionModel, dataset, estimator, errors=None) -> str:
    """The text ``fricgen train`` prints: data, model and errors."""
    s = dataset.scaling
    vs_note = " (estimated from the data; pass --vs-max to set it)" if dataset.vs_max_estimated else ""
    lines = [
        f"data      {dataset.x.size} training points in [0, v_sat], v_sat = {dataset.v_sat:.6g} m/s"
        f"{vs_note}" + (f"; the {dataset.n_rows} rows there averaged in bins of equal count"
                        if dataset.binned else ""),
        f"viscous   B = {dataset.viscous:.6g} N s/m from {dataset.n_high_speed} high-speed points"
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
    lines.append(f"errors    E_train = {errors['e_train']:.5f} ({errors['e_train_newton']:.4f} N), "
                 f"{errors['e_validation_kind']} = {errors['e_loo']:.5f} ({errors['e_loo_newton']:.4f} N)")
    return "\n".join(lines)


def greybox_lines(estimator: StribeckRegressor, dataset) -> list:
    """The grey-box model of eq. (1) in SI units, each parameter +- its standard error."""
    net, se = estimator.network_, estimator.standard_errors_
    k_in, k_out = dataset.scaling.k_in, dataset.scaling.k_out
    broad = "" if estimator.xs_max_ <= XS_MAX else f", v_s up to {estimator.xs_max_ / k_in:.4g} m/s"
    lines = [f"model     grey-box eq. (1): {net.n_sources} {net.shape} source(s){broad}, chosen by "
             f"AIC among {len(estimator.candidates_)} fits",
             f"coulomb   sum f_c = {net.offset / k_out:.5g} +- {se['offset'] / k_out:.2g} N"]
    for k in range(net.n_sources):
        lines.append(f"source {k + 1:<2d} f_s - f_c = {net.amplitudes[k] / k_out:.5g} +- "
                     f"{se['amplitudes'][k] / k_out:.2g} N, v_s = {net.stribeck[k] / k_in:.5g} +- "
                     f"{se['stribeck'][k] / k_in:.2g} m/s")
    return lines


def validation_error(estimator) -> tuple:
    """The kind and value of the error on held-out points that the fit report prints."""
    if isinstance(estimator, DefaultRegressor):
        return "cross-validated", estimator.cv_rmse_[estimator.choice_]
    if isinstance(estimator, StribeckRegressor):
        return "cross-validated", estimator.cv_rmse_
    return "leave-one-out", estimator.loo_rmse_


def run(args) -> int:
    check_destination(args.output, [args.sweep], args.force)
    name = check_model_name(args.name, "--name")
    sweep = read_sweep_csv(args.sweep)
    dataset = prepare(sweep, vs_max=args.vs_max)
    estimator = _estimator(args)
    options = {"scheme": args.method} if args.method != "elm" else {
        "scheme": args.scheme, "w_max": args.w_max, "solver": args.solver}
    model = FrictionModel.fit(dataset, estimator, name=name, training={
        "method": args.method, **options, "seed": args.seed, "source": Path(args.sweep).name,
        "vs_max_estimated": dataset.vs_max_estimated})
    chosen = estimator.chosen_ if isinstance(estimator, DefaultRegressor) else estimator
    model.training["activation"] = chosen.activation
    model.training["n_hidden"] = chosen.n_hidden
    if isinstance(estimator, DefaultRegressor):
        model.training.update(choice=estimator.choice_, choice_reason=estimator.why(),
                              n_outliers_rejected=estimator.n_outliers_)
    if isinstance(chosen, StribeckRegressor):
        model.training.update(shape=chosen.shape_, n_sources=chosen.n_sources_)
    else:
        model.training["C"] = chosen.C_
    e_train = rmse(estimator.predict(dataset.x), dataset.t)
    kind, e_validation = validation_error(estimator)
    errors = {"e_train": e_train, "e_train_newton": e_train / dataset.scaling.k_out,
              "e_loo": e_validation, "e_loo_newton": e_validation / dataset.scaling.k_out,
              "e_validation_kind": kind}
    model.training["metrics"] = errors
    out(fit_report(model, dataset, estimator, errors))
    write_file(args, model.to_json(), [args.sweep])
    say(f"wrote {args.output} (model {model.model_hash})")
    return 0


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("sweep", help="CSV with columns v (m/s) and f (N)")
    add_output(p, "model.json to write (default model.json)", default="model.json")
    p.add_argument("--vs-max", type=positive_float, help="bound on the Stribeck velocities, m/s "
                   "(default: estimated from the data)")
    p.add_argument("--method", choices=["auto", "elm_auto", "stribeck", "elm"],
                   help="auto: the grey-box eq. (1) or the automatic ELM, whichever has the "
                   "smaller cross-validated error (default); elm_auto: the automatic ELM; "
                   "stribeck: the grey-box eq. (1); elm: the ELM the options below describe "
                   "(default when any of them is given)")
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
    p.add_argument("--name", default=DEFAULT_MODEL_NAME,
                   help=f"model name, a C identifier not beginning with fric_ (default {DEFAULT_MODEL_NAME})")
    p.set_defaults(run=run)
