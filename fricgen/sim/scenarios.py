"""Randomized closed-loop test logs whose assumptions differ from the diagnosis' (section 6).

A scenario is a measured-style log of a plant the user does not know exactly, the friction
model the user holds and the nominal mass and force constant the user believes:

    m x'' = phi h(i) - F_p(v, t, s) - F_ext(x, v, t)        (eq. 18, ``MotorAxis``)

- **Plant.** Per seed: mass 0.5-20 kg, force constant 5-60 N/A and a base friction F_p of two
  or three Stribeck sources whose shapes are stretched exponentials exp(-(u/vs)^d) or
  rational powers 1/(1 + (u/vs)^d) with 0.8 <= d <= 2.5 (not the three shapes of eq. 2), plus
  viscous friction. h is the actuator (identity unless an actuator effect is hidden).
- **The user's model** is fricgen's default estimator trained (``data.prepare``) on a noisy
  sweep of the base friction alone (no hidden effect), with a ``--vs-max`` an engineer would
  pick: where the plant's curve has flattened. It is close to F_p, not equal.
- **Controller** (sampled at rate_hz, zero-order hold, current limit): ``pid`` (PID on the
  position error, dirty derivative), ``pd_i`` (PD on the measured velocity plus an integral)
  or ``cascade`` (P position loop around a PI velocity loop), with randomized bandwidth,
  damping and integral share, with or without inertia and friction feed-forward (the user's
  model at v_d), all from the nominal m and phi.
- **Trajectory**: ``point_to_point`` (dwells 0.02-0.3 s), ``dwell`` (0.3-1.5 s), ``sine``,
  ``multisine`` or ``ramps`` (constant speed with smoothed reversals).
- **Sensors**: Gaussian noise on x, v and the logged current, encoder, velocity and ADC
  quantization. The log holds t, x, v, i (the current command after the limit) and x_d.
  The controller acts on the noisy x and v before quantization (see the stitching below).

Hidden effects are written here as force-law closures of their own (not the diagnosis' forms,
``fricgen.effects``); they are applied at their **reference magnitude** times ``magnitude``.
F_c is the plant's Coulomb level (its Stribeck curve at high speed), a_rms the RMS of the
reference acceleration, v_pk its peak speed and i_pk the planned peak current:

=====================  ========================================================================
position_ripple        0.2 F_c sin(2 pi x / P + phase), P fitting 4-40 periods in the travel
                       but no faster than 10 Hz at the RMS reference speed
direction_asymmetry    friction in one (random) direction x (1 +- 0.25)
constant_load          +-0.3 F_c
inertia_mismatch       true mass = nominal (1 + r) or / (1 + r), r = 0.3 or more, such that
                       |dm| a_rms = 0.25 F_c, r at most 2 (x3 / x0.5); at k times the
                       reference size r is k times that (up to x(1 + 2k)), never below x0.5
force_constant_mismatch  true phi = nominal (1 - 0.15) or (1 + 0.15)
extra_friction_source  a further source: fc 0.25 F_c, fs 0.5 F_c, vs within the plant's,
                       stretched exponent 1-2, viscous 0.25 F_c / v_pk
frictional_lag         the Stribeck part follows |v| low-passed with time constant tau: 1-1.5
                       times the tau (10 ms-0.3 s) at which S(lowpass |v_d|) - S(|v_d|) has
                       an RMS of 0.05 F_c while moving
thermal_drift          friction x (1 +- D (1 - exp(-t / T))), T 0.5-2 log durations, friction
                       changed by 25 % at the end of the log (saturating, not linear in t)
=====================  ========================================================================

Out-of-vocabulary shapes (``hidden`` entries ``"oov:<shape>"``), at reference magnitude:

=====================  ========================================================================
ripple_harmonics       cogging with its 2nd and 3rd harmonics: 0.12, 0.10, 0.08 F_c
local_drag             0.5 F_c sgn(v) over a raised-cosine stretch of 5-15 % of the travel,
                       exactly 0 outside it
nonlinear_viscous      c sgn(v) |v|^p, p 3-4, 0.4 F_c at v_pk (p = 2 is a Gauss-shaped extra
                       source with a negative Stribeck part and a large vs: not outside)
actuator_deadzone      h(i) = sgn(i) max(|i| - i_dz, 0), phi i_dz = 0.2 F_c
actuator_saturation    h(i) = i_s tanh(i / i_s), i_s = i_pk / 1.2
sensor_delay           the controller and the log see x and v late: 2 ms or more, such that
                       delay x RMS d/dt (m a_d + F_p(v_d)) = 0.1 F_c, at most 0.5 rad at the
                       fastest loop's crossover (>= 1 sample)
=====================  ========================================================================

The loop advances many stretches of the log at once (``_stitched``): the log is cut where the
reference moves (never within a dwell) into stretches of about STRETCH_S; each stretch starts
on the reference, warms up over at least WARMUP_S and the whole stretch before it, and runs
in lockstep with the others through ``MotorAxis.karnopp``. A closed loop in motion forgets
its start; a stretch whose state at its seam (x, v, friction memory, controller memory)
differs from its predecessor's by more than SEAM_TOLERANCE of the sensor resolution it shows
on is re-run from the predecessor's state, until every seam agrees. So a log is a serial
simulation up to state jumps below half the sensor noise, at a fraction of its cost
(``conditions["passes"]``, ``conditions["seam_jump"]``). Quantizing the fed-back signals
would make the loop's state depend on rounding boundaries, and stretches would not agree.

``Scenario.conditions`` (JSON) holds the settings (rate_hz, duration_s, samples, plant,
controller, feedforward, trajectory, noise, quantization, magnitude), each hidden effect's
parameters (``magnitudes``) and its RMS force along the log (``signature_rms``, N; compare
with ``force_noise`` = phi sigma_i), and the loop's ``tracking_rms`` (m) and
``current_limit_fraction``. ``Scenario.hidden_force`` is the hidden effects' force per sample.
The truth a diagnosis is measured against is the user's model on ``Scenario.truth_log()`` (the
current corrected by the hidden forces but a mass error's) with ``Scenario.truth_mass()``;
``without`` leaves effects out of both, for whether each one is visible beside the others.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import Dict, Optional, Sequence, Tuple

import numpy as np
from scipy.signal import lfilter

from ..data import MotionLog, Sweep, prepare
from ..effects import EFFECTS
from ..fit import default_estimator
from ..model import FrictionModel
from .axis import AxisState, MotorAxis

#: The named effects the generator can hide (keys of ``fricgen.effects.EFFECTS``).
NAMED = ("position_ripple", "direction_asymmetry", "constant_load", "inertia_mismatch",
         "force_constant_mismatch", "extra_friction_source", "frictional_lag", "thermal_drift")
#: Shapes outside the named forms, hidden as ``"oov:<shape>"``.
OUT_OF_VOCABULARY = ("ripple_harmonics", "local_drag", "nonlinear_viscous", "actuator_deadzone",
                     "actuator_saturation", "sensor_delay")
#: Controller kinds.
CONTROLLERS = ("pid", "pd_i", "cascade")
#: Trajectory kinds.
TRAJECTORIES = ("point_to_point", "dwell", "sine", "multisine", "ramps")
#: Ranges drawn per seed unless fixed by an argument.
RATE_RANGE = (250.0, 4000.0)          # Hz
DURATION_RANGE = (5.0, 120.0)         # s
#: Longest log (20 minutes).
MAX_DURATION = 1200.0
#: The plant's Stribeck table covers speeds up to this (m/s); S is flat long before.
TABLE_TOP = 100.0
#: Largest plant integration step (s).
MAX_PLANT_STEP = 2.5e-4
#: Largest state jump at a seam of the stitched simulation, as a fraction of the sensor
#: resolution (noise or quantization step / sqrt(12), whichever is larger) it would show on.
SEAM_TOLERANCE = 0.5
#: Length of a stretch and of the warm-up before it (s); at most MAX_STRETCHES stretches.
STRETCH_S, WARMUP_S, MAX_STRETCHES = 0.5, 1.0, 4096

assert set(NAMED) == set(EFFECTS)


@dataclass(frozen=True)
class Scenario:
    """One test log and what the user holds about its plant."""

    log: MotionLog
    model: FrictionModel
    mass: float
    force_constant: float
    hidden: Tuple[str, ...]
    conditions: Dict = field(default_factory=dict)
    #: Each hidden effect's force along the log (N per sample) as the residual
    #: phi i - m dv/dt - F_p(v) of the logged signals sees it (``_hidden_forces``).
    hidden_forces: Dict[str, np.ndarray] = field(default_factory=dict)
    #: The plant's mass (``mass`` unless an inertia mismatch is hidden).
    true_mass: Optional[float] = None

    def _summed(self, skip=()) -> np.ndarray:
        return sum((f for k, f in self.hidden_forces.items() if k not in skip),
                   np.zeros(self.log.t.size))

    @property
    def hidden_force(self) -> np.ndarray:
        """The hidden effects' summed force (zeros when nothing is hidden)."""
        return self._summed()

    @property
    def force_but_mass(self) -> np.ndarray:
        """The part of ``hidden_force`` that is not a mass error's (m_true - m) dv/dt."""
        return self._summed(skip=("inertia_mismatch",))

    def truth_log(self, without: Sequence[str] = ()) -> MotionLog:
        """The log with its current corrected by the hidden effects' force except a mass
        error's, which ``truth_mass`` carries: a correction m dv/dt from the measured velocity
        would feed the velocity sensor's noise into the current the simulation is driven by.
        ``without``: hidden effects the truth leaves out (the truth missing them)."""
        skip = ("inertia_mismatch", *without)
        return replace(self.log, i=self.log.i - self._summed(skip) / self.force_constant)

    def truth_mass(self, without: Sequence[str] = ()) -> float:
        """The mass of the truth: the plant's, or the nominal one when ``without`` names the
        mass error."""
        return self.mass if "inertia_mismatch" in without else self.true_mass


# ----------------------------------------------------------------------------- plant friction


@dataclass(frozen=True)
class StretchedStribeck:
    """F_p(v) = sgn(v) sum_k [fc_k + (fs_k - fc_k) g_k(|v|)] + B v with
    g_k(u) = exp(-(u / vs_k)^d_k) (``stretched``) or 1 / (1 + (u / vs_k)^d_k) (``rational``)."""

    fc: Tuple[float, ...]
    fs: Tuple[float, ...]
    vs: Tuple[float, ...]
    exponent: Tuple[float, ...]
    kind: Tuple[str, ...]
    viscous: float

    def shape(self, speed, k):
        q = (np.abs(speed) / self.vs[k]) ** self.exponent[k]
        return np.exp(-q) if self.kind[k] == "stretched" else 1.0 / (1.0 + q)

    def stribeck(self, speed) -> np.ndarray:
        speed = np.abs(np.asarray(speed, dtype=float))
        return sum(self.fc[k] + (self.fs[k] - self.fc[k]) * self.shape(speed, k)
                   for k in range(len(self.fc)))

    def __call__(self, v) -> np.ndarray:
        v = np.asarray(v, dtype=float)
        return np.sign(v) * self.stribeck(v) + self.viscous * v

    @property
    def coulomb(self) -> float:
        return float(sum(self.fc))

    def flat_speed(self, level: float = 0.01) -> float:
        """The speed beyond which every source is within ``level`` of its Coulomb value."""
        out = 0.0
        for k in range(len(self.fc)):
            d = self.exponent[k]
            q = math.log(1.0 / level) if self.kind[k] == "stretched" else 1.0 / level - 1.0
            out = max(out, self.vs[k] * q ** (1.0 / d))
        return out

    def table(self, top: float, points: int = 4000):
        """S tabulated on 0 and geometric speeds from 1e-9 top to ``top`` (for fast lookups)."""
        speed = np.concatenate([[0.0], np.geomspace(1e-9 * top, top, points)])
        return speed, self.stribeck(speed)

    def to_dict(self) -> dict:
        return {"fc": list(self.fc), "fs": list(self.fs), "vs": list(self.vs),
                "exponent": list(self.exponent), "kind": list(self.kind), "B": self.viscous}


def _draw_friction(rng, mass: float, v_peak: float) -> StretchedStribeck:
    """Two or three sources, F_c = 0.05-0.4 m g, fs/fc 1.2-2.5, vs 2-20 mm/s; B such that
    B v_peak is 0.2-1.5 F_c."""
    n = int(rng.integers(2, 4))
    total = mass * 9.81 * rng.uniform(0.05, 0.4)             # F_c
    share = rng.dirichlet(np.ones(n))
    fc = total * share
    fs = fc * rng.uniform(1.2, 2.5, n)
    vs = np.exp(rng.uniform(math.log(2e-3), math.log(2e-2), n))
    kind = tuple(str(k) for k in rng.choice(["stretched", "rational"], n))
    exponent = np.where(np.array(kind) == "stretched", rng.uniform(0.8, 2.5, n),
                        rng.uniform(1.5, 2.5, n))
    viscous = total / v_peak * rng.uniform(0.2, 1.5)
    return StretchedStribeck(tuple(float(f) for f in fc), tuple(float(f) for f in fs),
                             tuple(float(f) for f in vs), tuple(float(e) for e in exponent),
                             kind, viscous=float(viscous))


# ----------------------------------------------------------------------------- the user's model


@lru_cache(maxsize=64)
def _user_model(friction: StretchedStribeck, v_top: float, sigma: float, seed: int) -> FrictionModel:
    """The default estimator trained on a noisy sweep of ``friction`` up to ``v_top``."""
    rng = np.random.default_rng([seed, 11])
    vs_max = friction.flat_speed(0.02) / 3.0
    v_sat = 3.0 * vs_max
    top = max(v_top, 2.0 * v_sat)
    low = np.exp(rng.uniform(math.log(v_sat * 1e-3), math.log(v_sat), 200))
    high = rng.uniform(v_sat, top, 60)
    v = np.concatenate([low, high]) * rng.choice([-1.0, 1.0], 260)
    f = friction(v) + sigma * rng.standard_normal(v.size)
    dataset = prepare(Sweep(v, f), vs_max=vs_max)
    return FrictionModel.fit(dataset, default_estimator(seed), name="user_model",
                             training={"method": "auto", "source": "scenario sweep"})


def _tabulated_force(model: FrictionModel, v) -> np.ndarray:
    """The model's F(v) of eq. (3) with its Stribeck part interpolated from 4097 speeds in
    [0, v_sat] (beyond it the network input saturates): error ~1e-5 N, fast on long logs."""
    grid = np.linspace(0.0, model.v_sat, 4097)
    return np.sign(v) * np.interp(np.abs(v), grid, model.stribeck(grid)) + model.viscous * v


# ----------------------------------------------------------------------------- trajectories


def _smoothstep(t, ramp):
    tau = np.clip(t / ramp, 0.0, 1.0)
    s = 3 * tau ** 2 - 2 * tau ** 3
    ds = np.where(tau < 1, (6 * tau - 6 * tau ** 2) / ramp, 0.0)
    return s, ds


def _velocity_profile(kind, rng, t, v_peak, a_max):
    """(v, a, description) of a trajectory kind on the grid t, before fading in."""
    if kind in ("sine", "multisine"):
        n = 1 if kind == "sine" else int(rng.integers(3, 7))
        f = np.exp(rng.uniform(math.log(0.2), math.log(2.0 if n == 1 else 5.0), n))
        amp = rng.uniform(0.3, 1.0, n)
        ph = rng.uniform(0, 2 * np.pi, n)
        w = 2 * np.pi * f
        v = np.zeros_like(t)
        a = np.zeros_like(t)
        for k in range(n):
            v += amp[k] * np.sin(w[k] * t + ph[k])
            a += amp[k] * w[k] * np.cos(w[k] * t + ph[k])
        return v, a, {"frequencies_hz": f.tolist()}
    if kind == "ramps":
        period = rng.uniform(0.5, 4.0)
        width = rng.uniform(0.05, 0.3)
        w = 2 * np.pi / period
        ph = rng.uniform(0, 2 * np.pi)
        arg = np.sin(w * t + ph) / width
        v = np.tanh(arg) / math.tanh(1.0 / width)
        a = (1.0 - np.tanh(arg) ** 2) * np.cos(w * t + ph) * w / width / math.tanh(1.0 / width)
        return v, a, {"period_s": period, "reversal_width": width}
    raise ValueError(f"unknown trajectory {kind!r}")


def _moves(rng, t, travel, v_peak, a_max, dwell_range):
    """Point-to-point moves with 1 - cos speed bumps, dwelling between them: x, v, a."""
    starts, targets, lengths = [], [], []
    clock, pos = 0.5, 0.0
    end = t[-1] + 1.0
    dwells = []
    while clock < end:
        target = rng.uniform(-travel, travel)
        if abs(target - pos) < 0.2 * travel:
            target = pos - math.copysign(0.5 * travel, pos if pos else 1.0)
        dist = abs(target - pos)
        peak = v_peak * rng.uniform(0.4, 1.0)
        length = max(2.0 * dist / peak, math.sqrt(2 * np.pi * dist / a_max))
        starts.append(clock)
        targets.append(target)
        lengths.append(length)
        dwell = rng.uniform(*dwell_range)
        dwells.append(dwell)
        clock += length + dwell
        pos = target
    starts, targets, lengths = map(np.asarray, (starts, targets, lengths))
    origin = np.concatenate([[0.0], targets[:-1]])
    dist = targets - origin
    k = np.clip(np.searchsorted(starts, t, side="right") - 1, -1, None)
    before = k < 0
    k = np.maximum(k, 0)
    tau = np.clip(t - starts[k], 0.0, lengths[k])
    moving = (t >= starts[k]) & (t - starts[k] < lengths[k]) & ~before
    ratio = dist[k] / lengths[k]
    arg = 2 * np.pi * tau / lengths[k]
    x = np.where(before, 0.0, origin[k] + ratio * (tau - lengths[k] / (2 * np.pi) * np.sin(arg)))
    v = np.where(moving, ratio * (1.0 - np.cos(arg)), 0.0)
    a = np.where(moving, ratio * 2 * np.pi / lengths[k] * np.sin(arg), 0.0)
    return x, v, a, {"moves": int(np.sum(starts < t[-1])), "mean_dwell_s": float(np.mean(dwells))}


def _trajectory(kind, rng, t, v_peak, a_max, travel):
    """x_d, v_d, a_d on the grid t (starting at rest at 0) and a description."""
    if kind in ("point_to_point", "dwell"):
        dwell = (0.02, 0.3) if kind == "point_to_point" else (0.3, 1.5)
        x, v, a, info = _moves(rng, t, travel, v_peak, a_max, dwell)
        return x, v, a, info
    u, du, info = _velocity_profile(kind, rng, t, v_peak, a_max)
    ramp = 0.5
    s, ds = _smoothstep(t, ramp)
    v = s * u
    a = ds * u + s * du
    scale = min(v_peak / max(np.max(np.abs(v)), 1e-12), a_max / max(np.max(np.abs(a)), 1e-12))
    v, a = v * scale, a * scale
    x = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
    if kind == "ramps":
        x = x - np.mean(x)                 # any offset: the axis starts at x_d(0) anyway
        x = x - x[0]
    return x, v, a, info


# ----------------------------------------------------------------------------- hidden effects


@dataclass
class _Hidden:
    """The closures and parameters of the hidden effects of one scenario."""

    mass_factor: float = 1.0
    phi_factor: float = 1.0
    lag_tau: float = 0.0
    external: list = field(default_factory=list)      # f(x, v, t)
    sliding: list = field(default_factory=list)       # f(v, t, base)  (added)
    gains: list = field(default_factory=list)         # g(v, t)        (multiplies F_p)
    actuator: Optional[object] = None                 # h(i)
    delay_samples: int = 0
    delay_wanted: float = 0.0
    parameters: Dict[str, dict] = field(default_factory=dict)
    signatures: Dict[str, object] = field(default_factory=dict)   # f(signals) -> force


class _PlantLaw:
    """The plant's ``ForceLaw`` (``sim.axis``): base friction, hidden closures."""

    def __init__(self, friction: StretchedStribeck, hidden: _Hidden, mass, force_constant, i_max):
        self.friction, self.hidden = friction, hidden
        self.mass = mass * hidden.mass_factor
        self.force_constant = force_constant * hidden.phi_factor
        self.i_max = i_max
        self.lag_tau = hidden.lag_tau
        self._speeds, self._stribeck = friction.table(TABLE_TOP)

    def sliding_friction(self, v, t, s):
        """F_p at the speed (lagged speed under frictional lag), times the gains, plus the
        additive terms; S is interpolated from a table (relative error < 1e-5)."""
        speed = s if self.lag_tau > 0 else np.abs(v)
        base = np.sign(v) * np.interp(speed, self._speeds, self._stribeck) + \
            self.friction.viscous * v
        f = base
        for g in self.hidden.gains:
            f = f * g(v, t)
        for extra in self.hidden.sliding:
            f = f + extra(v, t)
        return f

    def external_force(self, x, v, t):
        total = np.zeros_like(np.asarray(x, dtype=float))
        for ext in self.hidden.external:
            total = total + ext(x, v, t)
        return total


def _effect_rng(seed, name):
    order = NAMED + OUT_OF_VOCABULARY
    return np.random.default_rng([seed, 3, order.index(name)])


def _add_effect(h: _Hidden, name: str, k: float, rng, ctx: dict) -> None:
    """Add effect ``name`` at ``k`` times its reference magnitude (module docstring), with
    its force signature along a log (``_hidden_forces``)."""
    fc, vpk = ctx["coulomb"], ctx["v_peak"]
    sign = float(rng.choice([-1.0, 1.0]))
    p: dict
    if name in ("position_ripple", "ripple_harmonics"):
        period = _ripple_period(rng, ctx)
        if name == "position_ripple":
            amps, phases = [0.2 * fc * k], [rng.uniform(0, 2 * np.pi)]
        else:
            amps = [0.12 * fc * k, 0.10 * fc * k, 0.08 * fc * k]
            phases = rng.uniform(0, 2 * np.pi, 3).tolist()
        wn = 2 * np.pi / period

        def force(x, v, t):
            return sum(a * np.sin((j + 1) * wn * np.asarray(x) + ph)
                       for j, (a, ph) in enumerate(zip(amps, phases)))
        h.external.append(force)
        signature = _external_signature(force)
        p = ({"amplitude": amps[0], "period": period, "phase": phases[0]}
             if name == "position_ripple" else
             {"amplitudes": amps, "period": period, "phases": phases})
    elif name == "direction_asymmetry":
        gain, side = 0.25 * k, sign

        def factor(v, t):
            return np.where(side * np.asarray(v) > 0, 1.0 + gain, 1.0)
        h.gains.append(factor)
        signature = _gain_signature(factor)
        p = {"direction": side, "gain": gain}
    elif name == "constant_load":
        load = sign * 0.3 * fc * k

        def force(x, v, t):
            return np.full(np.shape(x), load)
        h.external.append(force)
        signature = _external_signature(force)
        p = {"load": load}
    elif name == "inertia_mismatch":
        rel = max(0.3, 0.25 * fc / (ctx["mass"] * max(ctx["a_rms"], 1e-9)))
        rel = min(rel, 2.0) * k
        h.mass_factor = 1.0 + rel if sign > 0 else 1.0 / (1.0 + min(rel, 1.0))
        dm = ctx["mass"] * (h.mass_factor - 1.0)

        def signature(q):
            return dm * q["a"]
        p = {"mass": ctx["mass"] * h.mass_factor, "nominal_mass": ctx["mass"]}
    elif name == "force_constant_mismatch":
        h.phi_factor = 1.0 + sign * 0.15 * k
        dphi = ctx["force_constant"] * (h.phi_factor - 1.0)

        def signature(q):
            return -dphi * q["i"]          # the nominal phi i is dphi i short of the force
        p = {"force_constant": ctx["force_constant"] * h.phi_factor,
             "nominal_force_constant": ctx["force_constant"]}
    elif name == "extra_friction_source":
        vs = math.exp(rng.uniform(math.log(min(ctx["vs"])), math.log(max(ctx["vs"]))))
        d = rng.uniform(1.0, 2.0)
        fce, fse, be = 0.25 * fc * k, 0.5 * fc * k, 0.25 * fc / vpk * k

        def extra(v, t):
            v = np.asarray(v)
            return np.sign(v) * (fce + (fse - fce) * np.exp(-(np.abs(v) / vs) ** d)) + be * v
        h.sliding.append(extra)
        signature = _sliding_signature(extra)
        p = {"fc": fce, "fs": fse, "vs": vs, "exponent": d, "B": be}
    elif name == "frictional_lag":
        h.lag_tau = tau = _lag_reference(ctx) * rng.uniform(1.0, 1.5) * k

        def signature(q):
            alpha = 1.0 - math.exp(-q["ts"] / tau)
            lagged = lfilter([alpha], [1.0, alpha - 1.0], np.abs(q["v"]))
            return np.sign(q["v"]) * (q["stribeck"](lagged) - q["stribeck"](np.abs(q["v"])))
        p = {"tau": tau}
    elif name == "thermal_drift":
        time_constant = ctx["duration"] * rng.uniform(0.5, 2.0)
        level = sign * 0.25 * k / (1.0 - math.exp(-ctx["duration"] / time_constant))

        def factor(v, t):
            return 1.0 + level * (1.0 - np.exp(-np.asarray(t) / time_constant))
        h.gains.append(factor)
        signature = _gain_signature(factor)
        p = {"level": level, "time_constant": time_constant}
    elif name == "local_drag":
        lo, hi = ctx["x_range"]
        width = (hi - lo) * rng.uniform(0.05, 0.15)
        centre = rng.uniform(lo + 0.3 * (hi - lo), hi - 0.3 * (hi - lo))
        drag = 0.5 * fc * k

        def force(x, v, t):
            return _local_drag(v, x, centre, width, drag)
        h.external.append(force)
        signature = _external_signature(force)
        p = {"centre": centre, "width": width, "drag": drag}
    elif name == "nonlinear_viscous":
        power = rng.uniform(3.0, 4.0)
        c = 0.4 * fc * k / vpk ** power

        def extra(v, t):
            return c * np.sign(v) * np.abs(v) ** power
        h.sliding.append(extra)
        signature = _sliding_signature(extra)
        p = {"coefficient": c, "power": power}
    elif name in ("actuator_deadzone", "actuator_saturation"):
        if name == "actuator_deadzone":
            i_dz = 0.2 * fc * k / ctx["force_constant"]

            def actuator(i):
                return np.sign(i) * np.maximum(np.abs(i) - i_dz, 0.0)
            p = {"deadzone_a": i_dz}
        else:
            i_s = ctx["i_peak"] / (1.2 * k)

            def actuator(i):
                return i_s * np.tanh(np.asarray(i) / i_s)
            p = {"saturation_a": i_s}
        h.actuator = actuator

        def signature(q):
            return -q["phi"] * (actuator(q["i"]) - q["i"])
    elif name == "sensor_delay":
        h.delay_wanted = max(0.002, 0.1 * fc / max(ctx["force_rate_rms"], 1e-12)) * k

        def signature(q):
            """What the residual sees: m a + F of the logged motion at t is phi i(t - d)
            (the motion is logged d late), so phi i(t) - phi i(t - d)."""
            d = h.delay_samples
            i = np.asarray(q["i"], dtype=float)
            return q["phi"] * (i - np.concatenate([np.full(d, i[0]), i[:-d]]))
        p = {}
    else:   # pragma: no cover - names are checked before
        raise ValueError(name)
    key = name if name in NAMED else "oov:" + name
    h.parameters[key] = p
    h.signatures[key] = signature


def _external_signature(force):
    return lambda q: force(q["x"], q["v"], q["t"])


def _sliding_signature(extra):
    return lambda q: extra(q["v"], q["t"])


def _gain_signature(factor):
    return lambda q: q["base"] * (factor(q["v"], q["t"]) - 1.0)


def _hidden_forces(h: _Hidden, log: MotionLog, friction, mass, phi) -> Dict[str, np.ndarray]:
    """Each hidden effect's force along the log: its contribution to phi i - m a - F_p(v),
    evaluated on the logged signals (a from v smoothed over 10 ms), in newtons per sample."""
    ts = log.sample_time
    w = max(1, int(round(0.01 / ts)))
    v_smooth = np.convolve(log.v, np.ones(w) / w, mode="same")
    q = {"x": log.x, "v": log.v, "t": log.t, "i": log.i, "a": np.gradient(v_smooth, ts),
         "ts": ts, "base": friction(log.v), "v_smooth": v_smooth, "friction": friction,
         "stribeck": friction.stribeck, "mass": mass, "phi": phi}
    return {key: np.broadcast_to(np.asarray(sig(q), dtype=float), log.t.shape)
            for key, sig in h.signatures.items()}


def _ripple_period(rng, ctx) -> float:
    """A ripple period: 4 to 40 periods over the travel, but no faster than 10 Hz at the
    reference's RMS speed (a faster ripple is filtered out by the axis' own mass)."""
    lo_x, hi_x = ctx["x_range"]
    span = hi_x - lo_x
    lo = max(span / 40.0, ctx["v_rms"] / 10.0)
    hi = max(span / 4.0, 2.0 * lo)
    return _log_uniform(rng, lo, hi)


def _lag_reference(ctx) -> float:
    """The frictional-lag time constant (10 ms to 0.3 s) at which the lagged Stribeck part
    S(lowpass |v_d|) - S(|v_d|) has an RMS of 5 % of F_c over the moving samples."""
    speed, ts = ctx["speed"], ctx["ts"]
    step = max(1, int(1e-3 / ts))
    speed = speed[::step]
    moving = speed > 0
    stribeck = ctx["stribeck"]
    base = stribeck(speed)
    for tau in np.geomspace(0.01, 0.3, 16):
        alpha = 1.0 - math.exp(-step * ts / tau)
        lagged = lfilter([alpha], [1.0, alpha - 1.0], speed)
        gap = stribeck(lagged) - base
        if np.sqrt(np.mean(gap[moving] ** 2)) >= 0.05 * ctx["coulomb"]:
            return float(tau)
    return 0.3


def _local_drag(v, x, centre, width, drag):
    """drag sgn(v) over |x - centre| < width / 2 (raised cosine), exactly 0 outside; 0 at
    rest, so it adds to no breakaway force and pushes no axis."""
    u = (np.asarray(x) - centre) / (0.5 * width)
    bump = np.where(np.abs(u) < 1.0, 0.5 * (1.0 + np.cos(np.pi * np.clip(u, -1, 1))), 0.0)
    return drag * np.sign(v) * bump


def local_drag_profile(x, centre, width, drag=1.0):
    """The position profile of the ``local_drag`` shape (for checks): drag over the stretch."""
    return _local_drag(np.ones_like(np.asarray(x, dtype=float)), x, centre, width, drag)


# ----------------------------------------------------------------------------- the closed loop


def _quantize(value, step):
    return np.round(value / step) * step


class _Loop:
    """The sampled closed loop of one scenario, advancing a batch of stretches in lockstep."""

    def __init__(self, plant: _PlantLaw, cond: dict, ref, feedforward, noise, ctrl: dict):
        self.axis = MotorAxis(plant)
        self.plant, self.cond, self.ctrl = plant, cond, ctrl
        self.xd, self.vd, self.ad = ref
        self.ff = feedforward
        self.noise = noise
        self.ts = 1.0 / cond["rate_hz"]
        self.substeps = cond["substeps"]
        self.delay = plant.hidden.delay_samples

    def initial(self, idx, exact):
        """States at samples ``idx``: at rest at 0 where ``exact`` (the log's start), else on
        the reference with the controller's memory empty."""
        x = np.where(exact, 0.0, self.xd[idx])
        v = np.where(exact, 0.0, self.vd[idx])
        state = {"x": x, "v": v, "s": np.abs(v), "integral": np.zeros_like(x),
                 "filtered": np.zeros_like(x)}
        if self.delay:
            state["hx"] = np.repeat(x[:, None], self.delay, axis=1)
            state["hv"] = np.repeat(v[:, None], self.delay, axis=1)
        return state

    def step(self, st, idx):
        """One sample: measure, control, log, then advance the plant by Ts."""
        c, cond = self.ctrl, self.cond
        z = self.noise[idx]
        if self.delay:
            xs, vs_ = st["hx"][:, 0], st["hv"][:, 0]
        else:
            xs, vs_ = st["x"], st["v"]
        xm = xs + cond["sigma_x"] * z[:, 0]     # the controller sees the noisy sensors, the
        vm = vs_ + cond["sigma_v"] * z[:, 1]    # log their quantized values
        xd, vd, ad = self.xd[idx], self.vd[idx], self.ad[idx]
        e = xd - xm
        m = c["mass"]
        acc_ff = ad * c["inertia_ff"]
        if c["kind"] == "pid":
            deriv = (e - st["filtered"]) / c["tf"]
            filtered = st["filtered"] + (self.ts / c["tf"]) * (e - st["filtered"])
            u = m * (acc_ff + c["kp"] * e + c["kd"] * deriv) + c["ki_m"] * st["integral"]
            err_int = e
        elif c["kind"] == "pd_i":
            filtered = st["filtered"]
            u = m * (acc_ff + c["kp"] * e + c["kd"] * (vd - vm)) + c["ki_m"] * st["integral"]
            err_int = e
        else:   # cascade
            filtered = st["filtered"]
            v_cmd = vd + c["kpos"] * e
            ev = v_cmd - vm
            u = m * (acc_ff + c["kv"] * ev) + c["ki_m"] * st["integral"]
            err_int = ev
        u = u + self.ff[idx]
        i_lim = self.plant.i_max
        i_cmd = u / c["force_constant"]
        i = np.clip(i_cmd, -i_lim, i_lim)
        # integrate unless the limit is pushing the same way (anti-windup)
        grow = ~((np.abs(i_cmd) > i_lim) & (np.sign(err_int) == np.sign(i_cmd)))
        integral = st["integral"] + np.where(grow, err_int * self.ts, 0.0)
        im = _quantize(i + cond["sigma_i"] * z[:, 2], cond["q_i"])
        applied = i if self.plant.hidden.actuator is None else self.plant.hidden.actuator(i)
        state = AxisState(st["x"], st["v"], idx * self.ts, st["s"])
        nxt = self.axis.karnopp(state, applied, self.ts, self.substeps)
        new = {"x": nxt.x, "v": nxt.v, "s": nxt.s, "integral": integral, "filtered": filtered}
        if self.delay:
            new["hx"] = np.concatenate([st["hx"][:, 1:], st["x"][:, None]], axis=1)
            new["hv"] = np.concatenate([st["hv"][:, 1:], st["v"][:, None]], axis=1)
        return new, (_quantize(xm, cond["q_x"]), _quantize(vm, cond["q_v"]), im)


def _mismatch(a: dict, b: dict, scale: dict) -> np.ndarray:
    """Per stretch: the largest |a - b| over the state components, in units of their
    ``scale``."""
    worst = None
    for key in a:
        d = np.abs(a[key] - b[key]) / scale[key]
        d = d.reshape(d.shape[0], -1).max(axis=1)
        worst = d if worst is None else np.maximum(worst, d)
    return worst


def _take(state: dict, rows) -> dict:
    return {k: np.array(v[rows]) for k, v in state.items()}


def seams(speed: np.ndarray, stretch: int) -> np.ndarray:
    """Sample indices that cut a log into stretches of about ``stretch`` samples, each cut
    where the reference ``speed`` is largest within half a stretch of the regular grid, and
    none within a dwell (an axis in motion forgets its past; one stuck does not)."""
    n = speed.size
    cuts = [0]
    for b in range(stretch, n - stretch // 2, stretch):
        a, z = max(b - stretch // 2, cuts[-1] + stretch // 2), min(b + stretch // 2, n - 1)
        if z > a:
            c = a + int(np.argmax(speed[a:z]))
            if speed[c] > 0:
                cuts.append(c)
    return np.array(cuts + [n])


def _stitched(loop: _Loop, cuts: np.ndarray, warmup: int, resolution: dict):
    """The log's measured x, v, i, simulated as the stretches between ``cuts`` in lockstep
    (see the module docstring). Returns the arrays, the number of passes and the largest
    state jump at a seam in units of ``resolution``."""
    n = int(cuts[-1])
    k = cuts.size - 1
    lo, hi = cuts[:-1], cuts[1:]
    out = np.zeros((3, n))

    def run(rows, start, init, steps):
        """Advance stretches ``rows`` from ``init`` at samples ``start`` for ``steps`` samples,
        logging their own samples; returns their states at lo and hi."""
        st = init
        at_lo, at_hi = _take(init, slice(None)), _take(init, slice(None))
        for j in range(steps + 1):
            idx = start + j
            mark = idx == lo[rows]
            if mark.any():
                for key in st:
                    at_lo[key][mark] = st[key][mark]
            mark = idx == hi[rows]
            if mark.any():
                for key in st:
                    at_hi[key][mark] = st[key][mark]
            if j == steps:
                break
            clipped = np.minimum(idx, n - 1)
            st, meas = loop.step(st, clipped)
            own = (idx >= lo[rows]) & (idx < hi[rows])
            if own.any():
                out[:, idx[own]] = np.stack(meas)[:, own]
        return at_lo, at_hi

    # each stretch warms up for at least ``warmup`` samples and over the whole stretch before
    start = np.maximum(np.minimum(lo - warmup, np.concatenate([[0], lo[:-1]])), 0)
    exact = start == 0
    rows = np.arange(k)
    at_lo, at_hi = run(rows, start, loop.initial(start, exact), int(np.max(hi - start)))
    passes = 1
    seam = np.zeros(k)
    while True:
        for j in range(1, k):
            if not exact[j] and exact[j - 1]:
                seam[j] = _mismatch(_take(at_lo, [j]), _take(at_hi, [j - 1]), resolution)[0]
                exact[j] = bool(seam[j] <= SEAM_TOLERANCE)
        bad = np.flatnonzero(~exact)
        if bad.size == 0:
            break
        first = bad[0]
        redo = bad
        init = _take(at_hi, redo - 1)
        new_lo, new_hi = run(redo, lo[redo], init, int(np.max(hi[redo] - lo[redo])))
        for key in at_lo:
            at_lo[key][redo] = new_lo[key]
            at_hi[key][redo] = new_hi[key]
        exact[first] = True
        seam[first] = 0.0
        passes += 1
    return out, passes, float(np.max(seam))


# ----------------------------------------------------------------------------- scenarios


def _resolution(sensors: dict, ctrl: dict, phi: float) -> dict:
    """The sensor resolution each state component shows on: x and v directly, the
    controller's memory through the force it commands (noise or quantization step /
    sqrt(12), whichever is larger)."""
    def resolution(sigma, step):
        return max(sigma, step / math.sqrt(12.0))

    x = resolution(sensors["sigma_x"], sensors["q_x"])
    v = resolution(sensors["sigma_v"], sensors["q_v"])
    force = phi * resolution(sensors["sigma_i"], sensors["q_i"])
    filtered = force * ctrl["tf"] / (ctrl["mass"] * ctrl["kd"]) if ctrl["kind"] == "pid" else 1.0
    return {"x": x, "v": v, "s": v, "integral": force / ctrl["ki_m"], "filtered": filtered,
            "hx": x, "hv": v}


def _log_uniform(rng, lo, hi):
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _normalize_hidden(hidden) -> Tuple[str, ...]:
    if isinstance(hidden, str):
        hidden = (hidden,)
    out = []
    for name in hidden:
        if not isinstance(name, str):
            raise ValueError(f"hidden effects are names, got {name!r}")
        name = str(name)
        bare = name[4:] if name.startswith("oov:") else name
        if name in NAMED:
            key = name
        elif bare in OUT_OF_VOCABULARY:
            key = "oov:" + bare
        else:
            raise ValueError(f"unknown hidden effect {name!r}; named: {', '.join(NAMED)}; "
                             f"out of vocabulary: {', '.join('oov:' + s for s in OUT_OF_VOCABULARY)}")
        if key in out:
            raise ValueError(f"hidden effect {key!r} given twice")
        out.append(key)
    if "oov:actuator_deadzone" in out and "oov:actuator_saturation" in out:
        raise ValueError("one actuator: hide actuator_deadzone or actuator_saturation, not both")
    return tuple(out)


def _controller(rng, kind, mass, force_constant, rate, feedforward):
    f_bw = min(_log_uniform(rng, 4.0, 25.0), rate / 40.0)
    w = 2 * np.pi * f_bw
    zeta = rng.uniform(0.5, 1.2)
    share = rng.uniform(0.05, 0.3)
    c = {"kind": kind, "bandwidth_hz": f_bw, "damping": zeta, "integral_share": share,
         "mass": mass, "force_constant": force_constant,
         "inertia_ff": float(rng.uniform() < 0.7), "friction_ff": feedforward}
    if kind in ("pid", "pd_i"):
        c.update(kp=w * w, kd=2 * zeta * w, ki_m=mass * share * w ** 3)
        c["tf"] = max(1.0 / (w * rng.uniform(5.0, 15.0)), 2.0 / rate)
    else:
        wv = min(w * rng.uniform(2.0, 4.0), 2 * np.pi * rate / 15.0)
        c.update(kpos=w * rng.uniform(0.5, 1.0), kv=wv, ki_m=mass * share * wv * wv,
                 velocity_bandwidth_hz=wv / (2 * np.pi))
        c["tf"] = 1.0
    return c


def draw_settings(seed: int, *, rate_hz: Optional[float] = None,
                  duration_s: Optional[float] = None, noise: Optional[float] = None,
                  controller: Optional[str] = None, trajectory: Optional[str] = None,
                  feedforward: Optional[bool] = None) -> dict:
    """The log settings of ``seed`` (rate_hz, duration_s, noise scale, controller,
    trajectory, feedforward): drawn unless given (rate log-uniform in RATE_RANGE, duration
    log-uniform in DURATION_RANGE), checked when given."""
    rng = np.random.default_rng([int(seed), 1])
    draws = {"rate": rng.uniform(), "duration": rng.uniform(),
             "controller": int(rng.integers(len(CONTROLLERS))),
             "trajectory": int(rng.integers(len(TRAJECTORIES))),
             "feedforward": bool(rng.uniform() < 0.5)}
    rate = float(round(RATE_RANGE[0] * (RATE_RANGE[1] / RATE_RANGE[0]) ** draws["rate"])) \
        if rate_hz is None else float(rate_hz)
    duration = round(DURATION_RANGE[0] * (DURATION_RANGE[1] / DURATION_RANGE[0])
                     ** draws["duration"], 1) if duration_s is None else float(duration_s)
    if not (math.isfinite(rate) and 50.0 <= rate <= 20000.0):
        raise ValueError(f"rate_hz must be in [50, 20000], got {rate_hz!r}")
    if not (math.isfinite(duration) and 1.0 <= duration <= MAX_DURATION):
        raise ValueError(f"duration_s must be in [1, {MAX_DURATION:g}], got {duration_s!r}")
    noise_scale = 1.0 if noise is None else float(noise)
    if not (math.isfinite(noise_scale) and noise_scale >= 0):
        raise ValueError(f"noise must be >= 0, got {noise!r}")
    kind = CONTROLLERS[draws["controller"]] if controller is None else controller
    if kind not in CONTROLLERS:
        raise ValueError(f"controller must be one of {CONTROLLERS}, got {controller!r}")
    traj_kind = TRAJECTORIES[draws["trajectory"]] if trajectory is None else trajectory
    if traj_kind not in TRAJECTORIES:
        raise ValueError(f"trajectory must be one of {TRAJECTORIES}, got {trajectory!r}")
    use_ff = draws["feedforward"] if feedforward is None else bool(feedforward)
    return {"rate_hz": rate, "duration_s": duration, "noise": noise_scale, "controller": kind,
            "trajectory": traj_kind, "feedforward": use_ff}


def make_scenario(seed: int, hidden: Sequence[str] = (), *, rate_hz: Optional[float] = None,
                  duration_s: Optional[float] = None, noise: Optional[float] = None,
                  controller: Optional[str] = None, trajectory: Optional[str] = None,
                  feedforward: Optional[bool] = None, magnitude: float = 1.0) -> Scenario:
    """The scenario of ``seed`` with ``hidden`` effects (names of ``NAMED`` or
    ``"oov:<shape>"`` of ``OUT_OF_VOCABULARY``) at ``magnitude`` times their reference size.

    Everything not fixed by an argument is drawn from ``seed`` alone, so the same seed with
    other hidden effects has the same plant, controller, trajectory and sensor noise: the
    logs differ only by the effects. ``noise`` scales the drawn sensor noise (1: as drawn).
    """
    hidden = _normalize_hidden(hidden)
    if not (isinstance(magnitude, (int, float)) and math.isfinite(magnitude) and magnitude > 0):
        raise ValueError(f"magnitude must be > 0, got {magnitude!r}")
    drawn = draw_settings(seed, rate_hz=rate_hz, duration_s=duration_s, noise=noise,
                          controller=controller, trajectory=trajectory, feedforward=feedforward)
    rate, duration, noise_scale = drawn["rate_hz"], drawn["duration_s"], drawn["noise"]
    kind, traj_kind, use_ff = drawn["controller"], drawn["trajectory"], drawn["feedforward"]

    # plant
    prng = np.random.default_rng([int(seed), 2])
    mass = _log_uniform(prng, 0.5, 20.0)
    phi = _log_uniform(prng, 5.0, 60.0)
    v_peak = _log_uniform(prng, 0.05, 0.5)
    a_max = _log_uniform(prng, 1.0, 15.0)
    travel = _log_uniform(prng, 0.02, 0.3)
    friction = _draw_friction(prng, mass, v_peak)
    f_peak = mass * a_max + float(friction(v_peak)) + max(friction.fs)
    i_peak = f_peak / phi
    i_max = i_peak * prng.uniform(2.0, 3.0)
    sensors = {
        "sigma_x": _log_uniform(prng, 1e-7, 2e-6) * noise_scale,
        "q_x": float(prng.choice([1e-7, 5e-7, 1e-6, 5e-6])),
        "sigma_v": _log_uniform(prng, 1e-4, 2e-3) * noise_scale,
        "q_v": float(prng.choice([1e-5, 1e-4, 5e-4])),
        "sigma_i": i_peak * _log_uniform(prng, 2e-3, 2e-2) * noise_scale,
        "adc_bits": int(prng.choice([10, 12, 14, 16])),
    }
    sensors["q_i"] = 2 * i_max / 2 ** sensors["adc_bits"]
    model = _user_model(friction, 1.5 * v_peak, 0.02 * friction.coulomb, int(seed) % 1000)

    # trajectory
    n = int(round(duration * rate)) + 1
    t = np.arange(n) / rate
    trng = np.random.default_rng([int(seed), 4])
    xd, vd, ad, traj_info = _trajectory(traj_kind, trng, t, v_peak, a_max, travel)
    ctrl = _controller(np.random.default_rng([int(seed), 5]), kind, mass, phi, rate, use_ff)
    ff = _tabulated_force(model, vd) if use_ff else np.zeros(n)

    # hidden effects
    ctx = {"coulomb": friction.coulomb, "travel": travel, "v_peak": float(np.max(np.abs(vd))),
           "mass": mass, "force_constant": phi, "a_rms": float(np.sqrt(np.mean(ad ** 2))),
           "vs": friction.vs, "duration": duration, "x_range": (float(np.min(xd)), float(np.max(xd))),
           "i_peak": i_peak, "rate_hz": rate, "v_rms": float(np.sqrt(np.mean(vd ** 2))),
           "speed": np.abs(vd), "ts": 1.0 / rate, "stribeck": friction.stribeck,
           "force_rate_rms": float(np.sqrt(np.mean(np.gradient(
               mass * ad + friction(vd), 1.0 / rate) ** 2))),
           "fast_loop": 2 * np.pi * ctrl.get("velocity_bandwidth_hz", ctrl["bandwidth_hz"])}
    h = _Hidden()
    for name in hidden:
        _add_effect(h, name[4:] if name.startswith("oov:") else name, magnitude,
                    _effect_rng(seed, name[4:] if name.startswith("oov:") else name), ctx)
    if h.delay_wanted:
        # at most 0.5 rad of phase at the fastest loop's crossover, which the hidden mass
        # and force constant errors shift by their gain
        gain = max(1.0, h.phi_factor / h.mass_factor)
        delay = min(h.delay_wanted, 0.5 / (ctx["fast_loop"] * gain))
        h.delay_samples = max(1, int(round(delay * rate)))
        h.parameters["oov:sensor_delay"].update(delay_s=h.delay_samples / rate,
                                                samples=h.delay_samples)
    law = _PlantLaw(friction, h, mass, phi, i_max)

    step = min(MAX_PLANT_STEP, 0.2 * law.mass / max(friction.viscous, 1e-12))
    substeps = max(1, int(math.ceil((1.0 / rate) / step)))
    cond = dict(sensors, rate_hz=rate, substeps=substeps)
    noise_rows = np.random.default_rng([int(seed), 6]).standard_normal((n, 3))
    loop = _Loop(law, cond, (xd, vd, ad), ff, noise_rows, ctrl)
    stretch = max(int(round(STRETCH_S * rate)), -(-n // MAX_STRETCHES))
    warmup = int(round(WARMUP_S * rate))
    (xm, vm, im), passes, seam = _stitched(loop, seams(np.abs(vd), stretch), warmup,
                                           _resolution(sensors, ctrl, phi))
    log = MotionLog(t=t, x=xm, v=vm, i=im, extra={"x_d": xd})
    forces = _hidden_forces(h, log, friction, mass, phi)

    conditions = _jsonable({
        "seed": int(seed), "rate_hz": rate, "duration_s": duration, "samples": n,
        "plant": {"mass": mass, "force_constant": phi, "i_max": i_max,
                  "friction": friction.to_dict(), "coulomb": friction.coulomb,
                  "substeps": substeps},
        "controller": {k: (float(v) if isinstance(v, (float, np.floating)) else v)
                       for k, v in ctrl.items()},
        "feedforward": use_ff,
        "trajectory": dict({"kind": traj_kind, "v_peak": ctx["v_peak"], "a_max": a_max,
                            "travel": travel}, **traj_info),
        "noise": {"scale": noise_scale, "sigma_x": sensors["sigma_x"],
                  "sigma_v": sensors["sigma_v"], "sigma_i": sensors["sigma_i"]},
        "quantization": {"x": sensors["q_x"], "v": sensors["q_v"], "i": sensors["q_i"],
                         "adc_bits": sensors["adc_bits"]},
        "magnitude": float(magnitude),
        "magnitudes": _jsonable(h.parameters),
        "signature_rms": {k: float(np.sqrt(np.mean(f ** 2))) for k, f in forces.items()},
        "force_noise": phi * sensors["sigma_i"],
        "passes": passes,
        "tracking_rms": float(np.sqrt(np.mean((xd - xm) ** 2))),
        "current_limit_fraction": float(np.mean(np.abs(im) >= 0.999 * i_max - sensors["q_i"])),
        "seam_jump": seam,
    })
    return Scenario(log=log, model=model, mass=mass, force_constant=phi, hidden=hidden,
                    conditions=conditions,
                    hidden_forces=forces, true_mass=law.mass)


def _jsonable(value):
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, (np.floating, float)):
        return float(value)
    if isinstance(value, (np.integer, int)) and not isinstance(value, bool):
        return int(value)
    return value
