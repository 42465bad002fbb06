"""The named effects that change the friction itself: a direction's level scaled, an extra
source of [F1], friction memory (frictional lag) and a drift of the level with time; each one
small class of the ``Effect`` contract (``base``)."""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar, Tuple

import numpy as np

from ..c_literal import c_float
from ..friction import SHAPES
from .base import PLAUSIBLE_FACTOR, Effect
from .fitting import grid_then_refine, lstsq
from .signals import Signals


def _sign(v):
    return np.sign(v)


@dataclass(frozen=True)
class DirectionAsymmetry(Effect):
    """Friction differs between directions: g+ F(v) for v > 0, g- F(v) for v < 0.

    Fitted one-sided (one gain is 0, the side chosen by the smaller residual).

    Parameters
    ----------
    gain_positive, gain_negative : float
        g+ and g- (dimensionless fractions of F(v) of [F3] or [F1]).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), t=np.array([0.0, 1.0]), x=np.array([0.0, 0.25]),
    ...               v=np.array([0.1, -0.1]), a=np.array([2.0, 2.0]), i=np.array([1.0, 1.0]),
    ...               sample_time=1.0)
    >>> from fricgen.effects import DirectionAsymmetry
    >>> DirectionAsymmetry(gain_positive=0.1, gain_negative=0.0).force(sig).round(3).tolist()
    [2.075, -0.0]
    """

    gain_positive: float
    gain_negative: float
    name: ClassVar[str] = "direction_asymmetry"
    in_xv: ClassVar[bool] = True

    def force(self, sig):
        v = np.asarray(sig.v)
        return np.where(v > 0, self.gain_positive, np.where(v < 0, self.gain_negative, 0.0)) * sig.friction

    @staticmethod
    def basis(sig):
        v, f = np.asarray(sig.v), sig.friction
        return np.column_stack([np.where(v > 0, f, 0.0), np.where(v < 0, f, 0.0)])

    def _sides(self):
        return [j for j, g in enumerate((self.gain_positive, self.gain_negative)) if g != 0] or [0]

    def linear(self, sig):
        gains = np.array([self.gain_positive, self.gain_negative])
        return self.basis(sig)[:, self._sides()], gains[self._sides()]

    def variants(self):
        """This side and the other: which direction differs is decided jointly with the others
        (a force-constant error changes both directions' level)."""
        if self.gain_positive == self.gain_negative:        # no side chosen: one form
            return (self,)
        return (self, replace(self, gain_positive=self.gain_negative, gain_negative=self.gain_positive))

    def with_coefficients(self, coef):
        gains = [0.0, 0.0]
        for j, g in zip(self._sides(), coef):
            gains[j] = float(g)
        return replace(self, gain_positive=gains[0], gain_negative=gains[1])

    @classmethod
    def fit(cls, problem, rows):
        basis, r = problem.at_rows(cls.basis(problem.signals), rows), problem.target[rows]
        (gp,), rss_p = lstsq(basis[:, :1], r)
        (gn,), rss_n = lstsq(basis[:, 1:], r)
        if rss_p <= rss_n:
            return cls(gain_positive=float(gp), gain_negative=0.0)
        return cls(gain_positive=0.0, gain_negative=float(gn))

    def c_expr(self):
        return (f"((v > 0.0f) ? {c_float(self.gain_positive)} : ((v < 0.0f) ? "
                f"{c_float(self.gain_negative)} : 0.0f)) * base")

    def force_f32(self, v, x, base):
        f32 = np.float32
        g = np.where(v > 0, f32(self.gain_positive), np.where(v < 0, f32(self.gain_negative), f32(0)))
        return g.astype(f32) * base


@dataclass(frozen=True)
class ExtraFrictionSource(Effect):
    """An additional source of [F1]: sgn(v) [fc + (fs - fc) g(v, vs)] + B v.

    Parameters
    ----------
    fc, fs : float
        Coulomb and Stribeck friction (N).
    vs : float
        Stribeck velocity (m/s), > 0.
    B : float
        Viscous coefficient (N s/m).
    shape : str
        g of [F2].

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), t=np.array([0.0, 1.0]), x=np.array([0.0, 0.25]),
    ...               v=np.array([0.1, -0.1]), a=np.array([2.0, 2.0]), i=np.array([1.0, 1.0]),
    ...               sample_time=1.0)
    >>> from fricgen.effects import ExtraFrictionSource
    >>> ExtraFrictionSource(fc=1.0, fs=2.0, vs=0.01, B=0.0).force(sig).round(3).tolist()
    [1.0, -1.0]
    """

    fc: float
    fs: float
    vs: float
    B: float
    shape: str = "gauss"
    name: ClassVar[str] = "extra_friction_source"
    in_xv: ClassVar[bool] = True
    positive: ClassVar[Tuple[str, ...]] = ("vs",)

    def force(self, sig):
        v = np.asarray(sig.v)
        g = SHAPES[self.shape](v, self.vs)
        return _sign(v) * (self.fc + (self.fs - self.fc) * g) + self.B * v

    def implausible_beside(self, curve, speeds):
        """A source whose force at the log's speeds exceeds PLAUSIBLE_FACTOR times the model's
        largest friction there is no friction source: a Stribeck term of a huge level below
        the speeds the log resolves, fitted to a few rows."""
        v = np.concatenate([speeds, -speeds])
        level = float(np.max(np.abs(curve(v))))
        peak = float(np.max(np.abs(self.force(Signals(curve, v=v)))))
        if peak > PLAUSIBLE_FACTOR * level:
            return (f"its force reaches {peak:.3g} at the log's speeds, beyond "
                    f"{PLAUSIBLE_FACTOR:g} times the model's largest friction there ({level:.3g}; "
                    "both in the log's force units)")
        return ""

    @staticmethod
    def basis(v, vs, shape="gauss"):
        """The regressors sgn(v), sgn(v) g(v, vs) and v, stacked on a last axis."""
        s = _sign(v)
        return np.stack([s, s * SHAPES[shape](v, vs), v], axis=-1)

    def linear(self, sig):
        return (self.basis(np.asarray(sig.v), self.vs, self.shape),
                np.array([self.fc, self.fs - self.fc, self.B]))

    def with_coefficients(self, coef):
        fc, dfs, B = (float(c) for c in coef)
        return replace(self, fc=fc, fs=fc + dfs, B=B)

    @classmethod
    def fit(cls, problem, rows):
        """vs on a log grid from the slowest usable speed to the model's v_sat (the larger
        direction's of an asymmetric model), then (fc, fs, B)."""
        v, r = problem.signals.v, problem.target[rows]

        def rss(log_vs):
            return lstsq(problem.at_rows(lambda i: cls.basis(v[i], math.exp(log_vs)), rows), r)[1]

        slow = float(np.quantile(np.abs(v[problem.rows[rows]]), 0.02))
        lo = math.log(max(problem.v_min, slow, 1e-4))
        v_sat = max(c.v_sat for c in problem.signals.model.directions)
        hi = math.log(max(v_sat, 2 * math.exp(lo)))
        log_vs = grid_then_refine(rss, np.linspace(lo, hi, 12))
        vs = math.exp(log_vs)
        (fc, dfs, B), _ = lstsq(problem.at_rows(lambda i: cls.basis(v[i], vs), rows), r)
        return cls(fc=float(fc), fs=float(fc + dfs), vs=float(vs), B=float(B))

    def c_expr(self):
        q = f"(speed * {c_float(1.0 / self.vs)})"
        g = {"gauss": f"expf(-({q} * {q}))", "exponential": f"expf(-{q})",
             "rational": f"(1.0f / (1.0f + {q}))"}[self.shape]
        return (f"(sgn * ({c_float(self.fc)} + ({c_float(self.fs - self.fc)} * {g}))) + "
                f"({c_float(self.B)} * v)")

    def force_f32(self, v, x, base):
        f32 = np.float32
        speed = np.abs(v)
        sgn = np.where(v > 0, f32(1), np.where(v < 0, f32(-1), f32(0))).astype(f32)
        q = speed * f32(1.0 / self.vs)
        if self.shape == "gauss":
            g = np.exp((-(q * q)).astype(np.float64)).astype(f32)
        elif self.shape == "exponential":
            g = np.exp((-q).astype(np.float64)).astype(f32)
        else:
            g = f32(1) / (f32(1) + q)
        return sgn * (f32(self.fc) + f32(self.fs - self.fc) * g) + f32(self.B) * v


@dataclass(frozen=True)
class FrictionalLag(Effect):
    """Friction memory (the frictional lag of dynamic models such as LuGre or Dahl): the
    velocity-weakening part follows the speed low-passed with time constant tau,
    sgn(v) [S(s) - S(|v|)] with S(u) = |F(u)| - B u and tau s' = |v| - s; S is that of the
    direction of v (each direction's own curve of an asymmetric model).

    Parameters
    ----------
    tau : float
        The time constant (s), > 0.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), t=np.array([0.0, 1.0]), x=np.array([0.0, 0.25]),
    ...               v=np.array([0.1, -0.1]), a=np.array([2.0, 2.0]), i=np.array([1.0, 1.0]),
    ...               sample_time=1.0)
    >>> from fricgen.effects import FrictionalLag
    >>> FrictionalLag(tau=0.01).force(sig).round(3).tolist()    # |v| steady: no lag
    [0.0, -0.0]
    """

    tau: float
    name: ClassVar[str] = "frictional_lag"
    positive: ClassVar[Tuple[str, ...]] = ("tau",)

    @property
    def lag_tau(self):
        return self.tau

    def force(self, sig):
        v = np.asarray(sig.v)
        return _sign(v) * (sig.stribeck(sig.lagged_speed(self.tau), v) - sig.stribeck_speed)

    @classmethod
    def fit(cls, problem, rows):
        """tau on a log grid from 1 ms to 1 s, refined; the force has no free gain."""
        r, sig = problem.target[rows], problem.signals

        def rss(log_tau):
            lagged = sig.lagged_speed(math.exp(log_tau))
            pred = problem.at_rows(lambda i: _sign(sig.v[i]) * (sig.stribeck(lagged[i], sig.v[i])
                                                                - sig.stribeck_speed[i]), rows)
            return float(np.sum((r - pred) ** 2))

        grid = np.linspace(math.log(max(1e-3, sig.sample_time)), math.log(1.0), 16)
        return cls(tau=float(math.exp(grid_then_refine(rss, grid))))


@dataclass(frozen=True)
class ThermalDrift(Effect):
    """The friction level drifts with time as a first-order (thermal) response from the
    model's level at the start of the log t0: rate h(t - t0) F(v), h(s) = T (1 - exp(-s / T)),
    or h(s) = s when the time constant T is 0 (a linear drift).

    A drift starts from nothing: a level error already there at t0 is a change of the friction
    curve (``ExtraFrictionSource``).

    Parameters
    ----------
    rate : float
        The initial rate of change (1/s).
    offset : float
        A relative level at t0, carried for models written with one; the fit leaves it at 0.
    t0 : float
        The start of the log (s).
    time_constant : float
        T (s), >= 0.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), t=np.array([0.0, 1.0]), x=np.array([0.0, 0.25]),
    ...               v=np.array([0.1, -0.1]), a=np.array([2.0, 2.0]), i=np.array([1.0, 1.0]),
    ...               sample_time=1.0)
    >>> from fricgen.effects import ThermalDrift
    >>> ThermalDrift(rate=0.01, offset=0.0, t0=0.0).force(sig).round(3).tolist()
    [0.0, -0.208]
    """

    rate: float
    offset: float
    t0: float
    time_constant: float = 0.0
    name: ClassVar[str] = "thermal_drift"
    fixed: ClassVar[Tuple[str, ...]] = ("t0", "offset")
    non_negative: ClassVar[Tuple[str, ...]] = ("time_constant",)
    time_constants: ClassVar[Tuple[str, ...]] = ("time_constant",)

    def for_log(self, mass, force_constant, t_start):
        """The drift starts anew with each log (from the model's level at its start)."""
        return replace(self, t0=float(t_start))

    @staticmethod
    def _shape(s, time_constant):
        s, tc = np.asarray(s, dtype=float), np.asarray(time_constant, dtype=float)
        if not np.any(tc > 0):
            return s
        safe = np.where(tc > 0, tc, 1.0)
        return np.where(tc > 0, safe * -np.expm1(-s / safe), s)

    def force(self, sig):
        s = np.asarray(sig.t) - self.t0
        return (self.offset + self.rate * self._shape(s, self.time_constant)) * sig.friction

    def linear(self, sig):
        h = self._shape(np.asarray(sig.t) - self.t0, self.time_constant)
        return (h * sig.friction)[:, None], np.array([self.rate])

    def with_coefficients(self, coef):
        return replace(self, rate=float(coef[0]))

    @classmethod
    def fit(cls, problem, rows):
        """T on a log grid from a twentieth of the fitted span to five spans, refined, against
        the linear limit; the rate by least squares at each T."""
        sig = problem.signals
        t0 = float(sig.t[0])
        r = problem.target[rows]
        span = max(float(np.ptp(sig.t[problem.rows[rows]])), sig.sample_time)

        def solve(time_constant):
            basis = (cls._shape(sig.t - t0, time_constant) * sig.friction)[:, None]
            return lstsq(problem.at_rows(basis, rows), r)

        grid = np.linspace(math.log(span / 20.0), math.log(5.0 * span), 10)
        log_t = grid_then_refine(lambda g: solve(math.exp(g))[1], grid)
        time_constant = math.exp(log_t)
        (rate,), rss = solve(time_constant)
        (rate_lin,), rss_lin = solve(0.0)
        # the time constant is one parameter more: kept when Akaike's criterion, with the
        # residual's effective sample size, prefers it
        n_eff = len(rows) * problem.n_effective / max(problem.fit_rows.size, 1)
        if not n_eff * math.log(max(rss, 1e-300) / max(rss_lin, 1e-300)) < -2.0:
            return cls(rate=float(rate_lin), offset=0.0, t0=t0, time_constant=0.0)
        return cls(rate=float(rate), offset=0.0, t0=t0, time_constant=float(time_constant))
