"""Robot joints whose friction depends on the load and the temperature, each written from a law
of its own rather than from fricgen's model form, for the load-and-temperature tests and
benchmark (rotary units: rad, rad/s, Nm, kg m^2, degC, W, K/W, J/K).

Both joints follow a prescribed reference exactly (an ideal position servo) and log the motor
torque at the joint that does it,

    force = J a + L + F(v, L, T) + o + noise,

L the gravity torque the motor holds up (the sign of [C1]: the drive supplies it), F the
friction, o a constant offset of the torque reading. J is constant: the payload's own inertia is
lumped into it (the feature's contract has one J). The motor lifts the load where v L > 0
(driving) and is driven by it where v L < 0 (back-driving). F(0, ., .) = 0: at rest the servo
holds the load alone.

``HarmonicJoint``, the harmonic-drive joint of an arm (shoulder or elbow) under gravity:

    L(q) = (m_link + s m_payload) g r cos(q + phi),      s the share of the full payload,
    F = sgn(v) theta(T) [Fc + (Fs - Fc) exp(-(|v| / vs)^delta) + k_q |L|] + B(T) v,
    mu(T) / mu(25) = exp(b / (T + 273.15 - T_V) - b / (298.15 - T_V))      (Vogel),
    B(T) = B25 mu(T) / mu(25),     theta(T) = (mu(T) / mu(25))^p,

k_q = k_d driving and k_b < k_d back-driving: the mesh's friction grows with the torque it
carries and adds to the static and Coulomb levels alike (the no-load Stribeck drop is the
bearings' and the seals'); b follows from the drawn mu(25) / mu(60) and Vogel temperature T_V;
the levels fall more weakly than the viscous term (p < 1). One thermal node,

    C dT/dt = |F v| + c_cu tau^2 - (T - T_amb) / R,      tau = J a + L + F + o,

the friction's heat and the motor's copper loss; R C = 5-10 min.

``PlanetaryJoint``, the planetary-geared joint of a palletizer arm whose load always pulls down
(the arm stays where cos q > 0.35):

    L(q) = (G_arm + s G_part) cos q,       s the share of the full part carried (0 moving empty),
    F = sgn(v) [Fc + lambda_q(|v|) |L|] + B25 nu(T) / nu(25) v,
    lambda = 1 / eta_f(|v|) - 1 driving,  1 - eta_b(|v|) back-driving,
    eta(|v|) = eta_inf - (eta_inf - eta_0) exp(-|v| / v_eta)                (each efficiency),
    log10 log10(nu + 0.7) = A - B log10(T + 273.15)                          (Walther, nu in cSt),

the mesh's loss from the gear's forward and backward efficiencies (lifting, the motor supplies
|L| / eta_f; lowering, it holds back eta_b |L|), both lower at low speed (mixed lubrication);
Walther's A and B from the drawn nu(25) and nu(25) / nu(60); Fc the seals' and bearings'. Two
thermal nodes, the oil (heated by the friction; the sensor sits in it) and the housing (heated by
the motor), integrated by RK4:

    C_o dT_o/dt = |F v| - (T_o - T_h) / R_oh,
    C_h dT_h/dt = c_cu tau^2 + (T_o - T_h) / R_oh - (T_h - T_amb) / R_ha.

The thermal state advances in steps of THERMAL_STEP under the step's mean heat, the friction held
at the step's temperature (the joint warms by less than 0.01 degC in a step). Each joint's cooling
is sized to its duty: R (R_oh and R_ha, the capacities divided by the same factor, which keeps
every time constant) is set so that the warming duty of the joint's seed ends at a drawn
TARGET_END degC from AMBIENT (``sized``).

The logs, at RATE Hz: ``t`` (s), ``x`` (an encoder of ENCODER_COUNTS counts per turn, read as the
count's centre), ``force`` (the torque plus white noise, Nm), ``load`` (L, Nm, exact: it comes
from the robot's model), ``temperature`` (a sensor read every THERMAL_STEP s and held: noise
SENSOR_NOISE, steps of SENSOR_STEP degC); the truth beside them: ``true_x``, ``true_v``,
``true_a``, ``true_temperature`` (the friction's), ``true_friction``. ``noise=False`` logs the
exact x, force and temperature.

The held-out design (``logs``):

- ``train``: the warming duty, DUTY_RUNS runs of RUN_SECONDS (20 min) from AMBIENT, the payload
  alternating by run between TRAIN_PAYLOADS (none, the full one); HarmonicJoint: random
  sinusoids (whole periods, from rest to rest) and point-to-point moves with a cruise, speeds
  log-uniform in SPEEDS; PlanetaryJoint: random pick-and-place cycles (the part carried on the
  move from the pick to the place point, low to high or high to low).
- ``heldout``: HELDOUT_SECONDS after the duty and HELDOUT_REST s at rest (the duty's thermal
  state carried over and cooled, motor off), with HELDOUT_PAYLOAD (half the full one: |L| within
  the training's), another trajectory family and a lighter duty (dwells of HELDOUT_DWELL): it
  runs at about 43-58 degC, a band in the upper half of the training's span reached by another
  path (cooled down, then level or warming slowly). HarmonicJoint: a work cycle through
  HELDOUT_WAYPOINTS fixed waypoints, repeated; PlanetaryJoint: palletizing, one pick point and a
  stack of place points that rises layer by layer.
- ``constant``: CONSTANT_SECONDS of the training's trajectory family with the gravity off (the
  joint's axis vertical, the arm horizontal: L = 0) at a drawn constant temperature (a thermal
  chamber): only the sensor's noise varies. A model should depend on neither input here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Dict, List, Tuple

import numpy as np

GRAVITY = 9.81                          # m/s^2
KELVIN = 273.15
AMBIENT = 25.0                          # degC, the reference temperature of the drawn laws
HOT = 60.0                              # degC, where the drawn viscosity ratios are read
TARGET_END = (58.0, 62.0)               # degC, the warming duty's sized end temperature
RATE = 200.0                            # Hz, the logs' rate
ENCODER_COUNTS = 2 ** 17                # per turn
SENSOR_NOISE, SENSOR_STEP = 0.1, 0.1    # degC
THERMAL_STEP = 0.1                      # s, the thermal model's step and the sensor's period
SIZING_STEP, SIZING_ITERATIONS = 1.0, 3     # s, the thermal model's step when sizing the cooling
DUTY_RUNS, RUN_SECONDS = 10, 120.0
HELDOUT_REST, HELDOUT_SECONDS, CONSTANT_SECONDS = 180.0, 300.0, 300.0
TRAIN_PAYLOADS, HELDOUT_PAYLOAD = (0.0, 1.0), 0.5     # shares of the full payload
SPEEDS = (0.05, 1.5)                    # rad/s, cruise and peak speeds (log-uniform)
ACCELERATIONS = (2.0, 5.0)              # rad/s^2, peak accelerations of the moves
MIN_CRUISE, MAX_CRUISE = 0.3, 8.0       # s, a move's cruise
MIN_MOVE = 0.3                          # rad, the shortest move
DWELL, HELDOUT_DWELL = (0.2, 1.0), (3.0, 8.0)         # s, after each piece
CONSTANT_TEMPERATURE = (30.0, 50.0)     # degC, the thermal chamber's
TWO_PI = 2.0 * math.pi

# HarmonicJoint's trajectories
WORKSPACE = 2.6                         # rad, |q| at most
SINE_AMPLITUDE = (0.2, 1.2)             # rad
SINE_PERIODS = (1, 3)                   # whole periods per sinusoid
SINE_PERIOD = 12.0                      # s, the longest period (slow sinusoids are small)
HELDOUT_WAYPOINTS = 6

# PlanetaryJoint's trajectories (q = 0: the arm horizontal)
LOW, HIGH = (-1.0, -0.1), (0.2, 1.2)    # rad, the pick and place points' ranges
LAYER = 0.08                            # rad, a pallet layer's rise

Reference = Dict[str, np.ndarray]       # x, v, a (rad, rad/s, rad/s^2), payload (share)


def _loguniform(rng, lo: float, hi: float) -> float:
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


# ----------------------------------------------------------------------------- references
def _piece(x, v, a, payload: float = 0.0) -> Reference:
    return {"x": x, "v": v, "a": a, "payload": np.full(x.size, payload)}


def _rest(x0: float, seconds: float, dt: float, payload: float = 0.0) -> Reference:
    n = max(int(round(seconds / dt)), 1)
    return _piece(np.full(n, x0), np.zeros(n), np.zeros(n), payload)


def _sine(x0: float, amplitude: float, speed: float, periods: int, dt: float,
          payload: float = 0.0) -> Reference:
    """x0 + A (1 - cos w t) over whole periods, from rest to rest; peak speed |A| w = speed."""
    w = speed / abs(amplitude)
    t = np.arange(math.ceil(periods * TWO_PI / w / dt)) * dt
    return _piece(x0 + amplitude * (1.0 - np.cos(w * t)), amplitude * w * np.sin(w * t),
                  amplitude * w * w * np.cos(w * t), payload)


def _move(x0: float, x1: float, speed: float, accel: float, dt: float,
          payload: float = 0.0) -> Reference:
    """From rest at x0 to rest at x1: a cosine ramp up to ``speed`` (peak acceleration
    ``accel``, ramp time tr = pi speed / (2 accel)), a cruise, the mirror ramp down; the speed
    lowered where the move is too short for MIN_CRUISE s of cruise."""
    d, sign = abs(x1 - x0), math.copysign(1.0, x1 - x0)
    c = math.pi / (2.0 * accel)          # tr = c speed; d = speed tr + speed tc
    speed = min(speed, (-MIN_CRUISE + math.sqrt(MIN_CRUISE ** 2 + 4.0 * c * d)) / (2.0 * c))
    tr = c * speed
    tc = d / speed - tr
    t = np.arange(math.ceil((2.0 * tr + tc) / dt)) * dt
    u = np.clip(t - tr - tc, 0.0, tr)                       # time into the ramp down
    up, down = t < tr, t >= tr + tc
    k = math.pi / tr
    v = np.where(up, 0.5 * speed * (1.0 - np.cos(k * t)),
                 np.where(down, 0.5 * speed * (1.0 + np.cos(k * u)), speed))
    a = np.where(up, accel * np.sin(k * t), np.where(down, -accel * np.sin(k * u), 0.0))
    x = np.where(up, 0.5 * speed * (t - np.sin(k * t) / k),
                 np.where(down, speed * (0.5 * tr + tc) + 0.5 * speed * (u + np.sin(k * u) / k),
                          speed * (t - 0.5 * tr)))
    return _piece(x0 + sign * x, sign * v, sign * a, payload)


def _transfer(rng, x0: float, x1: float, dt: float, payload: float,
              dwell: Tuple[float, float]) -> List[Reference]:
    """A move to x1 carrying ``payload`` at a speed and acceleration drawn, then a dwell drawn
    in ``dwell`` (a part gripped or released)."""
    move = _move(x0, x1, _loguniform(rng, *SPEEDS), rng.uniform(*ACCELERATIONS), dt, payload)
    return [move, _rest(x1, rng.uniform(*dwell), dt)]


def _join(pieces: List[Reference]) -> Reference:
    return {k: np.concatenate([p[k] for p in pieces]) for k in pieces[0]}


def _duration(pieces: List[Reference], dt: float) -> float:
    return sum(p["x"].size for p in pieces) * dt


# ----------------------------------------------------------------------------- the shared run
class _LoadedJoint:
    """What both joints share: the run under a reference, the sensors, the logs. A joint
    defines ``load(q, payload)``, ``true_friction(v, load, temperature)``, its thermal state
    (``initial_state``, ``advance``, ``with_cooling``) and its trajectories (``reference``,
    ``heldout_reference``)."""

    @property
    def resolution(self) -> float:
        """rad per encoder count."""
        return TWO_PI / ENCODER_COUNTS

    def torque(self, a, load, friction):
        """The motor torque J a + L + F + o (Nm)."""
        return self.inertia * a + load + friction + self.offset

    def heats(self, ref: Reference, load, temperature: float, per: int) -> np.ndarray:
        """The friction heat |F v| and the copper loss c_cu tau^2 (W) along ``ref`` at
        ``temperature``, each the mean of ``per`` samples: shape (2, steps)."""
        f = self.true_friction(ref["v"], load, temperature)
        tau = self.torque(ref["a"], load, f)
        steps = int(math.ceil(f.size / per))
        heat = np.zeros((2, steps * per))
        heat[0, :f.size], heat[1, :f.size] = np.abs(f * ref["v"]), self.copper * tau * tau
        return heat.reshape(2, steps, per).mean(axis=2)

    def sized(self, ref: Reference, seed: int) -> "_LoadedJoint":
        """The joint with its cooling sized so that ``ref`` (a warming duty from AMBIENT) ends
        at a temperature drawn in TARGET_END: the thermal model under the duty's heats (their
        means over each SIZING_STEP, interpolated in the temperature), its resistances
        rescaled SIZING_ITERATIONS times."""
        target = np.random.default_rng([seed, 7]).uniform(*TARGET_END)
        load = self.load(ref["x"], ref["payload"])
        grid = np.linspace(AMBIENT, TARGET_END[1] + 5.0, 6)
        per = int(round(SIZING_STEP * self.rate))
        heats = np.array([self.heats(ref, load, temp, per) for temp in grid])  # grid, 2, steps
        joint = self
        for _ in range(SIZING_ITERATIONS):
            state = joint.initial_state(AMBIENT)
            for k in range(heats.shape[2]):
                temp = state[0]
                state = joint.advance(state, float(np.interp(temp, grid, heats[:, 0, k])),
                                      float(np.interp(temp, grid, heats[:, 1, k])), SIZING_STEP)
            joint = joint.with_cooling((target - AMBIENT) / (state[0] - AMBIENT))
        return joint

    def rested(self, state: Tuple[float, ...], seconds: float) -> Tuple[float, ...]:
        """The thermal state after ``seconds`` at rest, the brakes on and the motor off."""
        for _ in range(int(round(seconds / SIZING_STEP))):
            state = self.advance(state, 0.0, 0.0, SIZING_STEP)
        return state

    def run(self, ref: Reference, start: Tuple[float, ...], noise_seed, noise: bool = True,
            gravity: bool = True, chamber: bool = False):
        """The joint along ``ref`` from the thermal state ``start``, its measurement noise drawn
        from ``noise_seed``; ``gravity`` False: L = 0; ``chamber``: the thermal state held.
        Returns (log, the thermal state at the end)."""
        x, v, a = ref["x"], ref["v"], ref["a"]
        n, per = x.size, max(int(round(THERMAL_STEP * self.rate)), 1)
        load = self.load(x, ref["payload"]) if gravity else np.zeros(n)
        friction, temperature = np.empty(n), np.empty(n)
        state = start
        for k in range(0, n, per):
            s = slice(k, k + per)
            temperature[s] = state[0]
            friction[s] = f = self.true_friction(v[s], load[s], state[0])
            if not chamber:
                tau = self.torque(a[s], load[s], f)
                state = self.advance(state, float(np.mean(np.abs(f * v[s]))),
                                     self.copper * float(np.mean(tau * tau)), per / self.rate)
        force = self.torque(a, load, friction)
        sensed, measured = temperature, x
        if noise:
            rng = np.random.default_rng(noise_seed)
            force = force + self.force_noise * rng.standard_normal(n)
            reads = temperature[::per] + SENSOR_NOISE * rng.standard_normal(temperature[::per].size)
            sensed = np.repeat(np.round(reads / SENSOR_STEP) * SENSOR_STEP, per)[:n]
            measured = (np.floor(x / self.resolution) + 0.5) * self.resolution
        log = {"t": np.arange(n) / self.rate, "x": measured, "force": force, "load": load,
               "temperature": sensed, "true_x": x, "true_v": v, "true_a": a,
               "true_temperature": temperature, "true_friction": friction}
        return log, state

    def duty_log(self, seed: int, noise: bool = True):
        """The warming duty from AMBIENT: (log, the thermal state at its end)."""
        return self.run(self.duty_reference(seed), self.initial_state(AMBIENT), [seed, 11], noise)

    def heldout_log(self, seed: int, after: Tuple[float, ...], noise: bool = True):
        """The held-out run, HELDOUT_REST s at rest after the thermal state ``after`` (the
        duty's end)."""
        start = self.rested(after, HELDOUT_REST)
        return self.run(self.heldout_reference(seed), start, [seed, 12], noise)[0]

    def constant_log(self, seed: int, noise: bool = True):
        """No gravity, a constant temperature drawn in CONSTANT_TEMPERATURE."""
        rng = np.random.default_rng([seed, 3])
        temperature = rng.uniform(*CONSTANT_TEMPERATURE)
        ref = self.reference(rng, CONSTANT_SECONDS, (0.0,))
        return self.run(ref, self.initial_state(temperature), [seed, 13], noise, gravity=False,
                        chamber=True)[0]

    def duty_reference(self, seed: int) -> Reference:
        return self.reference(np.random.default_rng([seed, 1]), RUN_SECONDS,
                              TRAIN_PAYLOADS * (DUTY_RUNS // len(TRAIN_PAYLOADS)))


def logs(joint: _LoadedJoint, seed: int, noise: bool = True) -> Dict[str, Dict[str, np.ndarray]]:
    """{"train": the warming duty, "heldout": the held-out run after it, "constant": the
    constant-conditions log} of ``joint``, drawn from ``seed``."""
    train, end = joint.duty_log(seed, noise)
    return {"train": train, "heldout": joint.heldout_log(seed, end, noise),
            "constant": joint.constant_log(seed, noise)}


# ----------------------------------------------------------------------------- HarmonicJoint
@dataclass(frozen=True)
class HarmonicJoint(_LoadedJoint):
    """A harmonic-drive joint under gravity (the law in the module's docstring)."""

    inertia: float = 5.0                # J, kg m^2
    link_mass: float = 12.0             # kg
    payload_mass: float = 5.0           # kg, the full payload
    radius: float = 0.5                 # r, m
    phase: float = 0.0                  # phi, rad
    coulomb: float = 5.0                # Fc, Nm at no load and 25 degC
    static: float = 7.5                 # Fs, Nm
    stribeck: float = 0.03              # vs, rad/s
    shape: float = 1.5                  # delta
    slope_driving: float = 0.10         # k_d
    slope_back: float = 0.05            # k_b
    viscous: float = 20.0               # B25, Nm s/rad
    viscosity_ratio: float = 3.0        # mu(25) / mu(60)
    vogel_temperature: float = 170.0    # T_V, K
    level_exponent: float = 0.15        # p
    time_constant: float = 450.0        # R C, s
    thermal_resistance: float = 1.0     # R, K/W
    copper: float = 1e-3                # c_cu, W/Nm^2
    offset: float = 0.0                 # o, Nm
    force_noise: float = 0.5            # Nm
    rate: float = RATE                  # Hz

    #: The friction law's parameters (the fields ``true_friction`` reads) and plausible bounds.
    LAW = {"coulomb": (0.5, 20.0), "static": (0.5, 40.0), "stribeck": (0.003, 0.5),
           "shape": (0.5, 3.0), "slope_driving": (0.0, 0.4), "slope_back": (0.0, 0.4),
           "viscous": (1.0, 100.0), "viscosity_ratio": (1.0, 8.0),
           "vogel_temperature": (100.0, 220.0), "level_exponent": (0.0, 1.0)}

    def load(self, q, payload):
        """L = (m_link + payload x m_payload) g r cos(q + phi), Nm (``payload`` a share)."""
        mass = self.link_mass + np.asarray(payload) * self.payload_mass
        return mass * GRAVITY * self.radius * np.cos(np.asarray(q) + self.phase)

    @property
    def peak_gravity(self) -> float:
        """The largest |L|, with the full payload (Nm)."""
        return (self.link_mass + self.payload_mass) * GRAVITY * self.radius

    def viscosity(self, temperature):
        """mu(T) / mu(25) (Vogel)."""
        tv = self.vogel_temperature
        hot, ref = HOT + KELVIN - tv, AMBIENT + KELVIN - tv
        b = math.log(self.viscosity_ratio) / (1.0 / ref - 1.0 / hot)
        return np.exp(b / (np.asarray(temperature, dtype=float) + KELVIN - tv) - b / ref)

    def true_friction(self, v, load, temperature):
        """F(v, L, T) (Nm), sgn(0) = 0."""
        v, load = np.asarray(v, dtype=float), np.asarray(load, dtype=float)
        mu = self.viscosity(temperature)
        slope = np.where(v * load > 0, self.slope_driving, self.slope_back)
        level = (self.coulomb + (self.static - self.coulomb) * np.exp(-(np.abs(v) / self.stribeck)
                                                                    ** self.shape)
                 + slope * np.abs(load))
        return np.sign(v) * mu ** self.level_exponent * level + self.viscous * mu * v

    def initial_state(self, temperature: float) -> Tuple[float, ...]:
        return (float(temperature),)

    def advance(self, state, friction_heat: float, copper_heat: float, h: float):
        """Exact over h under constant heat: T -> T_eq + (T - T_eq) exp(-h / RC)."""
        eq = AMBIENT + self.thermal_resistance * (friction_heat + copper_heat)
        return (eq + (state[0] - eq) * math.exp(-h / self.time_constant),)

    def with_cooling(self, factor: float) -> "HarmonicJoint":
        return replace(self, thermal_resistance=self.thermal_resistance * factor)

    def reference(self, rng, seconds: float, payloads) -> Reference:
        """Runs of ``seconds`` (the last piece finished), one per payload share: random
        sinusoids (a period of SINE_PERIOD s at most, a peak acceleration of ACCELERATIONS[1]
        at most) and point-to-point moves (MAX_CRUISE s of cruise at most) within +-WORKSPACE,
        each followed by a dwell."""
        dt, pieces, x0 = 1.0 / self.rate, [], 0.0
        for payload in payloads:
            start = _duration(pieces, dt)
            while _duration(pieces, dt) - start < seconds:
                speed = _loguniform(rng, *SPEEDS)
                if rng.random() < 0.5:
                    periods = int(rng.integers(SINE_PERIODS[0], SINE_PERIODS[1] + 1))
                    high = min(SINE_AMPLITUDE[1], speed * SINE_PERIOD / TWO_PI)
                    low = min(max(SINE_AMPLITUDE[0], speed ** 2 / ACCELERATIONS[1]), high)
                    amp = rng.uniform(low, high)
                    inward = abs(x0) + 2.0 * amp > WORKSPACE or rng.random() < 0.5
                    amp *= -math.copysign(1.0, x0) if inward else math.copysign(1.0, x0)
                    pieces.append(_sine(x0, amp, speed, periods, dt, payload))
                else:
                    accel = rng.uniform(*ACCELERATIONS)
                    reach = speed * (MAX_CRUISE + math.pi * speed / (2.0 * accel))
                    x1 = float(np.clip(rng.uniform(-WORKSPACE, WORKSPACE), x0 - reach, x0 + reach))
                    if abs(x1 - x0) < MIN_MOVE:
                        x1 = x0 - math.copysign(MIN_MOVE, x0)
                    pieces.append(_move(x0, x1, speed, accel, dt, payload))
                    x0 = x1
                pieces.append(_rest(x0, rng.uniform(*DWELL), dt, payload))
        return _join(pieces)

    def heldout_reference(self, seed: int) -> Reference:
        """A work cycle through HELDOUT_WAYPOINTS waypoints, each leg at its own speed and
        acceleration, a dwell at each waypoint; repeated for HELDOUT_SECONDS, payload
        HELDOUT_PAYLOAD."""
        rng = np.random.default_rng([seed, 2])
        dt = 1.0 / self.rate
        points = rng.uniform(-WORKSPACE, WORKSPACE, HELDOUT_WAYPOINTS)
        legs = [(_loguniform(rng, *SPEEDS), rng.uniform(*ACCELERATIONS),
                 rng.uniform(*HELDOUT_DWELL)) for _ in points]
        pieces, x0 = [_rest(points[-1], 0.5, dt, HELDOUT_PAYLOAD)], float(points[-1])
        while _duration(pieces, dt) < HELDOUT_SECONDS:
            for x1, (speed, accel, dwell) in zip(points, legs):
                pieces += [_move(x0, x1, speed, accel, dt, HELDOUT_PAYLOAD),
                           _rest(x1, dwell, dt, HELDOUT_PAYLOAD)]
                x0 = float(x1)
        return _join(pieces)


def random_harmonic_joint(seed: int) -> HarmonicJoint:
    """A joint from ``seed``: J 1-10 kg m^2, r 0.3-0.7 m, the link's peak gravity 15-100 Nm and
    the full payload's 0.3-0.5 of it (peak 20-150 Nm), phi anywhere; Fc 2-10 Nm, Fs / Fc 1.2-2,
    vs 0.01-0.1 rad/s, delta 1-2; k_d 0.06-0.15, k_b / k_d 0.35-0.7; B25 5-40 Nm s/rad,
    mu(25) / mu(60) 2-4, T_V 140-190 K, p 0.1-0.25; R C 5-10 min, a copper loss of 3-10 W at the
    peak gravity; o within +-0.5 Nm, a force noise of 5-15 % of Fc (log-uniform where the range
    spans a decade or so); the cooling sized to its warming duty."""
    rng = np.random.default_rng([seed, 41])
    radius = rng.uniform(0.3, 0.7)
    link = rng.uniform(15.0, 100.0) / (GRAVITY * radius)
    payload = link * rng.uniform(0.3, 0.5)
    coulomb = rng.uniform(2.0, 10.0)
    driving = rng.uniform(0.06, 0.15)
    peak = (link + payload) * GRAVITY * radius
    joint = HarmonicJoint(
        inertia=_loguniform(rng, 1.0, 10.0), link_mass=link, payload_mass=payload, radius=radius,
        phase=rng.uniform(-math.pi, math.pi), coulomb=coulomb,
        static=coulomb * rng.uniform(1.2, 2.0), stribeck=_loguniform(rng, 0.01, 0.1),
        shape=rng.uniform(1.0, 2.0), slope_driving=driving,
        slope_back=driving * rng.uniform(0.35, 0.7), viscous=_loguniform(rng, 5.0, 40.0),
        viscosity_ratio=rng.uniform(2.0, 4.0), vogel_temperature=rng.uniform(140.0, 190.0),
        level_exponent=rng.uniform(0.1, 0.25), time_constant=rng.uniform(300.0, 600.0),
        copper=rng.uniform(3.0, 10.0) / peak ** 2, offset=rng.uniform(-0.5, 0.5),
        force_noise=coulomb * rng.uniform(0.05, 0.15))
    return joint.sized(joint.duty_reference(seed), seed)


# ----------------------------------------------------------------------------- PlanetaryJoint
@dataclass(frozen=True)
class PlanetaryJoint(_LoadedJoint):
    """A planetary-geared palletizer joint (the law in the module's docstring)."""

    inertia: float = 5.0                # J, kg m^2
    arm_gravity: float = 50.0           # G_arm, Nm: the arm's gravity torque when horizontal
    part_gravity: float = 30.0          # G_part, Nm: the full part's
    coulomb: float = 5.0                # Fc, Nm
    forward: float = 0.9                # eta_f at speed
    forward_low: float = 0.75           # eta_f at rest
    back: float = 0.85                  # eta_b at speed
    back_low: float = 0.7               # eta_b at rest
    efficiency_speed: float = 0.1       # v_eta, rad/s
    viscous: float = 20.0               # B25, Nm s/rad
    oil_viscosity: float = 220.0        # nu(25), cSt
    oil_ratio: float = 3.0              # nu(25) / nu(60)
    oil_capacity: float = 200.0         # C_o, J/K
    housing_capacity: float = 900.0     # C_h, J/K
    oil_resistance: float = 0.5         # R_oh, K/W
    housing_resistance: float = 1.0     # R_ha, K/W
    copper: float = 1e-3                # c_cu, W/Nm^2
    offset: float = 0.0                 # o, Nm
    force_noise: float = 0.5            # Nm
    rate: float = RATE                  # Hz

    #: The friction law's parameters and plausible bounds, as HarmonicJoint.LAW.
    LAW = {"coulomb": (0.5, 20.0), "forward": (0.3, 1.0), "forward_low": (0.2, 1.0),
           "back": (0.3, 1.0), "back_low": (0.2, 1.0), "efficiency_speed": (0.005, 2.0),
           "viscous": (1.0, 100.0), "oil_viscosity": (20.0, 2000.0), "oil_ratio": (1.0, 8.0)}

    def load(self, q, payload):
        """L = (G_arm + payload x G_part) cos q, Nm (``payload`` the share carried)."""
        return (self.arm_gravity + np.asarray(payload) * self.part_gravity) * np.cos(np.asarray(q))

    @property
    def peak_gravity(self) -> float:
        return self.arm_gravity + self.part_gravity

    def viscosity(self, temperature):
        """nu(T) / nu(25) (Walther)."""
        def walther(nu):
            return math.log10(math.log10(nu + 0.7))
        lo, hi = math.log10(AMBIENT + KELVIN), math.log10(HOT + KELVIN)
        w25 = walther(self.oil_viscosity)
        slope = (w25 - walther(self.oil_viscosity / self.oil_ratio)) / (hi - lo)
        logt = np.log10(np.asarray(temperature, dtype=float) + KELVIN)
        return (10.0 ** (10.0 ** (w25 - slope * (logt - lo))) - 0.7) / self.oil_viscosity

    def efficiencies(self, v):
        """(eta_f, eta_b) at |v|."""
        fade = np.exp(-np.abs(np.asarray(v, dtype=float)) / self.efficiency_speed)
        return (self.forward - (self.forward - self.forward_low) * fade,
                self.back - (self.back - self.back_low) * fade)

    def true_friction(self, v, load, temperature):
        """F(v, L, T) (Nm), sgn(0) = 0."""
        v, load = np.asarray(v, dtype=float), np.asarray(load, dtype=float)
        forward, back = self.efficiencies(v)
        loss = np.where(v * load > 0, 1.0 / forward - 1.0, 1.0 - back)
        return (np.sign(v) * (self.coulomb + loss * np.abs(load))
                + self.viscous * self.viscosity(temperature) * v)

    def initial_state(self, temperature: float) -> Tuple[float, ...]:
        return (float(temperature), float(temperature))

    def advance(self, state, friction_heat: float, copper_heat: float, h: float):
        """RK4 over h of the oil and housing nodes under constant heat."""
        def rates(s):
            flow = (s[0] - s[1]) / self.oil_resistance
            return np.array([(friction_heat - flow) / self.oil_capacity,
                             (copper_heat + flow - (s[1] - AMBIENT) / self.housing_resistance)
                             / self.housing_capacity])
        s = np.array(state)
        k1 = rates(s)
        k2 = rates(s + 0.5 * h * k1)
        k3 = rates(s + 0.5 * h * k2)
        k4 = rates(s + h * k3)
        s = s + h * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0
        return (float(s[0]), float(s[1]))

    def with_cooling(self, factor: float) -> "PlanetaryJoint":
        return replace(self, oil_resistance=self.oil_resistance * factor,
                       housing_resistance=self.housing_resistance * factor,
                       oil_capacity=self.oil_capacity / factor,
                       housing_capacity=self.housing_capacity / factor)

    def reference(self, rng, seconds: float, payloads) -> Reference:
        """Runs of ``seconds`` (the last cycle finished), one per part (its share): pick-and-place
        cycles between a low and a high point drawn per cycle, picking at either, the part
        carried on the move from the pick to the place point."""
        dt, pieces, x0 = 1.0 / self.rate, [], 0.0
        for payload in payloads:
            start = _duration(pieces, dt)
            while _duration(pieces, dt) - start < seconds:
                low, high = rng.uniform(*LOW), rng.uniform(*HIGH)
                pick, place = (low, high) if rng.random() < 0.5 else (high, low)
                pieces += _transfer(rng, x0, pick, dt, 0.0, DWELL)
                pieces += _transfer(rng, pick, place, dt, payload, DWELL)
                x0 = place
        return _join(pieces)

    def heldout_reference(self, seed: int) -> Reference:
        """Palletizing for HELDOUT_SECONDS: parts of HELDOUT_PAYLOAD picked at one high point,
        placed on a stack that starts low and rises by LAYER per part (back to the bottom when
        full), each move at its own speed, longer dwells."""
        rng = np.random.default_rng([seed, 2])
        dt = 1.0 / self.rate
        pick, bottom = rng.uniform(HIGH[0] + 0.3, HIGH[1]), rng.uniform(LOW[0], LOW[0] + 0.3)
        layers = int((pick - MIN_MOVE - bottom) / LAYER)
        pieces, x0, k = [_rest(pick, 0.5, dt)], pick, 0
        while _duration(pieces, dt) < HELDOUT_SECONDS:
            place = bottom + LAYER * (k % layers)
            pieces += _transfer(rng, x0, place, dt, HELDOUT_PAYLOAD, HELDOUT_DWELL)
            pieces += _transfer(rng, place, pick, dt, 0.0, HELDOUT_DWELL)
            x0, k = pick, k + 1
        return _join(pieces)


def random_planetary_joint(seed: int) -> PlanetaryJoint:
    """A joint from ``seed``: J 1-10 kg m^2, the arm's gravity 20-80 Nm and the full part's
    0.4-0.8 of it (peak 28-144 Nm); Fc 2-10 Nm; eta_f 0.8-0.95 at speed and 0.75-0.9 of it at
    rest, eta_b 0.85-1 of eta_f at speed and 0.75-0.9 of it at rest, v_eta 0.03-0.3 rad/s;
    B25 5-40 Nm s/rad, nu(25) 100-500 cSt, nu(25) / nu(60) 2-4; the oil's time constant
    R_oh C_o 1-3 min, the housing's R_ha C_h 10-20 min, R_oh / R_ha 0.3-0.6; a copper loss of
    3-10 W at the peak gravity; o within +-0.5 Nm, a force noise of 5-15 % of Fc; the cooling
    sized to its warming duty."""
    rng = np.random.default_rng([seed, 43])
    arm = rng.uniform(20.0, 80.0)
    part = arm * rng.uniform(0.4, 0.8)
    coulomb = rng.uniform(2.0, 10.0)
    forward = rng.uniform(0.8, 0.95)
    back = forward * rng.uniform(0.85, 1.0)
    oil_resistance = rng.uniform(0.3, 0.6)          # the housing's 1 K/W before the sizing
    joint = PlanetaryJoint(
        inertia=_loguniform(rng, 1.0, 10.0), arm_gravity=arm, part_gravity=part, coulomb=coulomb,
        forward=forward, forward_low=forward * rng.uniform(0.75, 0.9), back=back,
        back_low=back * rng.uniform(0.75, 0.9), efficiency_speed=_loguniform(rng, 0.03, 0.3),
        viscous=_loguniform(rng, 5.0, 40.0), oil_viscosity=_loguniform(rng, 100.0, 500.0),
        oil_ratio=rng.uniform(2.0, 4.0), oil_resistance=oil_resistance, housing_resistance=1.0,
        oil_capacity=rng.uniform(60.0, 180.0) / oil_resistance,
        housing_capacity=rng.uniform(600.0, 1200.0),
        copper=rng.uniform(3.0, 10.0) / (arm + part) ** 2,
        offset=rng.uniform(-0.5, 0.5), force_noise=coulomb * rng.uniform(0.05, 0.15))
    return joint.sized(joint.duty_reference(seed), seed)
