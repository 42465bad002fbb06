"""A linear precision stage with dynamic (pre-sliding) friction, written from its own LuGre-type
law rather than from fricgen's models, for the dynamic-friction tests and benchmark (SI: m, N,
kg, s):

    m x'' = u - F,    F = sigma0 z + sigma1(v) z' + B v,    z' = v - sigma0 |v| z / g(v),
    g(v) = Fc_d + (Fs_d - Fc_d) exp(-|v / vs|^delta),       sigma1(v) = sigma1 exp(-(v / vd)^2),

with v = x', z the bristles' mean deflection, d the direction of v (Fc_+ = Fc (1 + a/2),
Fc_- = Fc (1 - a/2), Fs_d = Fc_d Fs / Fc: an asymmetry a of up to 15 %), the shape delta drawn
in [1, 2.5] and a micro-damping that fades with speed (the common variant of LuGre). In steady
sliding z' = 0 and F = sgn(v) g(v) + B v; at rest below the breakaway the bristles are a spring
of stiffness sigma0, and Fc / sigma0 is the pre-sliding distance.

The plant is integrated by classical RK4 with ``substeps`` steps per control period (the
bristles are stiff: |v| sigma0 / g reaches 5e4 1/s at the fastest moves), under a force held
over the period (zero-order hold). The drive, at ``rate``: an encoder of ``resolution`` m per
count (counts floored), read as the count's centre (count + 1/2) q, which takes away the
half-count bias of the floor; a velocity estimate that is the first difference of the measured
position over one period, low-passed by a first-order filter at ``velocity_filter`` Hz; a PID
position loop u = m a_ref + Kp e + Kd (v_ref - v_est) + I + c, I' = Ki e (I clamped to the
force limit: anti-windup), whose gains put a triple real pole of the rigid mass at
2 pi ``bandwidth`` rad/s (Kd = 3 m w, Kp = 3 m w^2, Ki = m w^3); c the compensation's force;
u clamped to +-``force_limit``. The measured force is u plus white noise.

A compensation is any object with ``reset()`` and ``step(v) -> force (N)``, called once per
control period with the reference velocity or the velocity estimate (``use_reference``); its
force is added to the PID's. ``SteadyStateCompensation`` and ``ExactLuGreCompensation`` are the
plant's own steady-state curve and its own LuGre equations run as an observer.

The scenarios (``hold_after_move``, ``slow_speeds``, ``reversals``) return their metrics from
the true position (the hold's from the measured one, in counts); ``identification_log`` is the
closed-loop experiment (no compensation) a friction model is identified from.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, Optional, Sequence

import numpy as np

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class PrecisionAxis:
    """The stage, its friction and its drive (SI units)."""

    mass: float = 1.0                       # kg
    coulomb: float = 2.0                    # Fc, N (the mean of the two directions)
    static_ratio: float = 1.5               # Fs / Fc
    stribeck: float = 2e-3                  # vs, m/s
    shape: float = 2.0                      # delta
    viscous: float = 8.0                    # B, N s/m
    sigma0: float = 1e5                     # N/m (Fc / sigma0 = 20 um)
    sigma1: float = 300.0                   # N s/m, at v = 0
    damping_speed: float = 2e-3             # vd, m/s
    asymmetry: float = 0.0                  # a: Fc_+ = Fc (1 + a/2), Fc_- = Fc (1 - a/2)
    resolution: float = 0.1e-6              # m per encoder count
    force_noise: float = 0.02               # N, standard deviation of the measured force
    rate: float = 8000.0                    # Hz, the control rate
    substeps: int = 10                      # RK4 steps per control period
    bandwidth: float = 40.0                 # Hz, the PID's triple pole
    velocity_filter: float = 1000.0         # Hz, the low-pass on the first difference
    force_limit: float = 60.0               # N
    seed: int = 0

    @property
    def dt(self) -> float:
        return 1.0 / self.rate

    @property
    def presliding_distance(self) -> float:
        """Fc / sigma0 (m)."""
        return self.coulomb / self.sigma0

    @property
    def levels(self):
        """(Fc_+, Fs_+, Fc_-, Fs_-), N."""
        fcp, fcn = self.coulomb * (1 + self.asymmetry / 2), self.coulomb * (1 - self.asymmetry / 2)
        return fcp, fcp * self.static_ratio, fcn, fcn * self.static_ratio

    @property
    def gains(self):
        """(Kp N/m, Ki N/(m s), Kd N s/m): the rigid mass's triple pole at 2 pi bandwidth."""
        w = TWO_PI * self.bandwidth
        return 3.0 * self.mass * w * w, self.mass * w ** 3, 3.0 * self.mass * w

    def g(self, v):
        """The Stribeck level g(v) > 0 (N), of the direction of v (v >= 0: positive)."""
        v = np.asarray(v, dtype=float)
        fcp, fsp, fcn, fsn = self.levels
        fc, fs = np.where(v >= 0, fcp, fcn), np.where(v >= 0, fsp, fsn)
        return fc + (fs - fc) * np.exp(-np.abs(v / self.stribeck) ** self.shape)

    def steady_friction(self, v):
        """sgn(v) g(v) + B v (N), sgn(0) = 0: the friction of steady sliding at v."""
        v = np.asarray(v, dtype=float)
        return np.sign(v) * self.g(v) + self.viscous * v

    def damping(self, v):
        """sigma1(v) (N s/m)."""
        return self.sigma1 * np.exp(-(np.asarray(v, dtype=float) / self.damping_speed) ** 2)

    def counts(self, x):
        """The encoder's count of the true position x (floored)."""
        return np.floor(np.asarray(x, dtype=float) / self.resolution)


def random_precision_axis(seed: int) -> PrecisionAxis:
    """An axis of random mass, friction, encoder, noise and rate from ``seed``: m 0.5-3 kg,
    Fc 1-4 N, Fs / Fc 1.2-2, vs 0.5-5 mm/s, delta 1-2.5, B 2-20 N s/m, Fc / sigma0 5-50 um,
    sigma1 = zeta 2 sqrt(sigma0 m) with zeta 0.2-1, vd 0.5-2 vs, asymmetry a within +-0.15, an
    encoder of 0.05-0.5 um per count, a force noise of 0.5-2 % of Fc, 5-10 kHz (log-uniform
    where the range spans a decade or so); the force limit 5.5 Fs + m 10 m/s^2."""
    rng = np.random.default_rng([seed, 31])

    def loguniform(lo, hi):
        return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))

    mass = rng.uniform(0.5, 3.0)
    coulomb = rng.uniform(1.0, 4.0)
    ratio = rng.uniform(1.2, 2.0)
    stribeck = loguniform(0.5e-3, 5e-3)
    sigma0 = coulomb / loguniform(5e-6, 50e-6)
    zeta = rng.uniform(0.2, 1.0)
    return PrecisionAxis(
        mass=mass, coulomb=coulomb, static_ratio=ratio, stribeck=stribeck,
        shape=rng.uniform(1.0, 2.5), viscous=loguniform(2.0, 20.0), sigma0=sigma0,
        sigma1=zeta * 2.0 * math.sqrt(sigma0 * mass),
        damping_speed=stribeck * loguniform(0.5, 2.0), asymmetry=rng.uniform(-0.15, 0.15),
        resolution=loguniform(0.05e-6, 0.5e-6),
        force_noise=coulomb * rng.uniform(0.005, 0.02), rate=rng.uniform(5000.0, 10000.0),
        force_limit=5.0 * coulomb * ratio * 1.1 + 10.0 * mass, seed=seed)


class Plant:
    """The stage's state (x m, v m/s, z m) and its integration over one control period under a
    constant force u (N)."""

    def __init__(self, axis: PrecisionAxis, x: float = 0.0, v: float = 0.0, z: float = 0.0):
        self.axis, self.x, self.v, self.z = axis, x, v, z
        fcp, fsp, fcn, fsn = axis.levels
        self._p = (fcp, fsp - fcp, fcn, fsn - fcn, 1.0 / axis.stribeck, axis.shape, axis.sigma0,
                   axis.sigma1, 1.0 / axis.damping_speed, axis.viscous, 1.0 / axis.mass)

    def friction(self) -> float:
        """The friction force now (N)."""
        return self._rates(self.v, self.z, 0.0)[2]

    def _rates(self, v, z, u):
        fcp, dp, fcn, dn, ivs, delta, s0, s1, ivd, b, im = self._p
        av = abs(v)
        if v >= 0.0:
            g = fcp + dp * math.exp(-(av * ivs) ** delta)
        else:
            g = fcn + dn * math.exp(-(av * ivs) ** delta)
        zd = v - s0 * av * z / g
        w = v * ivd
        f = s0 * z + s1 * math.exp(-w * w) * zd + b * v
        return (u - f) * im, zd, f

    def advance(self, u: float, dt: float) -> None:
        """Integrate over dt under the force u (RK4, ``axis.substeps`` steps)."""
        rates = self._rates
        n = self.axis.substeps
        h = dt / n
        h2 = 0.5 * h
        x, v, z = self.x, self.v, self.z
        for _ in range(n):                      # RK4 of (x' = v, v' = (u - F) / m, z')
            a1, z1, _f = rates(v, z, u)
            v2 = v + h2 * a1
            a2, z2, _f = rates(v2, z + h2 * z1, u)
            v3 = v + h2 * a2
            a3, z3, _f = rates(v3, z + h2 * z2, u)
            v4 = v + h * a3
            a4, z4, _f = rates(v4, z + h * z3, u)
            x += h * (v + 2.0 * v2 + 2.0 * v3 + v4) / 6.0
            v += h * (a1 + 2.0 * a2 + 2.0 * a3 + a4) / 6.0
            z += h * (z1 + 2.0 * z2 + 2.0 * z3 + z4) / 6.0
        self.x, self.v, self.z = x, v, z


# ----------------------------------------------------------------------------- compensations
class SteadyStateCompensation:
    """The plant's true steady-state friction sgn(v) g(v) + B v (sgn(0) = 0)."""

    def __init__(self, axis: PrecisionAxis):
        self.axis = axis
        fcp, fsp, fcn, fsn = axis.levels
        self._p = (fcp, fsp - fcp, fcn, fsn - fcn, 1.0 / axis.stribeck, axis.shape, axis.viscous)

    def reset(self) -> None:
        pass

    def step(self, v: float) -> float:
        fcp, dp, fcn, dn, ivs, delta, b = self._p
        if v > 0.0:
            return fcp + dp * math.exp(-(v * ivs) ** delta) + b * v
        if v < 0.0:
            return -(fcn + dn * math.exp(-(-v * ivs) ** delta)) + b * v
        return 0.0


class ExactLuGreCompensation:
    """The plant's own LuGre equations as an observer on the velocity it is given, held over the
    period dt: z is advanced exactly (z' = v - a z with a = sigma0 |v| / g(v) constant over the
    period), and the force is the period's mean sigma0 z + sigma1(v) z' + B v."""

    def __init__(self, axis: PrecisionAxis, dt: float):
        self.axis, self.dt = axis, dt
        fcp, fsp, fcn, fsn = axis.levels
        self._p = (fcp, fsp - fcp, fcn, fsn - fcn, 1.0 / axis.stribeck, axis.shape, axis.sigma0,
                   axis.sigma1, 1.0 / axis.damping_speed, axis.viscous)
        self.z = 0.0

    def reset(self) -> None:
        self.z = 0.0

    def step(self, v: float) -> float:
        fcp, dp, fcn, dn, ivs, delta, s0, s1, ivd, b = self._p
        dt, z = self.dt, self.z
        av = abs(v)
        if v >= 0.0:
            g = fcp + dp * math.exp(-(av * ivs) ** delta)
        else:
            g = fcn + dn * math.exp(-(av * ivs) ** delta)
        a = s0 * av / g
        if a * dt > 1e-9:
            z_ss = v / a
            decay = math.exp(-a * dt)
            z_new = z_ss + (z - z_ss) * decay
            z_mean = z_ss + (z - z_ss) * (1.0 - decay) / (a * dt)
        else:
            z_new = z + v * dt
            z_mean = z + 0.5 * v * dt
        self.z = z_new
        w = v * ivd
        return s0 * z_mean + s1 * math.exp(-w * w) * (z_new - z) / dt + b * v


# ----------------------------------------------------------------------------- the closed loop
def simulate(axis: PrecisionAxis, x_ref, v_ref, a_ref, comp=None, use_reference: bool = False,
             noise_seed: Optional[int] = None) -> Dict[str, np.ndarray]:
    """The closed loop along the references (one value per control period, m, m/s, m/s^2),
    from rest at x = x_ref[0] with relaxed bristles. Returns arrays per period k: t (s, the
    period's start), x and v (true, at t), x_meas (the drive's reading, (count + 1/2) q, at t), v_est (m/s), u (the
    drive force held over [t, t + dt), N), force (u + the measurement noise, N), comp (the
    compensation's share of u, N), friction (the true friction at t, N)."""
    n = len(x_ref)
    dt, q, m = axis.dt, axis.resolution, axis.mass
    kp, ki, kd = axis.gains
    lim = axis.force_limit
    alpha = 1.0 - math.exp(-TWO_PI * axis.velocity_filter * dt)
    xr, vr, ar = (np.asarray(a, dtype=float).tolist() for a in (x_ref, v_ref, a_ref))
    rng = np.random.default_rng(axis.seed + 101 if noise_seed is None else noise_seed)
    noise = (axis.force_noise * rng.standard_normal(n)).tolist()
    plant = Plant(axis, x=xr[0])
    if comp is not None:
        comp.reset()
    out = {k: [0.0] * n for k in ("x", "v", "x_meas", "v_est", "u", "comp", "friction")}
    ox, ov, oxm, ove, ou, oc, of = (out[k] for k in ("x", "v", "x_meas", "v_est", "u", "comp",
                                                    "friction"))
    floor = math.floor
    xm_prev = (floor(plant.x / q) + 0.5) * q
    v_est = integ = 0.0
    for k in range(n):
        x = plant.x
        xm = (floor(x / q) + 0.5) * q
        v_est += alpha * ((xm - xm_prev) / dt - v_est)
        xm_prev = xm
        e = xr[k] - xm
        integ += ki * e * dt
        integ = lim if integ > lim else (-lim if integ < -lim else integ)
        u = m * ar[k] + kp * e + kd * (vr[k] - v_est) + integ
        c = 0.0
        if comp is not None:
            c = comp.step(vr[k] if use_reference else v_est)
            u += c
        u = lim if u > lim else (-lim if u < -lim else u)
        ox[k], ov[k], oxm[k], ove[k], ou[k], oc[k] = x, plant.v, xm, v_est, u, c
        of[k] = plant.friction()
        plant.advance(u, dt)
    res = {k: np.array(v) for k, v in out.items()}
    res["t"] = np.arange(n) * dt
    res["force"] = res["u"] + np.array(noise)
    return res


# ----------------------------------------------------------------------------- references
def _rest(x0: float, duration: float, dt: float):
    n = max(int(round(duration / dt)), 0)
    return np.full(n, x0), np.zeros(n), np.zeros(n)


def _move(x0: float, distance: float, speed: float, dt: float, ramp: float = 0.05):
    """A move of ``distance`` (signed) at the cruise ``speed`` (> 0), with raised-cosine speed
    ramps of ``ramp`` s (shortened if the move is short): (x, v, a) per period."""
    d = abs(distance)
    if d == 0.0:
        return np.array([x0]), np.zeros(1), np.zeros(1)
    ramp = min(ramp, d / speed)                   # the ramps cover speed * ramp of the distance
    cruise = d / speed - ramp
    total = 2 * ramp + cruise
    t = np.arange(int(math.ceil(total / dt))) * dt
    v = np.full(t.size, speed)
    a = np.zeros(t.size)
    up, down = t < ramp, t > ramp + cruise
    s = t[up] / ramp
    v[up] = speed * 0.5 * (1 - np.cos(math.pi * s))
    a[up] = speed * 0.5 * math.pi / ramp * np.sin(math.pi * s)
    s = (t[down] - ramp - cruise) / ramp
    v[down] = speed * 0.5 * (1 + np.cos(math.pi * s))
    a[down] = -speed * 0.5 * math.pi / ramp * np.sin(math.pi * s)
    x = np.empty(t.size)                          # the exact integral of v
    x[up] = speed * 0.5 * (t[up] - ramp / math.pi * np.sin(math.pi * t[up] / ramp))
    mid = ~up & ~down
    x[mid] = speed * (0.5 * ramp + t[mid] - ramp)
    s = t[down] - ramp - cruise
    x[down] = speed * (0.5 * ramp + cruise + 0.5 * (s + ramp / math.pi * np.sin(math.pi * s / ramp)))
    sign = 1.0 if distance >= 0 else -1.0
    return x0 + sign * x, sign * v, sign * a


def _oscillation(x0: float, amplitude: float, freq: float, cycles: float, dt: float):
    """x0 + A (1 - cos(2 pi f t)) over ``cycles`` periods: (x, v, a) per period."""
    w = TWO_PI * freq
    t = np.arange(int(round(cycles / freq / dt))) * dt
    return (x0 + amplitude * (1 - np.cos(w * t)), amplitude * w * np.sin(w * t),
            amplitude * w * w * np.cos(w * t))


def _join(pieces: Sequence):
    return tuple(np.concatenate([p[i] for p in pieces]) for i in range(3))


# ----------------------------------------------------------------------------- scenarios
#: hold_after_move: the move (m) and its peak speed (m/s), then the hold (s); the last second is
#: measured.
HOLD_MOVE, HOLD_SPEED, HOLD_TIME = 3e-3, 20e-3, 2.5
#: slow_speeds: the speeds as multiples of vs, each reached over SLOW_RAMP s; SLOW_MEASURE s are
#: measured from SLOW_SETTLE s after the start (the loop's settling: 6 / (2 pi 40 Hz) = 24 ms
#: after the ramp).
SLOW_FACTORS, SLOW_RAMP, SLOW_SETTLE, SLOW_MEASURE = (0.1, 0.3, 1.0), 0.02, 0.05, 1.0
#: reversals: the peak speed (multiple of vs) and the frequency bounds (Hz) of x = A (1 - cos):
#: A = 1 mm where that puts f in [REV_F_MIN, REV_F_MAX], else f clipped and A = peak / (2 pi f).
REV_PEAK, REV_AMPLITUDE, REV_F_MIN, REV_F_MAX, REV_PERIODS = 3.0, 1e-3, 1.0, 4.0, 4
#: The glitch window after each reversal, as a share of the period.
REV_WINDOW = 0.125


def hold_after_move(axis: PrecisionAxis, comp=None, use_reference: bool = False) -> Dict[str, float]:
    """A move of HOLD_MOVE at HOLD_SPEED, then HOLD_TIME at rest. ``amplitude``: the peak-to-peak
    of the measured position error over the last second, in counts (the limit cycle);
    ``max_error``: its largest |value|, in counts; ``true_pp``: the true position's peak-to-peak
    over the last second, in counts."""
    dt = axis.dt
    ref = _join([_rest(0.0, 0.05, dt), _move(0.0, HOLD_MOVE, HOLD_SPEED, dt),
                 _rest(HOLD_MOVE, HOLD_TIME, dt)])
    log = simulate(axis, *ref, comp=comp, use_reference=use_reference)
    last = log["t"] >= log["t"][-1] - 1.0
    err = (ref[0][last] - log["x_meas"][last]) / axis.resolution
    x = log["x"][last] / axis.resolution
    return {"amplitude": float(np.round(err.max() - err.min())), "max_error": float(np.abs(err).max()),
            "true_pp": float(x.max() - x.min())}


def slow_speeds(axis: PrecisionAxis, comp=None, use_reference: bool = False,
                factors: Sequence[float] = SLOW_FACTORS) -> Dict[str, object]:
    """Constant-speed ramps at ``factors`` x vs, alternately forward and back, each from rest
    (0.1 s): the speed rises over SLOW_RAMP s (raised cosine) and is held SLOW_MEASURE s more.
    The error is measured from SLOW_SETTLE s after the ramp's start (the loop's own settling),
    so the friction's breakaway transient is counted. ``rms``: the RMS of x_ref - x (true) over
    every measured window (m); ``per_speed``: {factor: RMS over its window}."""
    dt = axis.dt
    pieces, windows, x0 = [], [], 0.0
    for j, f in enumerate(factors):
        speed = f * axis.stribeck
        sign = 1.0 if j % 2 == 0 else -1.0
        pieces.append(_rest(x0, 0.1, dt))
        start = sum(p[0].size for p in pieces)
        dist = sign * speed * (SLOW_SETTLE + SLOW_MEASURE)
        x, v, a = _move(x0, dist, speed, dt, ramp=SLOW_RAMP)
        n = int(round((SLOW_SETTLE + SLOW_MEASURE) / dt))   # the ramp up and the cruise
        pieces.append((x[:n], v[:n], a[:n]))
        windows.append((f, start + int(round(SLOW_SETTLE / dt)), start + n))
        x0 = float(x[n - 1] + v[n - 1] * dt)
    ref = _join(pieces)
    log = simulate(axis, *ref, comp=comp, use_reference=use_reference)
    err = ref[0] - log["x"]
    per = {f: float(np.sqrt(np.mean(err[a:b] ** 2))) for f, a, b in windows}
    every = np.concatenate([err[a:b] for _, a, b in windows])
    return {"rms": float(np.sqrt(np.mean(every ** 2))), "per_speed": per}


def reversal_motion(axis: PrecisionAxis):
    """(A m, f Hz) of the reversal scenario: peak speed A 2 pi f = REV_PEAK vs."""
    peak = REV_PEAK * axis.stribeck
    f = min(max(peak / (TWO_PI * REV_AMPLITUDE), REV_F_MIN), REV_F_MAX)
    return peak / (TWO_PI * f), f


def reversals(axis: PrecisionAxis, comp=None, use_reference: bool = False,
              periods: int = REV_PERIODS) -> Dict[str, object]:
    """x_ref = A (1 - cos(2 pi f t)) from rest over ``periods`` periods (``reversal_motion``).
    The velocity reverses at every half period; per reversal after the first period, the largest
    |x_ref - x| (true) within REV_WINDOW of a period after it. ``peak``: the mean over those
    reversals (m); ``max``: the largest; ``per_reversal``: each."""
    dt = axis.dt
    amp, f = reversal_motion(axis)
    ref = _join([_oscillation(0.0, amp, f, periods, dt), _rest(0.0, 0.05, dt)])
    log = simulate(axis, *ref, comp=comp, use_reference=use_reference)
    err = np.abs(ref[0] - log["x"])
    window = int(round(REV_WINDOW / f / dt))
    peaks = []
    for j in range(2, 2 * periods):
        k = int(round(j * 0.5 / f / dt))
        peaks.append(float(err[k:k + window].max()))
    return {"peak": float(np.mean(peaks)), "max": float(np.max(peaks)), "per_reversal": peaks,
            "amplitude": amp, "frequency": f}


# ----------------------------------------------------------------------------- identification
#: The constant-velocity moves: ID_SPEEDS speeds log-spaced over [ID_LOW, ID_HIGH] x vs, each
#: way, cruising max(ID_CRUISE, ID_TRAVEL pre-sliding distances / speed) s, capped at ID_MAX_CRUISE;
#: ID_DWELL s at rest after each move.
ID_SPEEDS, ID_LOW, ID_HIGH = 10, 0.2, 50.0
ID_CRUISE, ID_TRAVEL, ID_MAX_CRUISE, ID_DWELL = 0.4, 10.0, 2.5, 0.2
#: The small reversals: x0 + A (1 - cos) at ID_SMALL_F Hz, ID_SMALL_CYCLES cycles per amplitude
#: (multiples of Fc / sigma0) around each of the points (m), reached at 5 vs.
ID_SMALL_AMPLITUDES, ID_SMALL_F, ID_SMALL_CYCLES = (0.3, 0.7, 1.5, 3.0), 2.0, 2
ID_POINTS = (1e-3, -0.5e-3, 0.2e-3)


def identification_reference(axis: PrecisionAxis, presliding: bool = True):
    """The references (x, v, a) of ``identification_log``."""
    dt, vs, d = axis.dt, axis.stribeck, axis.presliding_distance
    pieces, x0 = [_rest(0.0, 0.2, dt)], 0.0
    for speed in np.geomspace(ID_LOW * vs, ID_HIGH * vs, ID_SPEEDS):
        cruise = min(max(ID_CRUISE, ID_TRAVEL * d / speed), ID_MAX_CRUISE)
        for sign in (1.0, -1.0):
            dist = sign * speed * (cruise + 0.05)     # the two ramps add 0.05 s of cruise
            pieces += [_move(x0, dist, speed, dt), _rest(x0 + dist, ID_DWELL, dt)]
            x0 += dist
    if presliding:
        for point in ID_POINTS:
            dist = point - x0
            pieces += [_move(x0, dist, 5 * vs, dt), _rest(point, ID_DWELL, dt)]
            x0 = point
            for amp in ID_SMALL_AMPLITUDES:
                pieces += [_oscillation(x0, amp * d, ID_SMALL_F, ID_SMALL_CYCLES, dt),
                           _rest(x0, 0.1, dt)]
    return _join(pieces)


def reference_of_moves(axis: PrecisionAxis, factors: Sequence[float], cruise: float, ramp: float,
                       dwell: float = 0.3):
    """The references (x, v, a) of rest-to-rest moves each way at ``factors`` x vs, each
    cruising ``cruise`` s between raised-cosine ramps of ``ramp`` s and followed by ``dwell`` s
    at rest: a log of long moves without small reversals."""
    dt, pieces, x0 = axis.dt, [_rest(0.0, 0.2, axis.dt)], 0.0
    for speed in np.asarray(factors, dtype=float) * axis.stribeck:
        for sign in (1.0, -1.0):
            dist = sign * speed * cruise
            pieces += [_move(x0, dist, speed, dt, ramp), _rest(x0 + dist, dwell, dt)]
            x0 += dist
    return _join(pieces)


def identification_log(axis: PrecisionAxis, seed: int, presliding: bool = True) -> Dict[str, np.ndarray]:
    """A closed-loop experiment without compensation, logged at the control rate: ``t`` (s),
    ``x`` (the drive's reading of the encoder, (count + 1/2) resolution, m), ``force`` (the measured drive force held over
    [t, t + dt), N; noise drawn from ``seed``). Constant-velocity moves each way at ID_SPEEDS
    speeds from ID_LOW to ID_HIGH x vs, each followed by a dwell; with ``presliding``, then
    small oscillations of ID_SMALL_AMPLITUDES x Fc / sigma0 around each of ID_POINTS (displacements
    after a reversal shorter than the pre-sliding distance). Without, every reversal follows a
    move of at least ID_CRUISE s."""
    log = simulate(axis, *identification_reference(axis, presliding), noise_seed=seed)
    return {"t": log["t"], "x": log["x_meas"], "force": log["force"]}


def static_friction_log(axis: PrecisionAxis, seed: int) -> Dict[str, np.ndarray]:
    """The motion of ``identification_log`` (small reversals included) on an axis whose friction
    is its steady-state curve alone, sgn(v) g(v) + B v, no bristles: the true position follows
    the reference exactly, the encoder reads it as the drive does and the force is
    m a + friction + noise (``seed``). What a log without pre-sliding looks like."""
    x_ref, v_ref, a_ref = (np.asarray(r, dtype=float) for r in identification_reference(axis))
    rng = np.random.default_rng(seed)
    force = axis.mass * a_ref + axis.steady_friction(v_ref) + axis.force_noise * rng.standard_normal(x_ref.size)
    x_meas = (axis.counts(x_ref) + 0.5) * axis.resolution
    return {"t": np.arange(x_ref.size) * axis.dt, "x": x_meas, "force": force}
