"""``fricgen train``: fit a friction model to a sweep CSV and write model.json."""
from __future__ import annotations

from pathlib import Path

from ..data import prepare, read_sweep_csv
from .._validate import MAX_HIDDEN
from ..data.training_set import OUTLIER_SIGMAS
from ..codegen.cost import cortex_m4f_instructions, host_ns
from ..errors import UsageError
from ..fit import DEFAULT_ELM, ELMRegressor, default_estimator
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
    if args.method == "auto":
        if given:
            raise UsageError(f"{flags} configure --method elm, not --method auto")
        return default_estimator(args.seed, max_neurons=args.max_neurons)
    if args.max_neurons is not None:
        raise UsageError("--max-neurons caps --method auto; --neurons sets the size of --method elm")
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
        f"model     {estimator.n_hidden} {estimator.activation} neurons, {estimator.scheme}, "
        f"C = {estimator.C_:.3g}",
        f"weights   ||beta|| = {estimator.beta_norm_:.4g}, log10 cond(H^T H) = {estimator.log10_cond_:.2f}",
        f"errors    E_train = {errors['e_train']:.5f} ({errors['e_train_newton']:.4f} N), "
        f"leave-one-out = {errors['e_loo']:.5f} ({errors['e_loo_newton']:.4f} N)",
        call_cost(estimator.n_hidden, estimator.activation),
    ]
    return "\n".join(lines)


def run(args) -> int:
    check_destination(args.output, [args.sweep], args.force)
    name = check_model_name(args.name, "--name")
    sweep = read_sweep_csv(args.sweep)
    dataset = prepare(sweep, vs_max=args.vs_max)
    estimator = _estimator(args)
    options = {"scheme": "auto"} if args.method == "auto" else {
        "scheme": args.scheme, "w_max": args.w_max, "solver": args.solver}
    model = FrictionModel.fit(dataset, estimator, name=name, training={
        "method": args.method, **options, "activation": estimator.activation,
        "seed": args.seed, "source": Path(args.sweep).name,
        "vs_max_estimated": dataset.vs_max_estimated})
    model.training["n_hidden"] = estimator.n_hidden
    model.training["C"] = estimator.C_
    e_train = rmse(estimator.predict(dataset.x), dataset.t)
    errors = {"e_train": e_train, "e_train_newton": e_train / dataset.scaling.k_out,
              "e_loo": estimator.loo_rmse_, "e_loo_newton": estimator.loo_rmse_ / dataset.scaling.k_out}
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
    p.add_argument("--method", choices=["auto", "elm"],
                   help="auto: units, M and C chosen by leave-one-out (default); elm: the ELM "
                   "the options below describe (default when any of them is given)")
    p.add_argument("--max-neurons", type=number(1, MAX_HIDDEN, integer=True),
                   help="(auto) at most this many hidden units, e.g. for a firmware budget")
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
