"""The default ``fricgen train`` on asymmetric sweeps against a per-direction honest oracle.

Each seed draws two Table 1-like frictions of [F1], one per direction of motion: Table 1
with every f_c and f_s times a factor in [0.8, 1.4], every v_s times one in [0.6, 1] (so
vs_max <= 0.02 m/s) and B times one in [0.7, 1.3], each direction its own factors. The sweep of
each direction: 200 noisy points uniform in [0, 3 vs_max] plus 100 in (3, 10] vs_max, noise
uniform in +-0.5 N, vs_max = 0.02 m/s. Both methods get vs_max = 0.02 (``--vs-max 0.02``):
  default: ``fit_directions`` with fricgen's default estimator, as ``fricgen train`` runs it
           (symmetry by cross-validation, each direction its own grey-box [F1] or elm_auto);
  oracle:  [F1] with the true shape and S = 3 (``fricgen.fit.oracle``) fitted to each
           direction separately, with and without the point at v = 0, the better of the two.
Error: RMS force error against the true law on (0, 3 vs_max] of both directions. Prints per
shape the medians, the median ratio default / oracle and the worst single ratio.
Run: python benchmarks/asymmetric_vs_oracle.py [--seeds 10]   (about 30 s of CPU per seed)
"""
import argparse

import numpy as np

from default_vs_oracle import measured_points
from fricgen.data import prepare
from fricgen.data.sweep import Sweep
from fricgen.fit import OracleRegressor, default_estimator
from fricgen.fit.directions import fit_directions
from fricgen.friction import multisource, preset
from fricgen.model import Direction, FrictionModel

VS_MAX = 0.02
FIRST_SEED = 1000
SPEEDS = np.linspace(0.0, 3 * VS_MAX, 301)[1:]
V_GRID = np.concatenate([SPEEDS, -SPEEDS])


def table1_like(rng, shape):
    """Table 1 with its forces, Stribeck velocities and B scaled by random factors."""
    force, vs, b = rng.uniform(0.8, 1.4), rng.uniform(0.6, 1.0), rng.uniform(0.7, 1.3)
    sources = preset("paper3").sources
    return multisource([force * s.fc for s in sources], [force * s.fs for s in sources],
                       [vs * s.vs for s in sources], [b * s.B for s in sources], shape)


def half_sweep(rng, law):
    """One direction's noisy sweep of ``law`` at positive speeds."""
    v = np.concatenate([rng.uniform(0.0, 3 * VS_MAX, 200), rng.uniform(3 * VS_MAX, 10 * VS_MAX, 100)])
    return v, law(v) + rng.uniform(-0.5, 0.5, v.size)


def true_force(laws, v):
    """The asymmetric law: ``laws[0]`` for v > 0, ``laws[1]`` (mirrored) for v < 0."""
    return np.where(v > 0, laws[0](np.abs(v)), -laws[1](np.abs(v)))


def strongest_oracle(sweep, sign, law, shape):
    """The oracle's curve of one direction: fitted with and without the point at v = 0
    (``default_vs_oracle.measured_points``), the better of the two on ``law``."""
    data = prepare(sweep.direction(sign), vs_max=VS_MAX)
    fits = [Direction.fit(d, OracleRegressor(shape)) for d in (data, measured_points(data))]
    return min(fits, key=lambda d: np.mean((FrictionModel.from_directions(d).force(SPEEDS)
                                            - law(SPEEDS)) ** 2))


def run_seed(shape, seed):
    """(default error, oracle error, symmetry chosen, per-direction choices) of one seed."""
    rng = np.random.default_rng(seed)
    laws = (table1_like(rng, shape), table1_like(rng, shape))
    (vp, fp), (vn, fn) = half_sweep(rng, laws[0]), half_sweep(rng, laws[1])
    sweep = Sweep(np.concatenate([vp, -vn]), np.concatenate([fp, -fn]))
    fitted = fit_directions(sweep, default_estimator(0), vs_max=VS_MAX, seed=0)
    default = FrictionModel.from_directions(*(f.curve for f in fitted.fits))
    oracle = FrictionModel.from_directions(*(strongest_oracle(sweep, sign, law, shape)
                                             for sign, law in ((1, laws[0]), (-1, laws[1]))))
    truth = true_force(laws, V_GRID)
    errors = [float(np.sqrt(np.mean((m.force(V_GRID) - truth) ** 2))) for m in (default, oracle)]
    return errors + [fitted.asymmetric, [f.estimator.choice_ for f in fitted.fits]]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10, help="seeds per shape, from 1000 (default 10)")
    seeds = range(FIRST_SEED, FIRST_SEED + parser.parse_args().seeds)
    print(f"{'shape':12s} {'default N':>10s} {'oracle N':>9s} {'median ratio':>12s} "
          f"{'worst ratio':>11s} {'asymmetric':>10s} {'[F1] curves':>14s}")
    for shape in ("gauss", "exponential", "rational"):
        rows = [run_seed(shape, seed) for seed in seeds]
        default, oracle = (np.array([r[k] for r in rows]) for k in (0, 1))
        ratio = default / oracle
        worst = int(np.argmax(ratio))
        choices = [c for r in rows for c in r[3]]
        print(f"{shape:12s} {np.median(default):10.4f} {np.median(oracle):9.4f} "
              f"{np.median(ratio):12.3f} {ratio[worst]:7.3f} ({seeds[worst]}) "
              f"{sum(r[2] for r in rows):>4d}/{len(rows):<5d} "
              f"{choices.count('stribeck'):>8d}/{len(choices)}")


if __name__ == "__main__":
    main()
