"""Measured-style motion logs from a truth axis with one hidden effect, for testing ``diagnose``.

The truth axis is m dv/dt = phi i - F(v) - effect [C1], with the paper's
friction (Table 1, ``preset("paper3")``) and at most one hidden effect of the diagnosis
vocabulary, an object of ``fricgen.effects`` (the force law is ``sim.effect_law.EffectLaw``).
It runs closed-loop under a PID position controller with model feedforward (nominal m, phi and
the trained friction model: it does not know the effect), integrated with fine Karnopp
stick-slip steps (``MotorAxis.karnopp``), and it is observed through noisy, quantized sensors.
Many logs advance together in one vectorized loop.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..data import MotionLog, synthesize_benchmark
from ..data.motionlog import MIN_SAMPLES
from ..effects import EFFECTS, Effect
from ..fit import as_rng, default_elm
from ..friction import preset
from ..model import FrictionModel
from .axis import AxisState, MotorAxis
from .effect_law import EffectLaw

#: The effects a truth axis can hide, with their size at magnitude 1 (see ``truth_parameters``).
HIDDEN_EFFECTS = ("none", "position_ripple", "direction_asymmetry", "constant_load",
                  "inertia_mismatch", "force_constant_mismatch", "extra_friction_source",
                  "frictional_lag", "thermal_drift", "position_friction")

#: Reference sizes at magnitude 1 (SI units); ``magnitude`` scales each.
RIPPLE_AMPLITUDE, RIPPLE_PERIOD, RIPPLE_PHASE = 3.0, 0.012, 0.7    # N, m, rad
ASYMMETRY = 0.2               # friction in the negative direction is (1 + 0.2) times larger
LOAD = 5.0                    # N
INERTIA = 0.3                 # true mass = (1 + 0.3) nominal
FORCE_CONSTANT = -0.15        # true phi = (1 - 0.15) nominal
EXTRA_SOURCE = dict(fc=2.0, fs=6.0, vs=0.03, B=15.0)   # fc, fs, B scale; vs does not
LAG_TAU = 0.02                # s
FRICTION_RIPPLE = 2.0         # N: sgn(v) 2 sin(2 pi x / RIPPLE_PERIOD + RIPPLE_PHASE)
DRIFT_RATE = 0.02             # friction level grows by 2 % per second

#: The truth axis' friction: Table 1 of the paper.
TRUTH_FRICTION = preset("paper3")

#: Sensor noise at noise = 1 (standard deviations) and quantization steps.
SIGMA_X, Q_X = 0.5e-6, 1e-6   # m
SIGMA_V, Q_V = 5e-4, 1e-4     # m/s
SIGMA_I, Q_I = 0.02, 0.005    # A


#: The longest log synthesized (20 minutes at 1 kHz: 1.2 million samples).
MAX_DURATION = 1200.0


@dataclass(frozen=True)
class LogSpec:
    """One synthetic log: the hidden effect and its magnitude, seed, noise scale and axis
    (the truth axis of [C1], with Table 1's friction).

    Parameters
    ----------
    effect : str
        The hidden effect, one of ``HIDDEN_EFFECTS`` ("none": none).
    magnitude : float
        Its size in units of the reference size (``magnitude_range`` bounds it).
    seed : int
        Seeds the reference trajectory and the sensor noise.
    duration : float
        Length of the log (s), at most ``MAX_DURATION``.
    noise : float
        Scale of the sensor noise (0: none).
    mass, force_constant, i_max : float
        Nominal m (kg), phi (N/A) and current limit (A) of the axis.
    sample_rate : float
        Samples per second (Hz).
    substeps : int
        Karnopp integration steps per sample.

    Examples
    --------
    >>> from fricgen.sim import LogSpec
    >>> LogSpec("constant_load", duration=2.0).n_samples
    2001
    >>> LogSpec("gremlins")
    Traceback (most recent call last):
    ValueError: effect must be one of [...], got 'gremlins'
    """

    effect: str = "none"
    magnitude: float = 1.0
    seed: int = 0
    duration: float = 12.0
    noise: float = 1.0
    mass: float = 4.0
    force_constant: float = 20.0
    sample_rate: float = 1000.0
    substeps: int = 10
    i_max: float = 20.0

    def __post_init__(self):
        if self.effect not in HIDDEN_EFFECTS:
            raise ValueError(f"effect must be one of {list(HIDDEN_EFFECTS)}, got {self.effect!r}")
        for name in ("duration", "mass", "force_constant", "sample_rate", "i_max"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        if not self.noise >= 0:
            raise ValueError(f"noise must be >= 0, got {self.noise}")
        if not self.duration <= MAX_DURATION:
            raise ValueError(f"duration must be <= {MAX_DURATION:g} s, got {self.duration}")
        if self.n_samples < MIN_SAMPLES:
            shortest = (MIN_SAMPLES - 1) / self.sample_rate
            raise ValueError(f"duration must be >= {shortest:g} s, the {MIN_SAMPLES} samples a log "
                             f"needs at {self.sample_rate:g} Hz, got {self.duration:g}")
        low, high = magnitude_range(self.effect, self.mass, self.force_constant)
        if not (np.isfinite(self.magnitude) and low < self.magnitude <= high):
            upper = f" and <= {high:g}" if high < math.inf else ""
            raise ValueError(f"magnitude must be a finite number > {low:g}{upper} for "
                             f"{self.effect}, got {self.magnitude:g}"[:200])

    @property
    def n_samples(self) -> int:
        """The samples of the log: ``duration`` at ``sample_rate``, both ends included."""
        return int(round(self.duration * self.sample_rate)) + 1


def magnitude_range(effect: str, mass: float, force_constant: float) -> Tuple[float, float]:
    """The magnitudes k, low < k <= high, at which ``effect`` is physical and reads as what its
    name says: k > 0 (the reference size fixes each effect's sign, and 0 hides nothing), and
    each parameter, linear in k, within the limits the effect library sets (``Effect.limits``:
    a positive tau, a force constant within a factor 5 of the nominal, ...). ``high`` is
    rounded down to 3 significant digits."""
    low, high = 0.0, math.inf
    if effect == "none":
        return low, high
    at0, at1 = (truth_effect(effect, k, mass, force_constant) for k in (0.0, 1.0))
    for name, (lo, hi) in at1.limits().items():
        p0, dp = getattr(at0, name), getattr(at1, name) - getattr(at0, name)
        if dp != 0:
            ends = sorted(((lo - p0) / dp, (hi - p0) / dp))
            low, high = max(low, ends[0]), min(high, ends[1])
    if high < math.inf:
        digits = 2 - math.floor(math.log10(high))
        high = math.floor(high * 10 ** digits) / 10 ** digits
    return low, high


def truth_parameters(spec: LogSpec) -> Dict[str, float]:
    """The hidden effect's true parameters, named as the diagnosis reports them."""
    return _parameters(spec.effect, spec.magnitude, spec.mass, spec.force_constant)


def _parameters(e: str, k: float, mass: float, force_constant: float) -> Dict[str, float]:
    """``truth_parameters`` of the effect ``e`` at magnitude ``k`` on the nominal axis."""
    if e == "position_ripple":
        return {"amplitude": RIPPLE_AMPLITUDE * k, "period": RIPPLE_PERIOD, "phase": RIPPLE_PHASE}
    if e == "position_friction":
        return {"amplitude": FRICTION_RIPPLE * k, "period": RIPPLE_PERIOD, "phase": RIPPLE_PHASE}
    if e == "direction_asymmetry":
        return {"gain_positive": 0.0, "gain_negative": ASYMMETRY * k}
    if e == "constant_load":
        return {"load": LOAD * k}
    if e == "inertia_mismatch":
        return {"mass": mass * (1.0 + INERTIA * k)}
    if e == "force_constant_mismatch":
        return {"force_constant": force_constant * (1.0 + FORCE_CONSTANT * k)}
    if e == "extra_friction_source":
        return {"fc": EXTRA_SOURCE["fc"] * k, "fs": EXTRA_SOURCE["fs"] * k,
                "vs": EXTRA_SOURCE["vs"], "B": EXTRA_SOURCE["B"] * k}
    if e == "frictional_lag":
        return {"tau": LAG_TAU * k}
    if e == "thermal_drift":
        return {"rate": DRIFT_RATE * k}
    return {}


def truth_effects(spec: LogSpec) -> Tuple[Effect, ...]:
    """The hidden effect of ``spec`` as an object of the effect library (none: no effect)."""
    if spec.effect == "none":
        return ()
    return (truth_effect(spec.effect, spec.magnitude, spec.mass, spec.force_constant),)


def truth_effect(e: str, k: float, mass: float, force_constant: float) -> Effect:
    """The effect ``e`` at magnitude ``k`` on the nominal axis, an object of the library."""
    context = {"inertia_mismatch": {"nominal_mass": mass},
               "force_constant_mismatch": {"nominal_force_constant": force_constant},
               "extra_friction_source": {"shape": TRUTH_FRICTION.shape},
               "thermal_drift": {"offset": 0.0, "t0": 0.0}}
    return EFFECTS[e](**_parameters(e, k, mass, force_constant), **context.get(e, {}))


def truth_law(specs: Sequence[LogSpec]) -> EffectLaw:
    """The truth force law of a batch of axes: the paper's friction (Table 1) and, on axis j,
    the hidden effect of ``specs[j]`` (specs share the nominal mass, phi and i_max)."""
    first = specs[0]
    return EffectLaw.batch(TRUTH_FRICTION, [truth_effects(s) for s in specs], mass=first.mass,
                           force_constant=first.force_constant, i_max=first.i_max)


def reference_trajectory(t, seed, ramp: float = 0.5):
    """A reversing multisine x_d(t) (and v_d, a_d) that fades in over ``ramp`` seconds.

    Five components from 0.3 to 4.7 Hz (random phases, +-10 % frequency jitter per seed) give
    speeds up to ~0.2 m/s, accelerations up to ~3 m/s^2 and about 0.1 m of travel.
    """
    rng = as_rng(seed)
    f = np.array([0.31, 0.73, 1.37, 2.9, 4.7]) * rng.uniform(0.9, 1.1, 5)
    vel = np.array([0.06, 0.06, 0.04, 0.05, 0.03])
    w = 2 * np.pi * f
    amp, ph = vel / w, rng.uniform(0, 2 * np.pi, 5)
    t = np.asarray(t, dtype=float)[:, None]
    arg = w * t + ph
    y = np.sum(amp * (np.sin(arg) - np.sin(ph)), axis=1)   # starts at 0
    yd = np.sum(amp * w * np.cos(arg), axis=1)
    ydd = np.sum(-amp * w * w * np.sin(arg), axis=1)
    tau = np.clip(t[:, 0] / ramp, 0.0, 1.0)
    s = 3 * tau ** 2 - 2 * tau ** 3
    sd = np.where(tau < 1, (6 * tau - 6 * tau ** 2) / ramp, 0.0)
    sdd = np.where(tau < 1, (6 - 12 * tau) / ramp ** 2, 0.0)
    return s * y, sd * y + s * yd, sdd * y + 2 * sd * yd + s * ydd


def _quantize(value, step):
    return np.round(value / step) * step


def nominal_model(seed: int = 0) -> FrictionModel:
    """The friction model a user would have: the default ELM trained on the paper benchmark."""
    bench = synthesize_benchmark(preset("paper3"), seed=seed)
    return FrictionModel.fit(bench.dataset, default_elm(seed), name="fric_model")


def synthesize_logs(specs: Sequence[LogSpec], model: Optional[FrictionModel] = None) -> List[MotionLog]:
    """Closed-loop logs of the truth axes of ``specs`` (one vectorized simulation).

    All specs must share duration, sample rate, substeps and nominal axis. The controller is
    i = [m_N (a_d + kp e + kd de + ki int e) + F_model(v_d)] / phi_N, saturated at +-i_max,
    with a 20 Hz closed-loop bandwidth, fed by the measured (noisy, quantized) x and v.
    """
    specs = list(specs)
    if not specs:
        raise ValueError("specs must hold at least one LogSpec")
    first = specs[0]
    shared = ("duration", "sample_rate", "substeps", "mass", "force_constant", "i_max")
    for s in specs[1:]:
        if any(getattr(s, k) != getattr(first, k) for k in shared):
            raise ValueError(f"specs must share {', '.join(shared)}")
    model = nominal_model() if model is None else model
    ts = 1.0 / first.sample_rate
    n = first.n_samples
    t = np.arange(n) * ts
    refs = [reference_trajectory(t, s.seed) for s in specs]
    xd, vd, ad = (np.stack([r[k] for r in refs], axis=1) for k in range(3))
    feedforward = model.force(vd)
    m_n, phi_n = first.mass, first.force_constant
    w = 2 * np.pi * 20.0
    kp, kd, ki = w * w, 2 * 0.7 * w, 0.1 * w ** 3
    # sensor noise, one independent stream per log: (sample, sensor, log)
    z = np.stack([np.random.default_rng([s.seed, 7]).standard_normal((n, 3)) * s.noise
                  for s in specs], axis=2)

    axis = MotorAxis(truth_law(specs))
    state = AxisState.of(np.zeros(len(specs)))
    logs = np.zeros((3, n, len(specs)))
    integral = np.zeros(len(specs))
    for k in range(n):
        xm = _quantize(state.x + SIGMA_X * z[k, 0], Q_X)
        vm = _quantize(state.v + SIGMA_V * z[k, 1], Q_V)
        e = xd[k] - xm
        integral += e * ts
        i = (m_n * (ad[k] + kp * e + kd * (vd[k] - vm) + ki * integral) + feedforward[k]) / phi_n
        i = np.clip(i, -first.i_max, first.i_max)
        logs[:, k] = (xm, vm, _quantize(i + SIGMA_I * z[k, 2], Q_I))
        state = axis.karnopp(state, i, ts, first.substeps)
    return [MotionLog(t=t, x=logs[0, :, j], v=logs[1, :, j], i=logs[2, :, j],
                      extra={"x_d": xd[:, j]}) for j in range(len(specs))]


def synthesize_log(spec: LogSpec, model: Optional[FrictionModel] = None) -> MotionLog:
    """One closed-loop log of the truth axis of ``spec`` (``synthesize_logs``).

    Parameters
    ----------
    spec : LogSpec
        The log's hidden effect, seed, noise and axis.
    model : FrictionModel, optional
        The friction model of the controller's feed-forward (default: ``nominal_model()``, the
        default ELM trained on the paper's benchmark).

    Returns
    -------
    MotionLog
        t, x, v, i as measured (noisy, quantized), and the reference in ``extra["x_d"]``.

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.sim import LogSpec, synthesize_log
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=10, random_state=0))
    >>> log = synthesize_log(LogSpec("position_ripple", duration=1.0, substeps=2), model)
    >>> len(log), sorted(log.extra), bool(abs(log.x).max() < 0.2)
    (1001, ['x_d'], True)
    """
    return synthesize_logs([spec], model)[0]
