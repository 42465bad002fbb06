"""A rotary PMSM servo axis with cogging, written from the motor's own law rather than from
fricgen's cogging model, for the anticogging tests and benchmark:

    J w' = kt i (1 + r sin(6 p theta + psi)) - T_cog(theta) - T_g sin(theta + gamma)
           - sgn(w) (T_fr(|w|) + T_pf(theta)),

with the cogging T_cog a sum over multiples of L = lcm(slots, 2 p) per revolution (the slot and
pole interaction), a torque ripple proportional to the current at the 6th electrical harmonic
(no position force: it scales with the load), a once-per-revolution unbalance, a Stribeck +
viscous friction and a friction that varies once and twice per revolution (T_pf). The drive is
the usual cascade at ``rate``: an encoder of ``bits`` (counts floored), a PLL velocity
estimate, a position P loop, a velocity PI loop with the integrator clamped (anti-windup), a
current limit and a first-order current loop; the measured current has white noise. At rest the
axis sticks until the drive torque exceeds the breakaway (Karnopp).

A linear motor is the same law with theta the phase of one pole pair (``linear_motor``): its
position in m is theta times the pole pitch over 2 pi.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Callable, Dict, Optional, Tuple

import numpy as np

TWO_PI = 2.0 * math.pi
#: (slots, pole pairs) of the motors a seed draws from.
WINDINGS = ((12, 7), (9, 3), (12, 4), (24, 10), (18, 8))


@dataclass(frozen=True)
class ServoAxis:
    """The motor, its load and its drive (SI units, rotary: rad, Nm, A)."""

    inertia: float = 2.0e-4
    kt: float = 0.08
    slots: int = 12
    pole_pairs: int = 7
    cogging: Tuple[Tuple[float, float], ...] = ((0.040, 0.3), (0.015, 2.1), (0.006, 4.0))
    ripple: Tuple[float, float] = (0.02, 1.0)              # r, psi
    unbalance: Tuple[float, float] = (0.020, 0.7)          # T_g, gamma
    coulomb: float = 0.020
    static: float = 0.030
    stribeck: float = 0.5                                  # rad/s
    viscous: float = 2.0e-4                                # Nm s/rad
    position_friction: Tuple[Tuple[int, float, float], ...] = ((1, 0.004, 0.2), (2, 0.003, 1.3))
    bits: int = 12
    rate: float = 8000.0
    current_noise: float = 0.02                            # A, standard deviation
    i_max: float = 20.0
    current_bandwidth: float = 2 * math.pi * 1500.0        # rad/s
    pll_bandwidth: float = 2 * math.pi * 300.0
    kp: float = 60.0                                       # (rad/s) / rad
    kv: float = 0.12 / 0.08                                # A / (rad/s)
    ki: float = 0.12 / 0.08 * 2 * math.pi * 15.0           # A / rad
    seed: int = 0
    label: str = "rotary"
    pitch: float = TWO_PI                                  # x per 2 pi of theta

    @property
    def period_count(self) -> int:
        """L, the cogging's periods per revolution."""
        return math.lcm(self.slots, 2 * self.pole_pairs)

    @property
    def counts(self) -> int:
        return 2 ** self.bits

    def cogging_torque(self, theta):
        """T_cog + the unbalance: the position force that acts at rest (Nm), at theta (rad)."""
        theta = np.asarray(theta, dtype=float)
        L = self.period_count
        out = sum(a * np.sin((j + 1) * L * theta + ph) for j, (a, ph) in enumerate(self.cogging))
        g, gamma = self.unbalance
        return out + g * np.sin(theta + gamma)

    def cogging_per_count(self):
        """The position force averaged over each encoder count (what a map indexed by the count
        can at best reproduce), from 16 points per count."""
        n = self.counts
        theta = (np.arange(n)[:, None] + (np.arange(16)[None, :] + 0.5) / 16) * TWO_PI / n
        return self.cogging_torque(theta).mean(axis=1)

    def map_error(self, cogging_map) -> float:
        """RMS over the encoder's counts of a map (anything with ``force(x)``; None counts as 0)
        less ``cogging_per_count``, over the truth's RMS about its mean."""
        truth = self.cogging_per_count()
        x = np.arange(self.counts) * self.pitch / self.counts
        est = np.zeros_like(x) if cogging_map is None else cogging_map.force(x)
        return float(np.sqrt(np.mean((est - truth) ** 2)) / np.std(truth))

    def friction_level(self, speed, theta):
        """The friction against motion at ``speed`` >= 0 and theta (Nm)."""
        level = self.coulomb + (self.static - self.coulomb) * math.exp(-(speed / self.stribeck) ** 2)
        level += self.viscous * speed
        for h, a, ph in self.position_friction:
            level += a * math.sin(h * theta + ph)
        return level


def random_axis(seed: int, bits: int = 12, linear: bool = False) -> ServoAxis:
    """An axis of random winding, cogging (1 to 3 multiples of L, decaying), ripple, unbalance
    and friction, from ``seed``."""
    rng = np.random.default_rng(seed)
    slots, pp = WINDINGS[rng.integers(len(WINDINGS))]
    base = rng.uniform(0.02, 0.06)
    n = int(rng.integers(1, 4))
    cogging = tuple((base * rng.uniform(0.2, 0.6) ** j, rng.uniform(0, TWO_PI)) for j in range(n))
    axis = ServoAxis(slots=slots, pole_pairs=pp, cogging=cogging,
                     ripple=(rng.uniform(0.0, 0.03), rng.uniform(0, TWO_PI)),
                     unbalance=(0.0 if linear else rng.uniform(0.0, 0.03), rng.uniform(0, TWO_PI)),
                     coulomb=rng.uniform(0.01, 0.03), stribeck=rng.uniform(0.2, 1.0),
                     position_friction=((1, rng.uniform(0, 0.004), rng.uniform(0, TWO_PI)),
                                        (2, rng.uniform(0, 0.003), rng.uniform(0, TWO_PI))),
                     bits=bits, seed=seed)
    axis = replace(axis, static=axis.coulomb * rng.uniform(1.2, 1.6))
    return linear_motor(axis) if linear else axis


def linear_motor(axis: ServoAxis, pole_pitch: float = 0.032) -> ServoAxis:
    """The axis as a linear motor: one 'revolution' is one pole pair's pitch (m), the cogging of
    its slots over that pitch, no unbalance (x = theta pitch / 2 pi)."""
    return replace(axis, pole_pairs=1, unbalance=(0.0, 0.0), label="linear", pitch=pole_pitch)


@dataclass
class Drive:
    """The cascade's state: the PLL, the integrator, the current; ``feedforward`` (A, a function of
    the measured theta) is the compensation added to the current command."""

    axis: ServoAxis
    feedforward: Optional[Callable[[float], float]] = None
    theta: float = 0.0
    omega: float = 0.0
    current: float = 0.0
    pos_est: float = 0.0
    vel_est: float = 0.0
    integrator: float = 0.0
    rng: np.random.Generator = field(default=None)

    def __post_init__(self):
        if self.rng is None:
            self.rng = np.random.default_rng(self.axis.seed + 7)
        L = self.axis.period_count
        self._cogging = [((j + 1) * L, a, ph) for j, (a, ph) in enumerate(self.axis.cogging)]

    def measured(self) -> float:
        """The encoder's theta: whole counts."""
        q = TWO_PI / self.axis.counts
        return math.floor(self.theta / q) * q

    def step(self, theta_ref: float, omega_ref: float, position_loop: bool) -> float:
        """One period of the cascade and the plant; returns the measured current (A)."""
        ax, dt = self.axis, 1.0 / self.axis.rate
        meas = self.measured()
        bw = ax.pll_bandwidth
        self.pos_est += dt * self.vel_est
        delta = meas - self.pos_est
        self.pos_est += dt * 2.0 * bw * delta
        self.vel_est += dt * bw * bw * delta
        vel_cmd = omega_ref + (ax.kp * (theta_ref - self.pos_est) if position_loop else 0.0)
        err = vel_cmd - self.vel_est
        self.integrator = min(max(self.integrator + dt * ax.ki * err, -ax.i_max), ax.i_max)
        i_cmd = ax.kv * err + self.integrator
        if self.feedforward is not None:
            i_cmd += self.feedforward(meas)
        i_cmd = min(max(i_cmd, -ax.i_max), ax.i_max)
        self.current += (1.0 - math.exp(-ax.current_bandwidth * dt)) * (i_cmd - self.current)
        self._plant(dt)
        return self.current + ax.current_noise * float(self.rng.standard_normal())

    def _plant(self, dt: float) -> None:
        ax, th, w = self.axis, self.theta, self.omega
        r, psi = ax.ripple
        g, gamma = ax.unbalance
        drive = ax.kt * self.current * (1.0 + r * math.sin(6 * ax.pole_pairs * th + psi))
        drive -= g * math.sin(th + gamma)
        for h, a, ph in self._cogging:
            drive -= a * math.sin(h * th + ph)
        if w == 0.0:
            breakaway = ax.friction_level(0.0, th)
            if abs(drive) <= breakaway:
                return
            w_new = dt / ax.inertia * (drive - math.copysign(breakaway, drive))
        else:
            w_new = w + dt / ax.inertia * (drive - math.copysign(ax.friction_level(abs(w), th), w))
            if w_new * w < 0.0:                        # friction does not reverse the motion
                w_new = 0.0
        self.theta = th + 0.5 * dt * (w + w_new)
        self.omega = w_new


def run(drive: Drive, theta_ref: np.ndarray, omega_ref: np.ndarray, position_loop: bool = True,
        every: int = 4) -> Dict[str, np.ndarray]:
    """Run the drive along the references (one value per period); the log every ``every``
    periods: t (s), x (axis units: rad, or m for a linear motor), i (A, measured), and the true
    theta and omega."""
    n = len(theta_ref)
    keep = n // every
    out = {k: np.empty(keep) for k in ("t", "x", "i", "theta", "omega")}
    scale = drive.axis.pitch / TWO_PI
    for k in range(n):
        i = drive.step(float(theta_ref[k]), float(omega_ref[k]), position_loop)
        if k % every == every - 1 and k // every < keep:
            j = k // every
            out["t"][j] = (k + 1) / drive.axis.rate
            out["x"][j] = drive.measured() * scale
            out["i"][j] = i
            out["theta"][j] = drive.theta
            out["omega"][j] = drive.omega
    return out


def calibration_move(axis: ServoAxis, turns: float = 2.0, speed: float = 3.0,
                     feedforward=None, every: int = 4) -> Dict[str, np.ndarray]:
    """The log (every ``every`` periods) of a position-controlled move of ``turns`` revolutions
    forward and back at ``speed`` (rad/s of theta), with a quarter second at rest before,
    between and after."""
    dt = 1.0 / axis.rate
    ramp = np.arange(0.0, turns * TWO_PI / speed, dt) * speed
    rest = np.zeros(int(0.25 * axis.rate))
    top = turns * TWO_PI
    theta = np.concatenate([rest, ramp, rest + top, top - ramp, rest])
    omega = np.concatenate([rest, np.full(ramp.size, speed), rest, np.full(ramp.size, -speed), rest])
    return run(Drive(axis, feedforward), theta, omega, position_loop=True, every=every)


def count_lookup(values, counts: int) -> Callable[[float], float]:
    """A drive's feedforward (A) of the measured theta (whole counts) from one value per count."""
    table = [float(v) for v in values]
    quantum = TWO_PI / counts
    return lambda theta: table[round(theta / quantum) % counts]


def map_feedforward(axis: ServoAxis, cogging_map) -> Optional[Callable[[float], float]]:
    """The current (A) a drive feeds forward at the measured theta: a cogging map (of x = theta
    pitch / 2 pi) over kt at each count; None for no map."""
    if cogging_map is None:
        return None
    theta = np.arange(axis.counts) * TWO_PI / axis.counts
    return count_lookup(cogging_map.force(theta * axis.pitch / TWO_PI) / axis.kt, axis.counts)
