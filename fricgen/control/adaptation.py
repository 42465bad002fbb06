"""Online adaptation of the friction model's linear output parameters (``regressor``), safe by
construction, and the backstepping controller of section 6 that compensates with it.

With F(v) = f0(v) + theta^T phi(v) (``fricgen.control.regressor``), two rules update theta once
per sample:

- ``"rls"``: recursive least squares with forgetting factor lambda on the friction observed by
  inverse dynamics ([C1], m v' = phi i - F, so F = phi (i - m_o v') with m_o = m / phi) at the
  nominal force constant phi_N and the controller's m_o_hat. Not at phi_N / k_hat: k_hat also
  scales the compensation, so a larger theta lowers k_hat, which raised y, which raised theta
  (measured: k_hat reached 0 after 140 s of the drift benchmark):

      y = phi_N (i_prev - m_o_hat (v - v_prev) / Ts)   at  v_mid = (v + v_prev) / 2
      e = y - F(v_mid),   g = P phi / (lambda + phi^T P phi),   theta += g e,
      P = (P - g (P phi)^T) / lambda   (its upper triangle, mirrored).

  The mirror keeps P symmetric in float: updated whole, rounding made P[i, k] and P[k, i]
  drift apart until P lost definiteness, and each reset to p0 threw theta (measured: RLS
  tracked 3.20x exact compensation under the drift benchmark, 1.12x with the mirror).

- ``"lyapunov"``: the gradient law of [C14] extended to theta. The compensation
  enters D_hat [C9] as k_hat F(v) / phi_N, so the regressor of theta in [C10] is
  phi(v) / phi_N and V of [C13] with the term (theta - theta*)^T Gamma_theta^-1 (theta -
  theta*) / 2 gives theta' = Gamma_theta e2 phi(v) / phi_N (k_hat ~ 1 folded into Gamma_theta),
  integrated by forward Euler over Ts as the controller does.

Safety, for both rules, in this order each sample:
  1. a non-finite input (v, the observed force or e2) changes nothing (``input fault``);
  2. while the controller's current saturates (``hold``) nothing changes (no wind-up);
  3. out of range: no update at |v| > ``v_max`` (a speed beyond what the axis does is a
     glitch; the viscous feature v is unbounded, so one such sample would move B far);
  4. dead zone: no update for |v| < ``v_dead`` (friction at rest is not observable, the axis
     sticks) or a small error, |e| < ``e_dead`` (N, RLS) or |e2| < ``e_dead`` (m/s, Lyapunov);
  5. the rule's input is clamped to +-``e_max`` (``clamped``): whatever finite value a glitch
     delivers, one update moves theta a bounded step. Default: ``RLS_ERROR_FRACTION`` of the
     band (N) for RLS; for Lyapunov the e2 at which one update moves the force by at most
     band Ts / ``RATE_TIME`` through the friction's parameters (adaptation follows slow change:
     drift, wear, temperature), and as much again through the axis's offset;
  6. RLS only: the covariance is bounded, trace(P) <= ``trace_max`` (P is scaled down when the
     forgetting would take it beyond: no wind-up of P with poor excitation); and no update at
     all in the dead zone, so P does not grow at rest;
  7. leakage toward the trained values: theta -= ``leak`` (theta - theta0) every update.
     Default: Lyapunov Ts / ``LEAK_TIME`` (what a glitch left decays); RLS 0, its forgetting
     lets later samples overwrite it (a leakage above 1 - lambda would outweigh the data).
     Not the axis's offset: its phi is 1 at every speed, so every moving sample corrects what
     a glitch left, and a leakage would cap how far it follows a changed load (at the rate
     limit of 5., to band LEAK_TIME / RATE_TIME);
  8. projection onto the box [lo, hi] around theta0 (``box``: half-width relative to the
     parameters' scale); an update that is NaN keeps the old value.
And the force the loop applies is bounded in what it means: the adapted correction
sum_k (theta_k - theta0_k) phi_k(v) is saturated at +-``band`` (N), so the adapted force stays
within the band around the trained model at every velocity, whatever the parameters (the rules
learn on the unsaturated model, so that a correction beyond the band is not wound up by them).
``reset()`` returns to theta0 and P0 = p0 I.

With projection onto a convex set containing theta*, the Lyapunov derivative of sec. 6 is not
increased by the projection, and the leakage (sigma-modification) and dead zone make e1, e2 and
theta uniformly ultimately bounded, as [C16] does for m_o_hat and k_hat (docs/guides/firmware.md).

In float32 (``dtype="float32"``) everything is the exact twin of c_runtime/fric_adapt.c: the
same float operations in the same order.
"""
from __future__ import annotations

import math
from typing import Optional, Tuple

import numpy as np

from ..codegen.cost import ADAPT_MAX_PARAMS as MAX_PARAMS  # FRIC_ADAPT_MAX_PARAMS of fric_adapt.h
from ..errors import ModelError
from ..model import FrictionModel
from ..networks import StribeckCurve
from .backstepping import AdaptiveBackstepping
from .c_abi import FLAGS as CTRL_FLAGS
from .c_abi import CFlags, Enumerator, choice
from .regressor import Regressor, adapts_offset, check_adaptable, trained_parameters, with_parameters

#: fric_adapt_rule_t.
RULE = choice("fric_adapt_rule_t",
              ("FRIC_ADAPT_RULE_RLS", 0, "rls"),
              ("FRIC_ADAPT_RULE_LYAPUNOV", 1, "lyapunov"))
#: What an update returns (and fric_adapt_t.flags holds): an OR of these. One family with the
#: controller's ``c_abi.FLAGS``: a bit means one thing in both, so that ``AdaptedController``
#: (and fric_adapt_ctrl_step) reports their OR.
FLAGS = CFlags("fric_adapt_flags_t", tuple(Enumerator(*m) for m in (
    ("FRIC_ADAPT_OK", 0, "ok"),
    ("FRIC_ADAPT_FAULT_NULL", 1, "NULL pointer"),
    ("FRIC_ADAPT_INPUT_FAULT", 2, "input fault"),
    ("FRIC_ADAPT_PROJECTED", 8, "projected"),
    ("FRIC_ADAPT_HELD", 16, "held"),
    ("FRIC_ADAPT_DEAD_ZONE", 32, "dead zone"),
    ("FRIC_ADAPT_TRACE_CLAMPED", 64, "trace clamped"),
    ("FRIC_ADAPT_CLAMPED", 128, "clamped"),
    ("FRIC_ADAPT_COVARIANCE_RESET", 256, "covariance reset"),
    ("FRIC_ADAPT_OUT_OF_RANGE", 512, "out of range"))))


#: The default band, as a fraction of the trained model's peak |F| over |v| <= v_sat.
BAND_FRACTION = 0.5
#: RLS's default memory, s: lambda = 1 - Ts / FORGET_TIME.
FORGET_TIME = 20.0
#: The default leakage's time constant, s: leak = Ts / LEAK_TIME.
LEAK_TIME = 10.0
#: Lyapunov's default e_max lets one update move the force by at most band Ts / RATE_TIME.
RATE_TIME = 100.0
#: The default v_max, in multiples of the model's v_sat (declare the axis's top speed instead).
V_MAX_FACTOR = 10.0
#: RLS's default e_max, as a fraction of the band.
RLS_ERROR_FRACTION = 0.1
#: How long ``AdaptedController`` holds the updates driven by e2 after the axis leaves the dead
#: zone |v| < v_dead, in time constants 1 / k1 of the position error (FRIC_ADAPT_SETTLE).
SETTLE = 3.0
#: The velocities, as fractions of v_max, at which the regressor's peaks are taken.
_PEAK_GRID = np.linspace(0.0, 1.0, 4001)


def _v_sat(model: FrictionModel) -> float:
    """The model's v_sat (the larger of an asymmetric model's two), m/s."""
    return max(float(c.v_sat) for c in model.directions)


def peak_force(model: FrictionModel) -> float:
    """The trained model's peak |F| over |v| <= v_sat (each way, ``_v_sat``), N."""
    speeds = np.linspace(0.0, _v_sat(model), _PEAK_GRID.size)
    return float(np.max(np.abs(model.force(np.concatenate([speeds, -speeds])))))


def parameter_scale(model: FrictionModel) -> np.ndarray:
    """The scale each parameter's box and Lyapunov gain are relative to: max |beta| (ELM) or
    max |a_k|, |c| [F1] for the curve's weights, and for B |B| or (1 / K_out) / v_sat when B
    is 0 (the viscous slope that adds the curve's force scale at v_sat); each direction's of an
    asymmetric model from its own curve; the offset's (``regressor.adapts_offset``), N, is
    sqrt(``friction_reach``) over |v| <= v_sat: its phi is 1, so the Lyapunov update moves it
    as far as it moves the friction at most, each within its own budget (``input_limit``)."""
    scales = []
    for curve in check_adaptable(model).directions:
        net = curve.aim
        weights = (np.concatenate([net.amplitudes, [net.offset]]) if isinstance(net, StribeckCurve)
                   else net.output_weights)
        w_scale = float(np.max(np.abs(weights))) or 1.0
        b_scale = abs(curve.viscous) or 1.0 / (curve.scaling.k_out * curve.v_sat)
        scales.append(np.concatenate([np.full(weights.size, w_scale), [b_scale]]))
    if adapts_offset(model):
        peaks = regressor_peaks(model, _v_sat(model))
        scales.append([math.sqrt(friction_reach(np.concatenate(scales), peaks, True))])
    return np.concatenate(scales)


def regressor_peaks(model: FrictionModel, v_top: float) -> np.ndarray:
    """max |phi_k(v)| over |v| <= v_top (float64, on a grid of 4001 speeds and v_sat each way:
    an asymmetric model's features differ between the directions)."""
    reg = Regressor(model)
    speeds = np.append(_PEAK_GRID * v_top, min(_v_sat(model), v_top))
    signs = (1.0,) if model.symmetric else (1.0, -1.0)
    return np.max(np.abs([reg(s * v)[1] for v in speeds for s in signs]), axis=0)


def friction_reach(scale, peaks, offset: bool) -> float:
    """sum_k (scale_k max |phi_k|)^2 over the friction's parameters (all but the offset, last,
    with ``offset``): how far one Lyapunov update per unit of gain and e2 moves the force."""
    n = len(peaks) - offset
    return float(np.sum((np.asarray(scale)[:n] * np.asarray(peaks)[:n]) ** 2))


def _positive(name, value, allow_zero=False):
    value = float(value)
    if not (np.isfinite(value) and (value >= 0 if allow_zero else value > 0)):
        raise ValueError(f"{name} must be {'>=' if allow_zero else '>'} 0, got {value}")
    return value


class FrictionAdapter:
    """Online adaptation of ``model``'s output parameters (module doc).

    Parameters
    ----------
    model : FrictionModel
        A symmetric ELM or grey-box model (``regressor.check_adaptable``).
    rule : {"rls", "lyapunov"}
    forgetting : float or None
        lambda of RLS, in (0, 1]. Default: 1 - Ts / ``FORGET_TIME`` (0.99995 at 1 kHz).
    p0 : float
        Initial covariance P0 = p0 diag(scale^2) (``parameter_scale``; per N^2 of error), > 0.
    trace_max : float
        The bound on the trace of P in the same units, sum_k P_kk / scale_k^2, >= p0 n.
    gamma : float
        Lyapunov gain: Gamma_theta = gamma diag(scale^2), 1/(N s m/s).
    box : float
        Half-width of the projection box, relative to ``parameter_scale``: theta0 +- box scale.
    band : float or None
        The declared force band, N: the adapted force stays within +-band of the trained
        model at every velocity. Default: ``BAND_FRACTION`` of the trained model's peak |F|
        over |v| <= v_sat.
    v_max : float or None
        No update at |v| > v_max, m/s. Default: ``V_MAX_FACTOR`` v_sat.
    e_max : float or None
        The clamp of the rule's input: N (RLS) or m/s of e2 (Lyapunov). Default: module doc.
    leak : float or None
        Leakage toward theta0 per update, in [0, 1). Default: Ts / ``LEAK_TIME`` (Lyapunov),
        0 (RLS).
    v_dead : float
        Dead zone in velocity, m/s.
    e_dead : float
        Dead zone in the error: N (RLS) or m/s of e2 (Lyapunov).
    hold_at_rest : bool
        ``AdaptedController`` holds the controller's estimates and Lyapunov's theta while the
        axis sticks and settles (True, the default: what ``readback`` exports stays the
        friction); False adapts them through every stick, as before ``FRIC_ADAPT_VERSION`` 5
        (tighter tracking where the controller's m_o_hat inflates, benchmarks/adaptation.py).
    ts, phi_n : float
        Sampling time (s) and nominal force constant (N/A) of the controller.
    dtype : {"float64", "float32"}; activation_impl : {"libm", "fast"}
        float32 makes the twin of c_runtime/fric_adapt.c with the regressor emitted so.

    Attributes
    ----------
    theta_ : ndarray
        The adapted parameters (``regressor.parameter_names``).
    P_ : ndarray
        The RLS covariance, n x n.
    flags_ : int
        What the last update returned (``FLAGS``); ``error_`` its prediction error (N) or e2.
    """

    def __init__(self, model: FrictionModel, rule: str = "lyapunov",
                 forgetting: Optional[float] = None, p0: float = 1e-3, trace_max: float = 1.0,
                 gamma: float = 2.0, box: float = 0.5, band: Optional[float] = None,
                 v_max: Optional[float] = None, e_max: Optional[float] = None,
                 leak: Optional[float] = None, v_dead: float = 0.005, e_dead: float = 0.0,
                 hold_at_rest: bool = True, ts: float = 1e-3, phi_n: float = 20.0,
                 dtype: str = "float64", activation_impl: str = "libm"):
        self.model = model
        self.rule = rule
        self.forgetting = forgetting
        self.p0 = p0
        self.trace_max = trace_max
        self.gamma = gamma
        self.box = box
        self.band = band
        self.v_max = v_max
        self.e_max = e_max
        self.leak = leak
        self.v_dead = v_dead
        self.e_dead = e_dead
        self.hold_at_rest = hold_at_rest
        self.ts = ts
        self.phi_n = phi_n
        self.dtype = dtype
        self.activation_impl = activation_impl

    _PARAMS = ("model", "rule", "forgetting", "p0", "trace_max", "gamma", "box", "band", "v_max",
               "e_max", "leak", "v_dead", "e_dead", "hold_at_rest", "ts", "phi_n", "dtype",
               "activation_impl")

    def get_params(self) -> dict:
        return {k: getattr(self, k) for k in self._PARAMS}

    def clone(self, **changes) -> "FrictionAdapter":
        return type(self)(**{**self.get_params(), **changes})

    def validate(self) -> "FrictionAdapter":
        """Check every parameter; ValueError (ModelError for the model) naming the first bad one."""
        check_adaptable(self.model)
        if self.rule not in RULE.keys:
            raise ValueError(f"rule must be one of {list(RULE.keys)}, got {self.rule!r}")
        lam = self.forgetting_factor()
        if not (0.0 < lam <= 1.0):
            raise ValueError(f"forgetting must be in (0, 1], got {self.forgetting}")
        for name in ("p0", "trace_max", "gamma", "box", "ts", "phi_n"):
            _positive(name, getattr(self, name))
        for name in ("band", "v_max", "e_max"):
            if getattr(self, name) is not None:
                _positive(name, getattr(self, name))
        for name in ("v_dead", "e_dead"):
            _positive(name, getattr(self, name), allow_zero=True)
        if not isinstance(self.hold_at_rest, (bool, np.bool_)):
            raise ValueError(f"hold_at_rest must be True or False, got {self.hold_at_rest!r}")
        if self.leak is not None and not (0.0 <= float(self.leak) < 1.0):
            raise ValueError(f"leak must be in [0, 1), got {self.leak}")
        n = len(Regressor(self.model).theta0)
        if n > MAX_PARAMS:
            own = MAX_PARAMS - adapts_offset(self.model)          # B per curve, one offset
            units = own - 1 if self.model.symmetric else own // 2 - 1
            raise ModelError(f"the model has {n} output parameters; online adaptation holds at most "
                             f"{MAX_PARAMS} (FRIC_ADAPT_MAX_PARAMS): an ELM of at most {units} "
                             f"neurons{'' if self.model.symmetric else ' per direction'} (train "
                             f"--max-neurons {units})")
        if not float(self.trace_max) >= float(self.p0) * n:
            raise ValueError(f"trace_max must be >= p0 n = {float(self.p0) * n:g}, got {self.trace_max}")
        return self

    def speed_limit(self) -> float:
        """v_max, m/s: the declared one or ``V_MAX_FACTOR`` v_sat."""
        return float(self.v_max) if self.v_max is not None else V_MAX_FACTOR * _v_sat(self.model)

    def feature_peaks(self) -> np.ndarray:
        """max |phi_k(v)| over |v| <= v_max (``regressor_peaks``)."""
        return regressor_peaks(self.model, self.speed_limit())

    def force_band(self) -> float:
        """The band, N: the declared one or ``BAND_FRACTION`` of the trained model's peak |F|
        over |v| <= v_sat (each way)."""
        if self.band is not None:
            return float(self.band)
        return BAND_FRACTION * peak_force(self.model)

    def bounds(self) -> Tuple[np.ndarray, np.ndarray]:
        """The projection box [lo, hi] (float64)."""
        theta0 = Regressor(self.model).theta0
        radius = float(self.box) * parameter_scale(self.model)
        return theta0 - radius, theta0 + radius

    def gain(self) -> float:
        """The Lyapunov gain per sample, Ts gamma / phi_N (Gamma_theta's diagonal is this times
        scale^2)."""
        return float(self.ts) * float(self.gamma) / float(self.phi_n)

    def input_limit(self) -> float:
        """e_max: the declared one, or RLS_ERROR_FRACTION of the band (N) for RLS, or for
        Lyapunov the |e2| (m/s) at which one update moves the force by at most band Ts /
        RATE_TIME anywhere through the friction's parameters, and at most as much again through
        the axis's offset (``parameter_scale``):
        |dF| <= gain e_max sum_k scale_k^2 max |phi_k|^2 (k: the friction's, ``friction_reach``)."""
        if self.e_max is not None:
            return float(self.e_max)
        band = self.force_band()
        if self.rule == "rls":
            return RLS_ERROR_FRACTION * band
        reach = self.gain() * friction_reach(parameter_scale(self.model), self.feature_peaks(),
                                             adapts_offset(self.model))
        return band * float(self.ts) / RATE_TIME / reach

    def n_leak(self) -> int:
        """How many parameters the leakage acts on, the first: all but the axis's offset (the
        C ``fric_adapt_params_t.n_leak``)."""
        return trained_parameters(self.model).size - adapts_offset(self.model)

    def forgetting_factor(self) -> float:
        """lambda: the declared one or 1 - Ts / FORGET_TIME."""
        if self.forgetting is not None:
            return float(self.forgetting)
        return 1.0 - float(self.ts) / FORGET_TIME

    def leakage(self) -> float:
        """leak: the declared one, or Ts / LEAK_TIME for Lyapunov and 0 for RLS."""
        if self.leak is not None:
            return float(self.leak)
        return float(self.ts) / LEAK_TIME if self.rule == "lyapunov" else 0.0

    def reset(self) -> "FrictionAdapter":
        """Validate, then theta = theta0, P = p0 I (the C ``fric_adapt_init``)."""
        self.validate()
        reg = self._reg = Regressor(self.model, self.dtype, self.activation_impl)
        kind = np.float64 if self.dtype == "float64" else np.float32
        f = self._f = reg._f
        lo, hi = self.bounds()
        self._theta0, self._lo, self._hi, scale = (np.asarray(a, dtype=kind) for a in
                                                   (reg.theta0, lo, hi, parameter_scale(self.model)))
        self._scale2 = scale * scale
        (self._lam, self._p0, self._trace_max, self._leak, self._v_dead, self._e_dead,
         self._gain, self._e_max, self._band, self._v_max) = (
            f(p) for p in (self.forgetting_factor(), self.p0, self.trace_max, self.leakage(), self.v_dead,
                           self.e_dead, self.gain(), self.input_limit(), self.force_band(),
                           self.speed_limit()))
        self._kind = kind
        self._leaking = np.arange(self._theta0.size) < self.n_leak()
        return self.restart()

    def restart(self) -> "FrictionAdapter":
        """theta = theta0, P = p0 I, flags and error 0 (the C ``fric_adapt_reset``)."""
        n = self._theta0.size
        self.theta_ = self._theta0.copy()
        self.P_ = np.diag(self._p0 * self._scale2).astype(self._kind)
        self.flags_, self.error_ = 0, self._f(0.0)
        return self

    # ------------------------------------------------------------------ the model, adapted

    def _predict(self, v):
        """(F(v) with theta_, phi(v)): f0 + sum_k theta_k phi_k, k ascending."""
        f0, phi = self._reg(v)
        acc = f0
        for k in range(phi.size):
            acc = acc + self.theta_[k] * phi[k]
        return acc, phi

    def force(self, v):
        """The adapted friction force at v, N: the trained model's plus the adapted correction
        saturated at +-band, f0 + sum_k theta0_k phi_k + sat(sum_k (theta_k - theta0_k) phi_k),
        k ascending (0 at a non-finite v: ``fric_adapt_force``)."""
        v = self._f(v)
        if not math.isfinite(v):
            return self._f(0.0)
        trained, phi = self._reg(v)
        delta = self._f(0.0)
        with np.errstate(over="ignore", invalid="ignore"):      # a huge finite v, as in C
            for k in range(phi.size):
                trained = trained + self._theta0[k] * phi[k]
                delta = delta + (self.theta_[k] - self._theta0[k]) * phi[k]
        band = self._band
        return trained + (band if delta > band else (-band if delta < -band else delta))

    # ------------------------------------------------------------------ the two rules

    def _gate(self, v, x, hold: bool):
        """(v, x, flags): v and the rule's input x in the working precision, and the flags of
        an update that stops here (a non-finite input, or ``hold``), else None."""
        v, x = self._f(v), self._f(x)
        if not (math.isfinite(v) and math.isfinite(x)):
            return v, x, self._done(FLAGS.value("input fault"))
        if hold:
            return v, x, self._done(FLAGS.value("held"))
        if abs(v) > self._v_max:
            return v, x, self._done(FLAGS.value("out of range"))
        return v, x, None

    def rls(self, v, force, hold: bool = False) -> int:
        """One RLS update on the friction ``force`` (N) observed at velocity ``v`` (m/s);
        returns the flags (``fric_adapt_rls``)."""
        f = self._f
        v, force, stop = self._gate(v, force, hold)
        if stop is not None:
            return stop
        pred, phi = self._predict(v)
        err = force - pred
        if not (abs(v) >= self._v_dead and abs(err) >= self._e_dead):
            return self._done(FLAGS.value("dead zone"), err)
        step, flags = self._clamp(err)
        P, lam = self.P_, self._lam
        n = phi.size
        p_phi = np.zeros(n, dtype=self._kind)
        for k in range(n):                               # P phi, each row in k order
            p_phi = p_phi + P[:, k] * phi[k]
        denom = lam
        for k in range(n):
            denom = denom + phi[k] * p_phi[k]
        if not (math.isfinite(denom) and denom > 0):      # P lost definiteness: start again
            self.P_ = np.diag(self._p0 * self._scale2).astype(self._kind)
            return self._done(FLAGS.value("covariance reset"), err)
        g = p_phi / denom
        updated = self.theta_ + g * step
        P = np.triu((P - g[:, None] * p_phi[None, :]) / lam)
        P = P + np.triu(P, 1).T                          # symmetric in float (the upper mirrored)
        trace = f(0.0)
        for k in range(n):
            trace = trace + P[k, k] / self._scale2[k]
        if not trace <= self._trace_max:                 # also NaN
            P = P * (self._trace_max / trace)
            flags |= FLAGS.value("trace clamped")
        self.P_ = P
        return self._finish(updated, flags, err)

    def lyapunov(self, v, e2, hold: bool = False) -> int:
        """One step of theta' = Gamma_theta e2 phi(v) / phi_N (forward Euler); returns the
        flags (``fric_adapt_lyapunov``)."""
        v, e2, stop = self._gate(v, e2, hold)
        if stop is not None:
            return stop
        if not (abs(v) >= self._v_dead and abs(e2) >= self._e_dead):
            return self._done(FLAGS.value("dead zone"), e2)
        error = e2
        e2, flags = self._clamp(e2)
        _, phi = self._reg(v)
        updated = self.theta_ + ((self._gain * self._scale2) * e2) * phi
        return self._finish(updated, flags, error)

    def _clamp(self, e):
        """(e clamped to +-e_max, the ``clamped`` flag or 0)."""
        if e > self._e_max:
            return self._e_max, FLAGS.value("clamped")
        if e < -self._e_max:
            return -self._e_max, FLAGS.value("clamped")
        return e, 0

    def _finish(self, updated, flags, err) -> int:
        """Leakage toward theta0, then projection onto [lo, hi] (NaN keeps the old value)."""
        updated = np.where(self._leaking, updated - self._leak * (updated - self._theta0), updated)
        with np.errstate(invalid="ignore"):
            nan = np.isnan(updated)
            below, above = updated < self._lo, updated > self._hi
        out = np.where(nan, self.theta_, np.where(below, self._lo, np.where(above, self._hi, updated)))
        if np.any(nan | below | above):
            flags |= FLAGS.value("projected")
        self.theta_ = out.astype(self._kind)
        return self._done(flags, err)

    def _done(self, flags: int, err=None) -> int:
        self.flags_ = flags
        if err is not None:
            self.error_ = err
        return flags

    @property
    def adapted_model(self) -> FrictionModel:
        """The model with the adapted parameters (``regressor.with_parameters``)."""
        return with_parameters(self.model, np.asarray(self.theta_, dtype=float))


class AdaptedController:
    """The backstepping controller of section 6 compensating with an adapted friction model:
    every sample (the C ``fric_adapt_ctrl_step``)

    1. the force F(u) of the adapted model at u = v or v_d (``controller.friction_input``);
    2. the controller's step with that force (``AdaptiveBackstepping.step_with_force``);
    3. RLS: update on the friction observed over the last sample (module doc, with the m_o_hat
       of this step), held unless this step and the last were fault-free and unsaturated (a
       glitch of this sample's v is in the observation);
       Lyapunov: update with the step's e2, held unless this step was fault-free and
       unsaturated.

    The updates driven by e2, the controller's m_o_hat and k_hat [C14] and Lyapunov's theta,
    are held (``FrictionAdapter.hold_at_rest``, the default) while the axis is in the dead zone
    |v| < v_dead and for ``SETTLE`` / k1 seconds after it leaves it (the controller keeps the
    estimates it had before the step, without ``projected``): while the axis sticks at a
    reversal the reference runs on, and the velocity error of the stick and of the catch-up
    after it is no model's. Adapted on, it raised m_o_hat to 2.5 m_o and k_hat F 4.4 % above
    the friction on the built-in axis (benchmarks/adaptation_readback.py).

    ``controller`` and ``adapter`` are reset with this; their ``dtype`` must agree (float32:
    the twin of the C).
    """

    def __init__(self, controller: AdaptiveBackstepping, adapter: FrictionAdapter):
        self.controller = controller
        self.adapter = adapter

    @property
    def ts(self) -> float:
        return self.controller.ts

    def reset(self) -> "AdaptedController":
        if self.controller.dtype != self.adapter.dtype:
            raise ValueError(f"controller and adapter dtypes differ: {self.controller.dtype} and "
                             f"{self.adapter.dtype}")
        self.controller.reset()
        self.adapter.reset()
        f = self._f = self.controller._f
        self._v_prev, self._i_prev, self._held = f(0.0), f(0.0), True
        self._settle = f(0.0)
        return self

    def step(self, x, v, xd, xd_dot, xd_ddot):
        c, a, f = self.controller, self.adapter, self._f
        x, v, xd, xd_dot, xd_ddot = (f(q) for q in (x, v, xd, xd_dot, xd_ddot))
        resting = not abs(v) >= a._v_dead                   # also a non-finite v
        if resting:
            self._settle = f(SETTLE) / c._k1
        elif self._settle > 0:
            self._settle = self._settle - c._ts
        settling = not resting and self._settle > 0
        if not a.hold_at_rest:                              # the estimates adapt through sticks
            resting = settling = False
        estimates = list(c.a_)
        u = c.friction_velocity(x, v, xd, xd_dot)
        force = a.force(u)
        i = c.step_with_force(x, v, xd, xd_dot, xd_ddot, force)
        ok = c.flags_ & (CTRL_FLAGS.value("saturated") | CTRL_FLAGS.value("input fault")) == 0
        if resting or settling:                             # the stick's error: A as it was
            c.a_ = estimates
            c.flags_ &= ~CTRL_FLAGS.value("projected")
        if a.rule == "rls" and (self._held or not ok):   # the observation spans a glitch
            a.rls(v, f(0.0), hold=True)
        elif a.rule == "rls":
            m_o_hat = c.a_[0]
            with np.errstate(all="ignore"):
                accel = (v - self._v_prev) / c._ts
                observed = c._phi_n * (self._i_prev - m_o_hat * accel)
                v_mid = f(0.5) * (v + self._v_prev)
            a.rls(v_mid, observed, hold=False)
        else:
            a.lyapunov(v, c.e2_, hold=not ok or settling)
        self._v_prev, self._i_prev, self._held = v, i, not ok
        return i

    @property
    def flags_(self) -> int:
        """The last step's flags: the controller's OR the update's (fric_adapt_ctrl_step's)."""
        return int(self.controller.flags_) | int(self.adapter.flags_)

    @property
    def adaptive_parameters(self) -> Tuple[float, float]:
        return self.controller.adaptive_parameters


def adapted(model: FrictionModel, rule: str = "lyapunov", controller: Optional[AdaptiveBackstepping] = None,
            dtype: str = "float64", activation_impl: str = "libm", **adapter) -> AdaptedController:
    """An ``AdaptedController`` for ``model``: ``controller`` (default ``AdaptiveBackstepping()``)
    in ``dtype``, and a ``FrictionAdapter`` with its ts and phi_n and the options ``adapter``."""
    ctrl = (controller or AdaptiveBackstepping()).clone(dtype=dtype, compensation=None)
    adapt = FrictionAdapter(model, rule, ts=ctrl.ts, phi_n=ctrl.phi_n, dtype=dtype,
                            activation_impl=activation_impl, **adapter)
    return AdaptedController(ctrl, adapt)
