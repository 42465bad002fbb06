"""Small sweeps: the default against the true-structure least-squares fit, and its CPU time.

Sweeps are drawn from three laws written here, per direction, with 3 to 20 log-spaced speeds
from 2 mm/s to 0.5 m/s a side and Gaussian force noise of 0.05 N:
  - "linear": Coulomb + viscous, different in each direction (the law every point count
    determines: its oracle is exact from 2 points a side);
  - "textbook": Coulomb + viscous + an exponential Stribeck term, different in each direction
    (a law of fricgen's candidate family);
  - "drag": a squared-rational Stribeck drop and a quadratic drag, v |v| (a law outside it).
The oracle knows the structure: it fits that law's own parameters per direction by nonlinear
least squares (scipy), started as a user would start it (not at the truth). Both are scored by their RMS error against the
true curve over 200 speeds spanning the sweep. Seeds 1000-1019 (they tuned nothing); printed:
the median and the worst ratio default / oracle per point count.

At 3 points per direction the oracle is underdetermined (4 parameters, 3 points): its error
from other starts of v_s is printed beside the default's. Then the CPU time of ``fricgen.train`` (median of 5 runs, after one to import): a 40-point and
a 300-point sweep of the "drag" law, and a 300-point sweep of the paper's Table 1 (3 sources).

Run: python benchmarks/small_sweeps.py [--seeds 20]
"""
import argparse
import time

import numpy as np
from scipy.optimize import least_squares

import fricgen

NOISE = 0.05
POINTS = (3, 5, 8, 12, 20)


def linear_law(p, speed):
    coulomb, viscous = p
    return coulomb + viscous * speed


def textbook_law(p, speed):
    coulomb, static, v_s, viscous = p
    return coulomb + (static - coulomb) * np.exp(-speed / v_s) + viscous * speed


def drag_law(p, speed):
    coulomb, static, v_s, viscous, drag = p
    return coulomb + (static - coulomb) / (1.0 + (speed / v_s) ** 2) + viscous * speed + drag * speed ** 2


LAWS = {
    "linear": (linear_law, ([2.0, 10.0], [1.6, 8.0])),
    "textbook": (textbook_law, ([2.0, 3.0, 0.02, 10.0], [1.6, 2.2, 0.03, 8.0])),
    "drag": (drag_law, ([2.0, 3.0, 0.02, 6.0, 8.0], [1.6, 2.2, 0.03, 5.0, 6.0])),
}


def sweep(law, points, rng):
    form, (pos, neg) = LAWS[law]
    speed = np.geomspace(0.002, 0.5, points)
    v = np.concatenate([speed, -speed])
    f = np.concatenate([form(pos, speed), -form(neg, speed)])
    return v, f + NOISE * rng.standard_normal(f.size)


def truth(law, v):
    form, (pos, neg) = LAWS[law]
    return np.where(v > 0, form(pos, np.abs(v)), -form(neg, np.abs(v)))


def oracle(law, v, f, v_s=None):
    """The true structure fitted per direction by bounded least squares (all parameters >= 0),
    started where a user would start it: levels from the slowest and the fastest points, v_s at
    the speeds' geometric mean (or at ``v_s``), no drag."""
    form, params = LAWS[law]
    fitted = []
    for sign in (1, -1):
        m = np.sign(v) == sign
        speed, force = np.abs(v[m]), sign * f[m]
        order = np.argsort(speed)
        slope = max((force[order[-1]] - force[order[0]]) / (speed[order[-1]] - speed[order[0]]), 0.0)
        coulomb = max(force[order[-1]] - slope * speed[order[-1]], 0.0)
        start = ([coulomb, slope] if len(params[0]) == 2 else
                 [coulomb, max(force[order[0]], 0.0),
                  float(np.sqrt(speed.min() * speed.max())) if v_s is None else v_s, slope,
                  0.0][:len(params[0])])
        res = least_squares(lambda p: form(p, speed) - force, start, bounds=(0.0, np.inf))
        fitted.append(res.x)
    return lambda u: np.where(u > 0, form(fitted[0], np.abs(u)), -form(fitted[1], np.abs(u)))


def underdetermined(seeds, starts=(0.003, 0.01, 0.1, 0.3)):
    """At 3 points per direction the textbook law's 4 parameters fit every point exactly along
    a line of solutions: the oracle's error then depends on where its v_s starts. Printed: the
    median RMS errors of the default and of the oracle from each start."""
    grid = np.concatenate([np.geomspace(0.002, 0.5, 100), -np.geomspace(0.002, 0.5, 100)])
    runs = [sweep("textbook", 3, np.random.default_rng(seed)) for seed in range(1000, 1000 + seeds)]
    default = [rms(fricgen.train({"v": v, "f": f}, warn=lambda line: None).model.force(grid)
                   - truth("textbook", grid)) for v, f in runs]
    line = f"3 points, 'textbook' law, median RMS error (N): default {np.median(default):.3f}; oracle from v_s ="
    for v_s in (None,) + tuple(starts):
        error = [rms(oracle("textbook", v, f, v_s)(grid) - truth("textbook", grid)) for v, f in runs]
        line += f" {'geometric mean' if v_s is None else f'{v_s:g}'}: {np.median(error):.3f}"
    print(line + " (0.0316; the truth's v_s: 0.02 and 0.03)")


def rms(e):
    return float(np.sqrt(np.mean(np.square(e))))


def accuracy(seeds):
    print(f"{'law':9s} {'points/dir':>10s} {'median':>7s} {'worst':>7s}  (default / oracle, RMS error "
          "against the truth)")
    for law in LAWS:
        for points in POINTS:
            ratios = []
            for seed in range(1000, 1000 + seeds):
                v, f = sweep(law, points, np.random.default_rng(seed))
                grid = np.concatenate([np.geomspace(0.002, 0.5, 100), -np.geomspace(0.002, 0.5, 100)])
                model = fricgen.train({"v": v, "f": f}, warn=lambda line: None).model
                ratios.append(rms(model.force(grid) - truth(law, grid)) /
                              rms(oracle(law, v, f)(grid) - truth(law, grid)))
            print(f"{law:9s} {points:10d} {np.median(ratios):7.3f} {np.max(ratios):7.3f}")


def cpu(columns, runs=5):
    times = []
    for _ in range(runs):
        start = time.process_time()
        fricgen.train(columns, warn=lambda line: None)
        times.append(time.process_time() - start)
    return float(np.median(times))


def speed():
    rng = np.random.default_rng(1000)
    fricgen.train(dict(zip("vf", sweep("drag", 20, rng))), warn=lambda line: None)   # imports
    for points in (20, 150):
        v, f = sweep("drag", points, rng)
        print(f"{2 * points:4d}-point sweep ('drag' law): {cpu({'v': v, 'f': f}):.3f} s CPU (median of 5)")
    bench = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=1000)
    table = bench.train
    print(f"{len(table.v):4d}-point sweep (Table 1, 3 sources): "
          f"{cpu({'v': table.v, 'f': table.f}):.3f} s CPU (median of 5)")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=20)
    args = p.parse_args()
    accuracy(args.seeds)
    underdetermined(args.seeds)
    speed()


if __name__ == "__main__":
    main()
