"""The effects a scenario hides in its plant, as force-law closures of their own (not the
diagnosis' forms, ``fricgen.effects``), applied at their **reference magnitude** times
``magnitude``, and the plant's force law of [C1], that carries them.

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
position_friction      0.2 F_c sgn(v) sin(2 pi x / P + phase), P as position_ripple's: a
                       friction level that changes periodically along the travel
=====================  ========================================================================

Out-of-vocabulary shapes (``hidden`` entries ``"oov:<shape>"``), at reference magnitude:

=====================  ========================================================================
ripple_harmonics       cogging with its 2nd and 3rd harmonics: 0.12, 0.10, 0.08 F_c
local_drag             0.5 F_c sgn(v) over a raised-cosine stretch of 5-15 % of the travel,
                       exactly 0 outside it
tight_spot             F_c sgn(v) (the friction doubled) over a raised-cosine stretch of 2 %
                       of the travel, in its middle 60 %: a tight spot of a guide or screw
nonlinear_viscous      c sgn(v) |v|^p, p 3-4, 0.4 F_c at v_pk (p = 2 is a Gauss-shaped extra
                       source with a negative Stribeck part and a large vs: not outside)
actuator_deadzone      h(i) = sgn(i) max(|i| - i_dz, 0), phi i_dz = 0.2 F_c
actuator_saturation    h(i) = i_s tanh(i / i_s), i_s = i_pk / 1.2
sensor_delay           the controller and the log see x and v late: 2 ms or more, such that
                       delay x RMS d/dt (m a_d + F_p(v_d)) = 0.1 F_c, at most 0.5 rad at the
                       fastest loop's crossover (>= 1 sample)
=====================  ========================================================================
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Dict, Optional

import numpy as np
from scipy.signal import lfilter

from ..data import MotionLog
from ..effects import EFFECTS
from .plant_friction import StretchedStribeck, log_uniform

#: The named effects the generator can hide (keys of ``fricgen.effects.EFFECTS``).
NAMED = ("position_ripple", "direction_asymmetry", "constant_load", "inertia_mismatch",
         "force_constant_mismatch", "extra_friction_source", "frictional_lag", "thermal_drift",
         "position_friction")
#: Shapes outside the named forms, hidden as ``"oov:<shape>"``.
OUT_OF_VOCABULARY = ("ripple_harmonics", "local_drag", "nonlinear_viscous", "actuator_deadzone",
                     "actuator_saturation", "sensor_delay", "tight_spot")
#: The order that seeds each effect's draws (``effect_rng``): names added later go at its end,
#: so that the scenarios of a seed keep their draws.
_DRAW_ORDER = NAMED[:8] + OUT_OF_VOCABULARY[:6] + NAMED[8:] + OUT_OF_VOCABULARY[6:]
#: The plant's Stribeck table covers speeds up to this (m/s); S is flat long before.
TABLE_TOP = 100.0

#: Named effects the generator hides under an out-of-vocabulary name of its own, kept so that
#: the scenarios of a seed keep their draws (the diagnosis names ``sensor_delay`` since, and
#: ``actuator_saturation`` in a form of its own: a force constant falling with i^2, not tanh).
HIDDEN_AS_OOV = ("sensor_delay", "actuator_saturation")

#: Named effects the generator does not hide: its plants' friction is a static curve (the
#: LuGre plants of ``benchmarks/second_simulator.py`` hold pre-sliding).
NOT_HIDDEN = ("presliding",)

assert set(NAMED) | set(HIDDEN_AS_OOV) | set(NOT_HIDDEN) == set(EFFECTS) and set(HIDDEN_AS_OOV) <= set(OUT_OF_VOCABULARY)


@dataclass
class HiddenEffects:
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


class PlantLaw:
    """The plant's ``ForceLaw`` (``sim.axis``): base friction, hidden closures."""

    def __init__(self, friction: StretchedStribeck, hidden: HiddenEffects, mass, force_constant, i_max):
        self.friction, self.hidden = friction, hidden
        self.mass = mass * hidden.mass_factor
        self.force_constant = force_constant * hidden.phi_factor
        self.i_max = i_max
        self.lag_tau = hidden.lag_tau
        self._speeds, self._stribeck = friction.table(TABLE_TOP)

    def thrust(self, i):
        """phi i: the hidden actuator's shape acts on the current before (``closed_loop``)."""
        return self.force_constant * i

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


def effect_rng(seed, name):
    return np.random.default_rng([seed, 3, _DRAW_ORDER.index(name)])


def add_effect(h: HiddenEffects, name: str, k: float, rng, ctx: dict) -> None:
    """Add effect ``name`` at ``k`` times its reference magnitude (module docstring), with
    its force signature along a log (``hidden_forces``)."""
    fc, vpk = ctx["coulomb"], ctx["v_peak"]
    sign = float(rng.choice([-1.0, 1.0]))
    p: dict
    if name in ("position_ripple", "ripple_harmonics", "position_friction"):
        period = _ripple_period(rng, ctx)
        if name != "ripple_harmonics":
            amps, phases = [0.2 * fc * k], [rng.uniform(0, 2 * np.pi)]
        else:
            amps = [0.12 * fc * k, 0.10 * fc * k, 0.08 * fc * k]
            phases = rng.uniform(0, 2 * np.pi, 3).tolist()
        wn = 2 * np.pi / period
        against_motion = name == "position_friction"

        def force(x, v, t):
            f = sum(a * np.sin((j + 1) * wn * np.asarray(x) + ph)
                    for j, (a, ph) in enumerate(zip(amps, phases)))
            return np.sign(v) * f if against_motion else f
        h.external.append(force)          # 0 at rest when against motion: it pushes no axis
        signature = _external_signature(force)
        p = ({"amplitudes": amps, "period": period, "phases": phases} if name == "ripple_harmonics"
             else {"amplitude": amps[0], "period": period, "phase": phases[0]})
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
    elif name in ("local_drag", "tight_spot"):
        lo, hi = ctx["x_range"]
        if name == "local_drag":
            width = (hi - lo) * rng.uniform(0.05, 0.15)
            centre = rng.uniform(lo + 0.3 * (hi - lo), hi - 0.3 * (hi - lo))
            drag = 0.5 * fc * k
        else:
            width = 0.02 * (hi - lo)
            centre = rng.uniform(lo + 0.2 * (hi - lo), hi - 0.2 * (hi - lo))
            drag = fc * k

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


def hidden_forces(h: HiddenEffects, log: MotionLog, friction, mass, phi) -> Dict[str, np.ndarray]:
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
    return log_uniform(rng, lo, hi)


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
