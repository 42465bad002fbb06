"""fricgen diagnose on logs of a second simulator, written apart from ``fricgen.sim``.

Nothing of ``fricgen.sim`` is used: the plant, its friction, the controller, the sensors and the
hidden effects are defined here, with other assumptions than the scenarios' generator.

- Plant: a mass with LuGre friction (bristle state z, dz/dt = v - sigma0 |v| z / g(v),
  F = sigma0 z + sigma1 dz/dt + sigma2 v, g a Gaussian Stribeck curve), so the friction has
  pre-sliding dynamics that no static curve holds (``--friction static``: its steady-state
  curve, with a tanh of 0.1 mm/s for the sign, instead); integrated by fourth-order
  Runge-Kutta at SUBSTEPS steps per sample, the current held over each sample.
- Controller: PID on position with acceleration feed-forward of the nominal mass, and the
  current limited; the reference is a sum of three sinusoids with random amplitudes, periods
  and phases (reversals at many speeds).
- Sensors: position quantized to 1 um, velocity by the backward difference of the quantized
  position (half a sample late), current with white noise; 1 kHz.
- The user's model: ``fricgen``'s default fitted to a steady-state speed sweep of the nominal
  plant (sigma2 v + g(v), with noise), vs_max chosen from the data; with ``--user-model
  bristles``, that model with the plant's LuGre bristles (sigma0, sigma1), as a model trained
  with pre-sliding carries them, so that diagnose runs them in its residual and simulations.
- Hidden effects (``EFFECTS`` below), each at a size of its own, as physical forces: a
  constant load, cogging with two harmonics, friction varying with position, an asymmetric
  Coulomb level, friction falling as the axis warms, an extra Stribeck source, a Stribeck
  curve that lags the velocity, a tight spot over 2 % of the travel, a mass and a force
  constant other than the nominal ones.

With ``--presliding``, diagnose also considers the contact's pre-sliding (``diagnose
--presliding``); on LuGre logs it is then a true name beside the hidden effect's (the plant has
it), and the truth's model carries the plant's bristles.

The truth of a log is the user's model with the hidden effects' exact force taken out of the
current and the true mass (as ``diagnose_confusion.py`` scores it); an effect is visible when
the truth shrinks the held-out gap by at least the guard's ``min_gain``. Prints, for every
hidden effect and for null logs: the named sets, exact names on visible logs, the gap before,
after and the truth's, and diagnose's gap over the truth's.

    python benchmarks/second_simulator.py [--seeds 3] [--first-seed 1000] [--jobs 2]
        [--friction lugre|static] [--user-model static|bristles] [--presliding] [--kinds KIND ...]
"""
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import dataclasses
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from fricgen.data import MotionLog, Sweep, prepare
from fricgen.effects.presliding import Bristles
from fricgen.diagnose.diagnoser import Diagnoser, candidates_with, diagnose
from fricgen.fit import DefaultRegressor
from fricgen.model import FrictionModel

RATE = 1000.0
DURATION = 30.0
SUBSTEPS = 10
#: The names fricgen may rightly give each hidden effect (one of them, alone).
EFFECTS = {"none": (), "load": ("constant_load",), "cogging": ("position_ripple",),
           "position_friction": ("position_friction",), "asymmetry": ("direction_asymmetry",),
           "warming": ("thermal_drift",), "extra_source": ("extra_friction_source",),
           "lag": ("frictional_lag",), "tight_spot": ("table_position", "table_position_friction"),
           "mass": ("inertia_mismatch",), "force_constant": ("force_constant_mismatch",)}


def draw_axis(rng):
    """The nominal plant: mass (kg), force constant (N/A), LuGre and Stribeck constants."""
    m = rng.uniform(1.0, 8.0)
    fc = rng.uniform(2.0, 10.0)
    return {"m": m, "kt": rng.uniform(0.5, 3.0), "fc": fc, "fs": fc * rng.uniform(1.3, 2.0),
            "vs": rng.uniform(0.004, 0.02), "sigma0": 2e4 * fc, "sigma1": 2.0 * np.sqrt(2e4 * fc * m) * 0.2,
            "sigma2": fc * rng.uniform(5.0, 30.0)}


def stribeck(axis, v):
    """g(v) of the LuGre model: the steady sliding friction level at speed |v|."""
    return axis["fc"] + (axis["fs"] - axis["fc"]) * np.exp(-(v / axis["vs"]) ** 2)


def steady_friction(axis, v):
    """LuGre friction at constant speed v."""
    return np.sign(v) * stribeck(axis, v) + axis["sigma2"] * v


def user_model(axis, rng, v_max, bristles=False):
    """fricgen's default on a noisy steady-state sweep of the nominal plant to 1.5 v_max; with
    ``bristles``, carrying the plant's LuGre bristles."""
    v = rng.uniform(0.0005, 1.5 * v_max, 400)
    f = steady_friction(axis, v) + rng.normal(0.0, 0.01 * axis["fc"], v.size)
    model = FrictionModel.fit(prepare(Sweep(v, f)), DefaultRegressor())
    if bristles:
        model = dataclasses.replace(model, presliding=Bristles(axis["sigma0"], axis["sigma1"]))
    return model


class Hidden:
    """A hidden effect's physical force (N, resisting +v when positive), its state, and the
    plant's true mass and force constant."""

    def __init__(self, kind, axis, rng, travel, duration):
        self.kind, self.axis = kind, axis
        fc = axis["fc"]
        self.m, self.kt = axis["m"], axis["kt"]
        self.size = {"load": 0.4 * fc, "cogging": 0.15 * fc, "position_friction": 0.3,
                     "asymmetry": 0.4 * fc, "warming": 0.35, "extra_source": 0.6 * fc,
                     "lag": 0.03, "tight_spot": 0.8 * fc}.get(kind, 0.0)
        self.period = travel / rng.uniform(4.0, 9.0)            # cogging, position friction
        self.phase = rng.uniform(0, 2 * np.pi)
        self.spot = rng.uniform(0.3, 0.7) * travel - travel / 2  # tight spot's centre
        self.width = 0.01 * travel                               # 2 % of the travel
        self.tau = duration / 3.0                                # warming time constant
        self.vs2 = 6.0 * axis["vs"]                               # the extra source's speed
        if kind == "mass":
            self.m *= rng.choice([0.7, 1.4])
        if kind == "force_constant":
            self.kt *= rng.choice([0.85, 1.15])

    def force(self, t, x, v, friction, v_lag):
        """The effect's force beside the LuGre friction ``friction``."""
        k, s = self.kind, self.size
        smooth_sign = np.tanh(v / 1e-3)
        if k == "load":
            return s
        if k == "cogging":
            u = 2 * np.pi * x / self.period + self.phase
            return s * (np.sin(u) + 0.5 * np.sin(2 * u + 1.0) + 0.25 * np.sin(3 * u + 2.0))
        if k == "position_friction":
            return s * np.sin(2 * np.pi * x / self.period + self.phase) * friction
        if k == "asymmetry":
            return s * smooth_sign * (v < 0)
        if k == "warming":
            return -s * (1.0 - np.exp(-t / self.tau)) * friction
        if k == "extra_source":
            return s * smooth_sign * np.exp(-(v / self.vs2) ** 2)
        if k == "lag":        # the Stribeck level follows the speed with a lag
            return smooth_sign * (stribeck(self.axis, v_lag) - stribeck(self.axis, v))
        if k == "tight_spot":
            return s * smooth_sign * np.exp(-0.5 * ((x - self.spot) / self.width) ** 2)
        return 0.0


def simulate(axis, hidden, rng, duration=DURATION, rate=RATE, friction_law="lugre"):
    """The closed loop: (MotionLog, hidden force in nominal terms (N) at each sample)."""
    n = int(duration * rate)
    h = 1.0 / rate
    amp = rng.uniform(0.2, 1.0, 3) * np.array([0.06, 0.012, 0.003])
    freq = rng.uniform(0.8, 1.25, 3) * np.array([0.25, 1.1, 3.3])
    phase = rng.uniform(0, 2 * np.pi, 3)

    def reference(t):
        w = 2 * np.pi * freq
        return (np.sum(amp * np.sin(w * t + phase)), np.sum(amp * w * np.cos(w * t + phase)),
                -np.sum(amp * w * w * np.sin(w * t + phase)))

    m_nom, kt_nom = axis["m"], axis["kt"]
    omega = 2 * np.pi * 25.0
    kp, kd, ki = m_nom * omega ** 2, 2 * 0.8 * m_nom * omega, m_nom * omega ** 3 / 10
    i_max = 20.0 * axis["fs"] / kt_nom
    lag_tau = hidden.size if hidden.kind == "lag" else 0.0

    def derivatives(t, state, current):
        x, v, z, v_lag = state
        g = stribeck(axis, v)
        dz = v - axis["sigma0"] * abs(v) * z / g
        friction = axis["sigma0"] * z + axis["sigma1"] * dz + axis["sigma2"] * v
        if friction_law == "static":
            friction = np.tanh(v / 1e-4) * g + axis["sigma2"] * v
        extra = hidden.force(t, x, v, friction, v_lag)
        a = (hidden.kt * current - friction - extra) / hidden.m
        dlag = (v - v_lag) / lag_tau if lag_tau else 0.0
        return np.array([v, a, dz, dlag]), extra

    state = np.zeros(4)
    state[0] = reference(0.0)[0]
    t_log = np.arange(n) * h
    x_log, v_log, i_log, hidden_log = (np.empty(n) for _ in range(4))
    x_prev = np.round(state[0] * 1e6) / 1e6
    integral = 0.0
    for k in range(n):
        t = t_log[k]
        x_meas = np.round(state[0] * 1e6) / 1e6
        v_meas = (x_meas - x_prev) / h if k else 0.0
        x_prev = x_meas
        r, rd, rdd = reference(t)
        error = r - x_meas
        integral += error * h
        current = (m_nom * rdd + kp * error + kd * (rd - v_meas) + ki * integral) / kt_nom
        current = float(np.clip(current, -i_max, i_max))
        i_meas = current + rng.normal(0.0, 0.002 * i_max)
        _, extra = derivatives(t, state, current)
        x_log[k], v_log[k], i_log[k] = x_meas, v_meas, i_meas
        # in the nominal axis's terms: the effect's force, and the force constant's error
        hidden_log[k] = extra - (hidden.kt - kt_nom) * current
        dt = h / SUBSTEPS
        for j in range(SUBSTEPS):
            tj = t + j * dt
            k1 = derivatives(tj, state, current)[0]
            k2 = derivatives(tj + dt / 2, state + dt / 2 * k1, current)[0]
            k3 = derivatives(tj + dt / 2, state + dt / 2 * k2, current)[0]
            k4 = derivatives(tj + dt, state + dt * k3, current)[0]
            state = state + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return MotionLog(t_log, x_log, v_log, i_log), hidden_log


def run(case):
    """Simulate, diagnose and score one log: a dict of figures."""
    kind, seed, friction_law, bristles, presliding = case
    rng = np.random.default_rng(seed)
    axis = draw_axis(rng)
    travel = 2 * 0.075
    hidden = Hidden(kind, axis, rng, travel, DURATION)
    start = time.time()
    log, hidden_force = simulate(axis, hidden, rng, friction_law=friction_law)
    model = user_model(axis, rng, float(np.max(np.abs(log.v))), bristles)
    d = diagnose(log, model, axis["m"], axis["kt"],
                 candidates=candidates_with("presliding") if presliding else None)
    truth = MotionLog(log.t, log.x, log.v, log.i - hidden_force / axis["kt"])
    true_model = model
    if presliding and friction_law == "lugre":       # the plant's contact is part of the truth
        true_model = dataclasses.replace(model, presliding=Bristles(axis["sigma0"], axis["sigma1"]))
    gap_truth = Diagnoser().held_out_gap(truth, true_model, hidden.m, axis["kt"])
    found = d.model_.presliding if model.presliding is None else None
    return {"kind": kind, "seed": seed, "effects": [s.effect for s in d.effects_],
            "stiffness": None if found is None else found.stiffness / axis["sigma0"],
            "damping": None if found is None else found.damping / axis["sigma1"],
            "gap_before": d.gap_before_, "gap_after": d.gap_after_, "gap_truth": gap_truth,
            "seconds": time.time() - start}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--first-seed", type=int, default=1000)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--kinds", nargs="+", default=list(EFFECTS), choices=list(EFFECTS))
    parser.add_argument("--friction", choices=("lugre", "static"), default="lugre")
    parser.add_argument("--user-model", choices=("static", "bristles"), default="static")
    parser.add_argument("--presliding", action="store_true")
    args = parser.parse_args()
    cases = [(kind, args.first_seed + 100 * j + s, args.friction, args.user_model == "bristles",
              args.presliding)
             for j, kind in enumerate(EFFECTS)
             if kind in args.kinds for s in range(args.seeds)]
    min_gain = Diagnoser().min_gain
    with ProcessPoolExecutor(args.jobs) as pool:
        records = list(pool.map(run, cases))
    print(f"{'hidden':18s} {'seed':>5s} {'named':40s} {'visible':>7s} {'exact':>5s} "
          f"{'before':>7s} {'after':>7s} {'truth':>7s} {'after/truth':>11s}")
    totals = {"visible": 0, "exact": 0, "within": 0, "hidden": 0, "null": 0, "false": 0}
    # the plant's own pre-sliding is a true name on its LuGre logs, beside the hidden effect's
    plant = ("presliding",) if args.presliding and args.friction == "lugre" else ()
    for r in records:
        want = EFFECTS[r["kind"]]
        named = [e for e in r["effects"] if e not in plant]
        visible = bool(want) and r["gap_truth"] <= (1 - min_gain) * r["gap_before"]
        exact = len(named) == len(want[:1]) and all(e in want for e in named)
        ratio = r["gap_after"] / r["gap_truth"]
        if not want:
            totals["null"] += 1
            totals["false"] += bool(named)
        else:
            totals["hidden"] += 1
            totals["within"] += ratio <= 1.1
            totals["visible"] += visible
            totals["exact"] += visible and exact
        print(f"{r['kind']:18s} {r['seed']:5d} {','.join(r['effects']) or '-':40s} "
              f"{'yes' if visible else 'no':>7s} {'yes' if exact else 'no':>5s} "
              f"{r['gap_before']:7.3f} {r['gap_after']:7.3f} {r['gap_truth']:7.3f} {ratio:11.2f}"
              + ("" if r["stiffness"] is None else
                 f"  sigma0 {r['stiffness']:.3f}, sigma1 {r['damping']:.3f} x the plant's"), flush=True)
    print(f"\nnull logs: {totals['false']}/{totals['null']} with a named effect"
          + (" (pre-sliding, the plant's, not counted)" if plant else ""))
    if plant:
        ratios = [r["stiffness"] for r in records if r["stiffness"] is not None]
        print(f"pre-sliding named on {len(ratios)}/{len(records)} logs; sigma0 / the plant's: median "
              f"{np.median(ratios) if ratios else float('nan'):.3f}, within 20 % on "
              f"{sum(abs(x - 1) <= 0.2 for x in ratios)}/{len(ratios)}")
    print(f"hidden: named exactly on {totals['exact']}/{totals['visible']} visible logs; "
          f"gap within 1.1 x the truth's on {totals['within']}/{totals['hidden']}")
    print(f"median seconds per log: {np.median([r['seconds'] for r in records]):.1f}")


if __name__ == "__main__":
    main()
