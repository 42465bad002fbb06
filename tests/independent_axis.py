"""A run-up of an axis simulated apart from fricgen: its own friction law (a squared-rational
Stribeck drop and quadratic drag), its own integrator (scipy's adaptive Runge-Kutta) and its own
sensors (a 1 um encoder and a noisy force), for tests and benchmarks that must not be judged on
data made with fricgen's assumptions."""
import numpy as np
from scipy.integrate import solve_ivp

MASS = 10.0                     # kg
COULOMB, STATIC, STRIBECK = 6.0, 9.0, 0.03     # N, N, m/s
VISCOUS, DRAG = 12.0, 4.0       # N s/m, N s^2/m^2
RATE, DURATION = 1500.0, 0.28   # Hz, s
ENCODER, FORCE_NOISE = 1e-6, 0.3  # m, N


def friction(v):
    """The true friction force (N) at velocity v (m/s)."""
    v = np.asarray(v, dtype=float)
    drop = (STATIC - COULOMB) / (1.0 + (np.abs(v) / STRIBECK) ** 2)
    return np.sign(v) * (COULOMB + drop) + VISCOUS * v + DRAG * v * np.abs(v)


def drive(t):
    """The drive force: +60 N for 0.14 s, then -30 N braking."""
    return np.where(t < 0.14, 60.0, -30.0)


def run_up(seed: int = 0, v0: float = 0.01):
    """(t, x, force) of a 0.28 s run-up from v0 to about 0.65 m/s and back, at 1.5 kHz."""
    t = np.arange(int(RATE * DURATION)) / RATE
    sol = solve_ivp(lambda _, y: [y[1], (drive(_) - friction(y[1])) / MASS], (0.0, t[-1]),
                    [0.0, v0], t_eval=t, rtol=1e-10, atol=1e-12, max_step=1e-4)
    rng = np.random.default_rng(seed)
    x = np.round(sol.y[0] / ENCODER) * ENCODER
    force = drive(t) + FORCE_NOISE * rng.standard_normal(t.size)
    return t, x, force, sol.y[1]


# ----------------------------------------------------------------------------- fleets of axes
#: A fleet axis's friction law (the same squared-rational Stribeck drop and quadratic drag as
#: ``friction``), its parameters drawn per axis around these.
FLEET_AXIS = dict(mass=8.0, coulomb=6.0, static=9.0, stribeck=0.02, viscous=12.0, drag=0.5,
                  offset=1.5)
FLEET_RATE = 1000.0             # Hz
FLEET_V_NOISE, FLEET_F_NOISE = 2e-4, 0.3     # m/s, N


def fleet_axis(seed: int) -> dict:
    """One axis of a fleet: the parameters of FLEET_AXIS, each spread by its own factor."""
    rng = np.random.default_rng([seed, 1])
    spread = dict(mass=0.2, coulomb=0.25, static=0.25, stribeck=0.3, viscous=0.25, drag=0.3,
                  offset=0.5)
    axis = {k: v * float(np.exp(spread[k] * rng.standard_normal())) for k, v in FLEET_AXIS.items()}
    axis["static"] = max(axis["static"], 1.2 * axis["coulomb"])
    return axis


def fleet_velocity(t: np.ndarray):
    """The axis's nightly motion program, velocity and acceleration: constant-speed passes in
    both directions at speeds from 3 mm/s to 0.25 m/s, joined by raised-cosine ramps of 0.15 s."""
    levels = np.geomspace(0.003, 0.25, 10)
    plan = np.ravel([[s, -s] for s in np.concatenate([levels, levels[::-1]])])
    hold, ramp = t[-1] / plan.size, 0.15
    k = np.minimum((t // hold).astype(int), plan.size - 1)
    start, prev = k * hold, np.where(k > 0, plan[k - 1], 0.0)
    u = np.clip((t - start) / ramp, 0.0, 1.0)
    shape = 0.5 - 0.5 * np.cos(np.pi * u)
    v = prev + (plan[k] - prev) * shape
    a = np.where(u < 1.0, (plan[k] - prev) * 0.5 * np.pi / ramp * np.sin(np.pi * u), 0.0)
    return v, a


def fleet_friction(axis: dict, v):
    """The axis's friction (N) at v (m/s): ``friction``'s law with the axis's parameters."""
    v = np.asarray(v, dtype=float)
    drop = (axis["static"] - axis["coulomb"]) / (1.0 + (np.abs(v) / axis["stribeck"]) ** 2)
    return np.sign(v) * (axis["coulomb"] + drop) + axis["viscous"] * v + axis["drag"] * v * np.abs(v)


def fleet_cogging(axis: dict, x):
    """The axis's cogging force (N) at the position x (m): ``cogging`` N of the fundamental of
    the pole pitch ``pitch`` (m) and a quarter of that at its second harmonic, 0 without one."""
    if not axis.get("cogging"):
        return np.zeros_like(np.asarray(x, dtype=float))
    phase = 2 * np.pi * np.asarray(x, dtype=float) / axis["pitch"]
    return axis["cogging"] * (np.sin(phase + axis.get("phase", 0.0)) + 0.25 * np.sin(2 * phase))


def fleet_log(axis: dict, seed: int, duration: float = 60.0) -> dict:
    """Columns (t, v, force) of one log of ``axis``: force = m a + friction + offset ([C1]
    with a constant load) + its cogging at the position (``fleet_cogging``; the log holds no
    position), the velocity and the force each with white sensor noise."""
    t = np.arange(int(FLEET_RATE * duration)) / FLEET_RATE
    v, a = fleet_velocity(t)
    rng = np.random.default_rng([seed, 2])
    x = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]))]) / FLEET_RATE
    force = axis["mass"] * a + fleet_friction(axis, v) + axis["offset"] + fleet_cogging(axis, x)
    return {"t": t, "v": v + FLEET_V_NOISE * rng.standard_normal(t.size),
            "force": force + FLEET_F_NOISE * rng.standard_normal(t.size)}


def write_fleet_log(path, columns: dict) -> None:
    """The log as a CSV t,v,force."""
    np.savetxt(path, np.column_stack([columns["t"], columns["v"], columns["force"]]),
               delimiter=",", header="t,v,force", comments="", fmt="%.9g")


#: The encoder-count axis: mass (kg), a PI velocity loop at the log's rate, and its own law.
COUNTS_MASS = 3.0


def counts_friction(v):
    """The encoder-count axis's law: a tanh-smoothed Coulomb level of 6 N with a Lorentzian
    Stribeck peak of 4 N at 0.015 m/s, and viscous 25 N s/m (no shape of fricgen's vocabulary)."""
    v = np.asarray(v, dtype=float)
    return np.tanh(v / 2e-4) * (6.0 + 4.0 / (1.0 + (v / 0.015) ** 2)) + 25.0 * v


def counts_log(seed: int, rate: float, duration: float, substeps: int = 20) -> dict:
    """t, the exact position x and the drive force (0.2 N noise) of a 3 kg axis under a PI
    velocity loop at ``rate`` following a triangle of +-0.2 m/s peaks, integrated by
    semi-implicit Euler at ``substeps`` steps per sample: quantize x to make an encoder's log."""
    rng = np.random.default_rng(seed)
    n, h = int(duration * rate), 1.0 / (rate * substeps)
    period = 4.0 + rng.uniform(0, 2)
    t = np.arange(n) / rate
    s = 4 * np.abs((t / period + 0.25) % 1.0 - 0.5) - 1                # triangle in [-1, 1]
    v_ref = 0.2 * s * np.abs(s)
    x = v = integral = 0.0
    xs, force = np.empty(n), np.empty(n)
    kp, ki = COUNTS_MASS * 2 * np.pi * 60, COUNTS_MASS * (2 * np.pi * 60) ** 2 / 4
    for k in range(n):
        error = v_ref[k] - v
        integral += error / rate
        f = kp * error + ki * integral
        xs[k], force[k] = x, f
        for _ in range(substeps):
            v += h * (f - counts_friction(v)) / COUNTS_MASS
            x += h * v
    return {"t": t, "x": xs, "force": force + 0.2 * rng.standard_normal(n)}
