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
