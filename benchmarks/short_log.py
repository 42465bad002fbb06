"""A 0.28 s run-up (420 samples at 1.5 kHz) of an axis simulated apart from fricgen
(tests/independent_axis.py: its own friction law, integrator and sensors), trained by
``fricgen train`` with no option. For each seed (from 1000 up): the mass identified, the
independent samples and the parameter budget, the model's size, and the RMS error of the model's
friction against the true law on the speeds of the deceleration, beside a 4-parameter law
(Coulomb + viscous + one exponential Stribeck drop, least squares on the same friction samples).
Run: python benchmarks/short_log.py [--seeds 10]
"""
import argparse
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from independent_axis import MASS, friction, run_up  # noqa: E402

from fricgen.data.inverse_dynamics import identify_friction  # noqa: E402
from fricgen.fit import default_estimator  # noqa: E402
from fricgen.fit.directions import fit_friction  # noqa: E402
from fricgen.model import FrictionModel  # noqa: E402


def four_parameter(v, f):
    """Coulomb + viscous + exponential Stribeck drop, least squares (v > 0)."""
    def residual(p):
        fc, fs, vs, b = p
        return fc + fs * np.exp(-v / abs(vs)) + b * v - f
    return least_squares(residual, [np.median(f), 1.0, 0.05, 1.0]).x


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=10)
    seeds = range(1000, 1000 + parser.parse_args().seeds)
    print(f"{'seed':>5s} {'mass kg':>8s} {'indep':>6s} {'budget':>6s} {'model':>18s} {'params':>6s} "
          f"{'fricgen N':>9s} {'4-param N':>9s}")
    ratios = []
    for seed in seeds:
        t, x, force, v_true = run_up(seed)
        ident = identify_friction(t, force, None, x=x)
        fitted = fit_friction(ident.sweep, default_estimator(0), None, ident)
        model = FrictionModel.from_directions(*(f.curve for f in fitted.fits))
        chosen = fitted.fits[0].estimator.chosen_
        n = chosen.n_hidden
        params = 2 * n + 2 if chosen.activation == "stribeck" else 2 * n + 1
        braking = v_true[t >= 0.14]
        speeds = np.linspace(braking.min(), braking.max(), 200)
        err = float(np.sqrt(np.mean((model.force(speeds) - friction(speeds)) ** 2)))
        p = four_parameter(np.abs(ident.sweep.v), np.sign(ident.sweep.v) * ident.sweep.f)
        base = p[0] + p[1] * np.exp(-speeds / abs(p[2])) + p[3] * speeds
        err4 = float(np.sqrt(np.mean((base - friction(speeds)) ** 2)))
        ratios.append(err / err4)
        kind = f"{n} {chosen.activation}"
        print(f"{seed:5d} {ident.body.mass:8.3f} {ident.independent:6.0f} {ident.parameter_budget:6d} "
              f"{kind:>18s} {params:6d} {err:9.4f} {err4:9.4f}")
    print(f"\ntrue mass {MASS} kg; median fricgen / 4-parameter error ratio {np.median(ratios):.2f}, "
          f"worst {max(ratios):.2f}")


if __name__ == "__main__":
    main()
