"""The default model (``fricgen train`` without options) against the honest oracle and elm_auto.

Sweeps as a user would record them: Table 1 friction, 200 noisy points uniform in [0, 3 vs_max]
plus 100 in (3, 10] vs_max, noise uniform in +-0.5 N, vs_max = 0.02 m/s, trained with
``--vs-max 0.02``. Error: RMSE of the model against the noise-free curve on (0, 3 vs_max].
Prints, as medians over the seeds:
  1. default / honest oracle ([F1] with the true shape and S = 3, fitted with and without the
     point at v = 0, the better of the two: ``oracle_error``) on the three shapes: the ratio
     of the median errors, the median of the per-sweep ratios (both fitted to the same training
     set) and the largest per-sweep ratio;
  2. default / elm_auto on two curves that are not sums of Stribeck curves;
  3. default with 2 % of the rows given +-20 N spikes / default on the clean rows.
Seeds start at 1000 (--first-seed): no constant of fricgen was tuned on seeds from 1000 up.
Run: python benchmarks/default_vs_oracle.py [--seeds 20]   (about 10 min on one core)
"""
import argparse
from dataclasses import replace

import numpy as np

from fricgen.data import prepare
from fricgen.data.sweep import Sweep
from fricgen.fit import AutoELMRegressor, DefaultRegressor, OracleRegressor
from fricgen.friction import preset
from fricgen.model import FrictionModel

VS_MAX = 0.02
V_GRID = np.linspace(0.0, 3 * VS_MAX, 601)[1:]


def sweep_velocities(rng):
    return np.concatenate([rng.uniform(0.0, 3 * VS_MAX, 200), rng.uniform(3 * VS_MAX, 10 * VS_MAX, 100)])


def sweep(curve, seed, spikes=0.0, noise="uniform"):
    """A noisy sweep of ``curve``: noise uniform in +-0.5 N, or ``noise="gauss"`` normal with the
    same standard deviation (0.29 N) and so unbounded; ``spikes``: the fraction of rows given
    +-20 N."""
    rng = np.random.default_rng(seed)
    v = sweep_velocities(rng)
    f = curve(v) + (rng.uniform(-0.5, 0.5, v.size) if noise == "uniform"
                    else rng.normal(0.0, 0.5 / np.sqrt(3.0), v.size))
    n = int(round(spikes * v.size))
    rows = rng.choice(v.size, n, replace=False)
    f[rows] += rng.choice([-20.0, 20.0], n)
    return Sweep(v, f)


def error(curve, data, estimator, grid=V_GRID):
    """RMSE (N) of the model fitted to ``data`` against ``curve`` on ``grid`` (Table 1's range)."""
    model = FrictionModel.fit(data, estimator)
    return float(np.sqrt(np.mean((model.force(grid) - curve(grid)) ** 2)))


def measured_points(data):
    """``data`` without its point at v = 0 (the mean of the slowest rows, section 2)."""
    return replace(data, x=data.x[data.x > 0], t=data.t[data.x > 0])


def oracle_error(curve, data, shape, grid=V_GRID):
    """The stronger honest oracle's RMSE (N): [F1] with the true shape and S = 3 fitted to every
    point of ``data`` and to its measured points alone (``measured_points``), the better of the
    two on ``curve``: the point at v = 0 helps a flat Stribeck start (gauss) and misleads a
    drop with a slope at 0 (exponential, rational)."""
    return min(error(curve, d, OracleRegressor(shape), grid) for d in (data, measured_points(data)))


def sqrt_viscous(v):
    """Table 1's Stribeck part with the viscous force 57.5 sqrt(0.2 |v|) sgn(v) in place of B v."""
    table1 = preset("paper3")
    return table1.stribeck(v) * np.sign(v) + 57.5 * np.sqrt(0.2 * np.abs(v)) * np.sign(v)


def measured_like(v):
    """A smooth Coulomb onset (tanh, 2 mm/s), a stretched-exponential Stribeck drop and B v."""
    a = np.abs(v)
    return np.sign(v) * (15.0 * np.tanh(a / 0.002) + 26.0 * np.exp(-(a / 0.01) ** 0.6)) + 57.5 * v


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first-seed", type=int, default=1000)
    args = parser.parse_args()
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    print(f"{'curve':14s} {'default N':>10s} {'oracle N':>9s} {'elm_auto N':>10s} "
          f"{'default/oracle':>14s} {'median':>7s} {'largest':>8s} {'default/elm_auto':>16s} "
          f"{'choices':>24s}")
    clean = {}
    for shape in ("gauss", "exponential", "rational"):
        curve = preset("paper3", shape)
        rows, choices = [], []
        for seed in seeds:
            data = prepare(sweep(curve, seed), vs_max=VS_MAX)
            default = DefaultRegressor()
            rows.append([error(curve, data, default), oracle_error(curve, data, shape),
                         float(np.sqrt(np.mean((FrictionModel.fit(data, default.elm_).force(V_GRID)
                                                - curve(V_GRID)) ** 2)))])
            choices.append(default.choice_)
        med = np.median(rows, axis=0)
        clean[shape] = med[0]
        ratios = [d / o for d, o, _ in rows]
        print(f"{shape:14s} {med[0]:10.4f} {med[1]:9.4f} {med[2]:10.4f} {med[0] / med[1]:14.3f} "
              f"{np.median(ratios):7.3f} {max(ratios):8.3f} {med[0] / med[2]:16.2f} "
              f"{choices.count('stribeck'):>3d} stribeck/{len(choices)}", flush=True)
    for name, curve in (("sqrt viscous", sqrt_viscous), ("measured-like", measured_like)):
        rows, choices = [], []
        for seed in seeds:
            data = prepare(sweep(curve, seed), vs_max=VS_MAX)
            default = DefaultRegressor()
            rows.append([error(curve, data, default), error(curve, data, AutoELMRegressor())])
            choices.append(default.choice_)
        med = np.median(rows, axis=0)
        print(f"{name:14s} {med[0]:10.4f} {'':9s} {med[1]:10.4f} {'':14s} {'':7s} {'':8s} {med[0] / med[1]:16.2f} "
              f"{choices.count('stribeck'):>3d} stribeck/{len(choices)}")
    print(f"\n{'spikes (2 %, +-20 N)':22s} {'default N':>10s} {'clean N':>8s} {'spiked/clean':>12s} "
          f"{'rejected':>9s}")
    for shape in ("gauss", "exponential", "rational"):
        curve = preset("paper3", shape)
        errors, rejected = [], []
        for seed in seeds:
            data = prepare(sweep(curve, seed, spikes=0.02), vs_max=VS_MAX)
            default = DefaultRegressor()
            errors.append(error(curve, data, default))
            rejected.append(default.n_outliers_ + data.n_outliers)
        med = float(np.median(errors))
        print(f"{shape:22s} {med:10.4f} {clean[shape]:8.4f} {med / clean[shape]:12.2f} "
              f"{np.median(rejected):9.0f}")


if __name__ == "__main__":
    main()
