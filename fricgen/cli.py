"""fricgen: train friction models, emit them as C, simulate, reproduce the paper, diagnose.

Every command reports bad input as one line ``fricgen: error: ...`` on stderr, exits with code
2, and leaves no output file behind.
"""
from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

from . import __version__
from .data import DataError, prepare, read_sweep_csv, rmse, sweep_csv_text, synthesize_benchmark
from .elm import ACTIVATIONS, DEFAULT_ELM, SCHEMES, SOLVERS, ELMRegressor, EnlargedScheme, default_elm
from .codegen import ACTIVATION_IMPLS, DTYPES
from .files import write_atomic
from .friction import PRESETS, SHAPES, preset
from .model import FrictionModel, ModelError, check_c_identifier
from . import paper, reproduce
from . import simulate_cmd
from . import diagnose_report, logsynth


class UsageError(ValueError):
    """Bad command-line input that is neither a data nor a model problem."""


def _say(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def _positive(text: str) -> float:
    value = float(text)
    if not (np.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


# ----------------------------------------------------------------------------- synth


def cmd_synth(args) -> int:
    """Write a measured-style sweep (v, f) of a preset: the paper benchmark's training data."""
    bench = synthesize_benchmark(preset(args.preset, args.shape), seed=args.seed, noise=args.noise)
    sweep = bench.train
    if args.both_signs:
        flip = np.random.default_rng(args.seed + 1).uniform(size=len(sweep)) < 0.5
        sweep = type(sweep)(np.where(flip, -sweep.v, sweep.v), np.where(flip, -sweep.f, sweep.f))
    write_atomic(args.output, sweep_csv_text(sweep))
    _say(f"wrote {len(sweep)} rows ({args.preset}, {args.shape} shape, noise +-{args.noise} N) "
         f"to {args.output}")
    return 0


# ----------------------------------------------------------------------------- train


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
        return default_elm(args.seed)
    for k, default in _ELM_OPTIONS.items():
        if getattr(args, k) is None:
            setattr(args, k, default)
    if args.solver == "ridge" and args.C is None:
        raise UsageError("--solver ridge needs --C")
    scheme = EnlargedScheme(w_max=args.w_max) if args.scheme == "enlarged" else args.scheme
    return ELMRegressor(n_hidden=args.neurons, activation=args.activation, scheme=scheme,
                        solver=args.solver, C=args.C, random_state=args.seed)


def fit_report(model: FrictionModel, dataset, estimator, errors=None) -> str:
    """The text ``fricgen train`` prints: data, model and errors."""
    s = dataset.scaling
    vs_note = " (estimated from the data; pass --vs-max to set it)" if dataset.vs_max_estimated else ""
    lines = [
        f"data      {dataset.x.size} training points in [0, v_sat], v_sat = {dataset.v_sat:.6g} m/s"
        f"{vs_note}",
        f"viscous   B = {dataset.viscous:.6g} N s/m from {dataset.n_high_speed} high-speed points",
        f"scaling   K_in = {s.k_in:.6g} 1/(m/s), K_out = {s.k_out:.6g} 1/N",
        f"model     {estimator.n_hidden} {estimator.activation} neurons, {estimator.scheme}, "
        f"C = {estimator.C_:.3g}",
        f"weights   ||beta|| = {estimator.beta_norm_:.4g}, log10 cond(H^T H) = {estimator.log10_cond_:.2f}",
        f"errors    E_train = {errors['e_train']:.5f} ({errors['e_train_newton']:.4f} N), "
        f"leave-one-out = {errors['e_loo']:.5f} ({errors['e_loo_newton']:.4f} N)",
    ]
    return "\n".join(lines)


def cmd_train(args) -> int:
    sweep = read_sweep_csv(args.sweep)
    dataset = prepare(sweep, vs_max=args.vs_max)
    estimator = _estimator(args)
    name = check_c_identifier(args.name, "--name")
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
    model.save(args.output)
    print(fit_report(model, dataset, estimator, errors))
    print(f"wrote {args.output} (model {model.model_hash})")
    return 0


# ----------------------------------------------------------------------------- eval


def cmd_eval(args) -> int:
    model = FrictionModel.load(args.model)
    values = []
    for n, line in enumerate(sys.stdin, start=1):
        text = line.strip()
        if not text:
            continue
        try:
            value = float(text)
        except ValueError:
            raise UsageError(f"stdin line {n}: not a number: {text[:40]!r}") from None
        if not np.isfinite(value):
            raise UsageError(f"stdin line {n}: velocity must be finite, got {text[:40]}")
        values.append(value)
    forces = model.force(np.array(values, dtype=float))
    sys.stdout.write("".join(f"{f!r}\n" for f in forces.tolist()))
    return 0


# ----------------------------------------------------------------------------- emit


def cmd_emit(args) -> int:
    from .codegen import emit

    model = FrictionModel.load(args.model)
    name = check_c_identifier(args.name if args.name else model.name, "--name")
    written = emit(model, args.output, name, activation_impl=args.activation_impl, dtype=args.dtype)
    _say(f"wrote {', '.join(sorted(written))} to {args.output} (model {model.model_hash})")
    return 0


# ----------------------------------------------------------------------------- demo


def _mean_errors(make, seeds):
    rows = []
    for seed in seeds:
        bench = synthesize_benchmark(preset("paper3"), seed=seed)
        est = make(seed).fit(bench.dataset.x, bench.dataset.t)
        e = bench.errors(est.predict)
        rows.append([e["e_train"], e["e_test"], e["e_ttest"], e["e_ttest_newton"],
                     est.beta_norm_, est.log10_cond_])
    return np.mean(rows, axis=0), float(np.median(np.array(rows)[:, 3]))


def cmd_demo(args) -> int:
    from .cbuild import build_model
    from .codegen import emit
    from . import parity

    seeds = range(args.seeds)
    _say(f"paper benchmark (Table 1, 3 sources), {args.seeds} seeds")
    makers = {label: (lambda s, cfg=cfg: ELMRegressor(random_state=s, **cfg))
              for label, cfg in paper.HEADLINE_ELMS.items()}
    makers["elm_loo (M=40, C by LOO)"] = lambda s: ELMRegressor(random_state=s, **DEFAULT_ELM)
    makers["fricgen default (auto)"] = default_elm
    print(f"{'model':28s} {'E_train':>8s} {'E_test':>8s} {'E_Ttest':>8s} {'E_Ttest N':>10s} "
          f"{'median N':>9s} {'||beta||':>10s} {'log10cond':>9s}   paper [E_train, E_test, E_Ttest]")
    for label, make in makers.items():
        means, median_n = _mean_errors(make, seeds)
        reported = paper.REPORTED.get(label)
        ref = f"[{', '.join(f'{r:.4f}' for r in reported)}]" if reported else "-"
        print(f"{label:28s} {means[0]:8.4f} {means[1]:8.4f} {means[2]:8.4f} {means[3]:10.4f} "
              f"{median_n:9.4f} {means[4]:10.3g} {means[5]:9.2f}   {ref}")
    print("(normalized errors depend on the unspecified K_out; compare ratios and newtons)")

    bench = synthesize_benchmark(preset("paper3"), seed=0)
    model = FrictionModel.fit(bench.dataset, default_elm(0), name="fm")
    out = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="fricgen_demo_"))
    try:
        emit(model, out, "fm")
        _say(f"emitted C to {out}; compiling with cffi ...")
        lib = build_model(out, "fm", build_dir=out / "build")
        p = parity.measure(model, lib, "fm")
    finally:
        if not args.out:
            shutil.rmtree(out, ignore_errors=True)
    print(f"C parity over {p['n_velocities']} velocities: max |C - float32 twin| = "
          f"{p['max_abs_c_vs_twin']:.3g} N ({p['n_not_bit_equal']} not bit-equal), "
          f"max |C - float64 model| / max|F| = {p['max_rel_c_vs_model']:.3g}")
    return 0


# ----------------------------------------------------------------------------- main


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="fricgen", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"fricgen {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("demo", help="paper benchmark -> default model -> C -> measured parity")
    p.add_argument("--seeds", type=int, default=paper.SEEDS, help="runs to average (default 20)")
    p.add_argument("--out", help="keep the emitted C in this folder (default: a temporary one)")
    p.set_defaults(run=cmd_demo)

    p = sub.add_parser("synth", help="write a measured-style friction sweep (CSV v,f)")
    p.add_argument("--preset", choices=sorted(PRESETS), default="paper3")
    p.add_argument("--shape", choices=sorted(SHAPES), default="gauss")
    p.add_argument("--noise", type=float, default=0.5, help="uniform noise half-width, N")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--both-signs", action="store_true", help="mirror a random half to v < 0")
    p.add_argument("-o", "--output", required=True)
    p.set_defaults(run=cmd_synth)

    p = sub.add_parser("train", help="fit a friction model to a sweep CSV; write model.json")
    p.add_argument("sweep")
    p.add_argument("-o", "--output", default="model.json")
    p.add_argument("--vs-max", type=float, help="bound on the Stribeck velocities, m/s "
                   "(default: estimated from the data)")
    p.add_argument("--method", choices=["auto", "elm"],
                   help="auto: units, M and C chosen by leave-one-out (default); elm: the ELM "
                   "the options below describe (default when any of them is given)")
    p.add_argument("--neurons", type=int, help=f"(elm) default {_ELM_OPTIONS['neurons']}")
    p.add_argument("--activation", choices=sorted(ACTIVATIONS),
                   help=f"(elm) default {_ELM_OPTIONS['activation']}")
    p.add_argument("--scheme", choices=sorted(SCHEMES), help="(elm) default enlarged")
    p.add_argument("--w-max", type=_positive, help="(elm) input-weight range of the enlarged "
                   f"scheme, eq. (16)-(17), default {_ELM_OPTIONS['w_max']:g}")
    p.add_argument("--solver", choices=sorted(SOLVERS), help=f"(elm) default {_ELM_OPTIONS['solver']}")
    p.add_argument("--C", type=_positive, help="regularization C of eq. (15) for --solver ridge")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--name", default="fric_model", help="model name (a C identifier)")
    p.set_defaults(run=cmd_train)

    reproduce.register(sub)

    p = sub.add_parser("eval", help="forces (N) for velocities read from stdin, one per line")
    p.add_argument("model")
    p.set_defaults(run=cmd_eval)

    p = sub.add_parser("emit", help="write NAME.h, NAME.c and the C runtime into a folder")
    p.add_argument("model")
    p.add_argument("-o", "--output", required=True, help="output folder")
    p.add_argument("--name", help="C name prefix (default: the model's name)")
    p.add_argument("--activation-impl", choices=ACTIVATION_IMPLS, default="libm",
                   help="sigmoid through libm's expf, or the fast one without libm (error <= 8.7e-7)")
    p.add_argument("--dtype", choices=DTYPES, default="float",
                   help="float, or integer-only fixed point for MCUs without FPU")
    p.set_defaults(run=cmd_emit)
    simulate_cmd.register(sub)
    diagnose_report.register(sub)
    logsynth.register(sub)
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except (DataError, ModelError, UsageError) as exc:
        _say(f"fricgen: error: {exc}")
        return 2
    except OSError as exc:
        _say(f"fricgen: error: {exc.filename or ''}: {exc.strerror}")
        return 2


if __name__ == "__main__":
    sys.exit(main())
