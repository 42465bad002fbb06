"""Randomized closed-loop test logs whose assumptions differ from the diagnosis' (section 6).

A scenario is a measured-style log of a plant the user does not know exactly, the friction
model the user holds and the nominal mass and force constant the user believes:

    m x'' = phi h(i) - F_p(v, t, s) - F_ext(x, v, t)        ([C1], ``MotorAxis``)

- **Plant.** Per seed: mass 0.5-20 kg, force constant 5-60 N/A and a base friction F_p of two
  or three Stribeck sources whose shapes are stretched exponentials exp(-(u/vs)^d) or
  rational powers 1/(1 + (u/vs)^d) with 0.8 <= d <= 2.5 (not the three shapes of [F2]), plus
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
  The controller acts on the noisy x and v before quantization (see ``closed_loop``).

Hidden effects (``hidden_effects``) are applied at their reference magnitude times
``magnitude``; the closed loop (``closed_loop``) is simulated in stretches stitched together.

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
from typing import Dict, Optional, Sequence, Tuple

import numpy as np

from ..data import MotionLog
from ..model import FrictionModel
from .closed_loop import CONTROLLERS, ClosedLoop, draw_controller, seam_resolution, simulate_log
from .hidden_effects import (NAMED, OUT_OF_VOCABULARY, HiddenEffects, PlantLaw, add_effect, effect_rng,
                             hidden_forces)
from .plant_friction import draw_friction, log_uniform, tabulated_force, user_model
from .trajectory import TRAJECTORIES, drawn_reference

#: Ranges drawn per seed unless fixed by an argument.
RATE_RANGE = (250.0, 4000.0)          # Hz
DURATION_RANGE = (5.0, 120.0)         # s
#: Longest log (20 minutes).
MAX_DURATION = 1200.0
#: Largest plant integration step (s).
MAX_PLANT_STEP = 2.5e-4


@dataclass(frozen=True)
class Scenario:
    """One test log and what the user holds about its plant (``make_scenario``).

    Parameters
    ----------
    log : MotionLog
        The measured-style log of the plant of [C1].
    model : FrictionModel
        The friction model the user holds.
    mass, force_constant : float
        The nominal m (kg) and phi (N/A) the user believes.
    hidden : tuple of str
        The hidden effects' names.
    conditions : dict
        The settings and measured figures (JSON; see the module docstring).
    hidden_forces : dict
        Each hidden effect's force along the log (N per sample).
    true_mass : float, optional
        The plant's mass.

    Examples
    --------
    >>> import numpy as np, fricgen
    >>> from fricgen.sim import LogSpec, Scenario, synthesize_log
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=10, random_state=0))
    >>> log = synthesize_log(LogSpec("constant_load", duration=1.0, substeps=2), model)
    >>> sc = Scenario(log, model, 4.0, 20.0, ("constant_load",), true_mass=4.0,
    ...               hidden_forces={"constant_load": np.full(len(log), 5.0)})
    >>> float(sc.hidden_force[0]), round(float(log.i[0] - sc.truth_log().i[0]), 3)   # 5 N / phi
    (5.0, 0.25)
    """

    log: MotionLog
    model: FrictionModel
    mass: float
    force_constant: float
    hidden: Tuple[str, ...]
    conditions: Dict = field(default_factory=dict)
    #: Each hidden effect's force along the log (N per sample) as the residual
    #: phi i - m dv/dt - F_p(v) of the logged signals sees it (``hidden_effects.hidden_forces``).
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

    Parameters
    ----------
    seed : int
        Draws the plant, controller, trajectory and sensors.
    hidden : sequence of str
        Hidden effects: names of ``hidden_effects.NAMED`` or ``"oov:<shape>"``.
    rate_hz, duration_s : float, optional
        Sample rate (50-20000 Hz) and length (1 s to ``MAX_DURATION``) of the log.
    noise : float, optional
        Scale of the drawn sensor noise.
    controller, trajectory : str, optional
        One of ``closed_loop.CONTROLLERS`` and of ``trajectory.TRAJECTORIES``.
    feedforward : bool, optional
        Whether the controller uses inertia and friction feed-forward.
    magnitude : float
        The hidden effects' size in units of their reference size.

    Returns
    -------
    Scenario

    Notes
    -----
    A scenario takes tens of seconds (the user's model is fitted by cross-validation), so the
    example shows only the settings' checks.

    Examples
    --------
    >>> from fricgen.sim import make_scenario
    >>> sc = make_scenario(3, ("constant_load",), duration_s=5.0)     # doctest: +SKIP
    >>> make_scenario(3, ("gremlins",))
    Traceback (most recent call last):
    ValueError: unknown hidden effect 'gremlins'; named: ...
    >>> make_scenario(3, ("constant_load",), rate_hz=10.0)
    Traceback (most recent call last):
    ValueError: rate_hz must be in [50, 20000], got 10.0
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
    mass = log_uniform(prng, 0.5, 20.0)
    phi = log_uniform(prng, 5.0, 60.0)
    v_peak = log_uniform(prng, 0.05, 0.5)
    a_max = log_uniform(prng, 1.0, 15.0)
    travel = log_uniform(prng, 0.02, 0.3)
    friction = draw_friction(prng, mass, v_peak)
    f_peak = mass * a_max + float(friction(v_peak)) + max(friction.fs)
    i_peak = f_peak / phi
    i_max = i_peak * prng.uniform(2.0, 3.0)
    sensors = {
        "sigma_x": log_uniform(prng, 1e-7, 2e-6) * noise_scale,
        "q_x": float(prng.choice([1e-7, 5e-7, 1e-6, 5e-6])),
        "sigma_v": log_uniform(prng, 1e-4, 2e-3) * noise_scale,
        "q_v": float(prng.choice([1e-5, 1e-4, 5e-4])),
        "sigma_i": i_peak * log_uniform(prng, 2e-3, 2e-2) * noise_scale,
        "adc_bits": int(prng.choice([10, 12, 14, 16])),
    }
    sensors["q_i"] = 2 * i_max / 2 ** sensors["adc_bits"]
    model = user_model(friction, 1.5 * v_peak, 0.02 * friction.coulomb, int(seed) % 1000)

    # trajectory
    n = int(round(duration * rate)) + 1
    t = np.arange(n) / rate
    trng = np.random.default_rng([int(seed), 4])
    xd, vd, ad, traj_info = drawn_reference(traj_kind, trng, t, v_peak, a_max, travel)
    ctrl = draw_controller(np.random.default_rng([int(seed), 5]), kind, mass, phi, rate, use_ff)
    ff = tabulated_force(model, vd) if use_ff else np.zeros(n)

    # hidden effects
    ctx = {"coulomb": friction.coulomb, "travel": travel, "v_peak": float(np.max(np.abs(vd))),
           "mass": mass, "force_constant": phi, "a_rms": float(np.sqrt(np.mean(ad ** 2))),
           "vs": friction.vs, "duration": duration, "x_range": (float(np.min(xd)), float(np.max(xd))),
           "i_peak": i_peak, "rate_hz": rate, "v_rms": float(np.sqrt(np.mean(vd ** 2))),
           "speed": np.abs(vd), "ts": 1.0 / rate, "stribeck": friction.stribeck,
           "force_rate_rms": float(np.sqrt(np.mean(np.gradient(
               mass * ad + friction(vd), 1.0 / rate) ** 2))),
           "fast_loop": 2 * np.pi * ctrl.get("velocity_bandwidth_hz", ctrl["bandwidth_hz"])}
    h = HiddenEffects()
    for name in hidden:
        add_effect(h, name[4:] if name.startswith("oov:") else name, magnitude,
                    effect_rng(seed, name[4:] if name.startswith("oov:") else name), ctx)
    if h.delay_wanted:
        # at most 0.5 rad of phase at the fastest loop's crossover, which the hidden mass
        # and force constant errors shift by their gain
        gain = max(1.0, h.phi_factor / h.mass_factor)
        delay = min(h.delay_wanted, 0.5 / (ctx["fast_loop"] * gain))
        h.delay_samples = max(1, int(round(delay * rate)))
        h.parameters["oov:sensor_delay"].update(delay_s=h.delay_samples / rate,
                                                samples=h.delay_samples)
    law = PlantLaw(friction, h, mass, phi, i_max)

    step = min(MAX_PLANT_STEP, 0.2 * law.mass / max(friction.viscous, 1e-12))
    substeps = max(1, int(math.ceil((1.0 / rate) / step)))
    cond = dict(sensors, rate_hz=rate, substeps=substeps)
    noise_rows = np.random.default_rng([int(seed), 6]).standard_normal((n, 3))
    loop = ClosedLoop(law, cond, (xd, vd, ad), ff, noise_rows, ctrl)
    (xm, vm, im), passes, seam = simulate_log(loop, np.abs(vd), seam_resolution(sensors, ctrl, phi))
    log = MotionLog(t=t, x=xm, v=vm, i=im, extra={"x_d": xd})
    forces = hidden_forces(h, log, friction, mass, phi)

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
