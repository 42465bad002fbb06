"""Adaptive backstepping position control with friction compensation (section 6).

With e1 = x_d - x, the virtual control v_d = x_d' + k1 e1 [C3], e2 = v_d - v [C5] and
v_d' = x_d'' + k1 (-k1 e1 + e2) [C7], the current is

    i = D_hat + k2 e2 + e1,   D_hat = A_hat^T xi                          [C11], [C9]
    A_hat = [m_o_hat, k_hat],  xi = [v_d', F_Fm(v) / phi_N]               [C10]

where F_Fm is the friction model used for compensation and phi_N the nominal force constant.
D = m_o v_d' + F_friction / phi (m_o = m / phi) is what the current must supply; the paper's
[C8] prints a minus sign before the friction term, but [C1] (m v' = phi i - F) gives the
plus sign used here, so k_hat tends to phi_N / phi > 0 when F_Fm matches the true friction.
The adaptation laws [C14] (printed as (12a,b,c), cited as (31a-c)) are

    (a) A' = e2 Gamma xi
    (b) A' = e2 Gamma xi - delta Gamma A
    (c) A' = e2 Gamma xi - delta sqrt(e1^2 + e2^2) Gamma A,

integrated with a forward Euler step of the sampling time Ts, as firmware does. The Lyapunov
function [C13] proves e1, e2 uniformly ultimately bounded for k1 > 0, k2 > 1/2 [C16].

The contract of fric_ctrl.h holds here too: each estimate is projected onto its interval
(``a_min``, ``a_max``); adaptation is frozen while the demand saturates at +-i_max; a
non-finite input (or a NaN demand from huge ones) gives 0 A and leaves the estimates as they
were. ``flags_`` holds what the C step returns (``c_abi.FLAGS``).

The controller computes in float64, or in float32 (``dtype="float32"``), then it is the exact
Python twin of ``fric_ctrl_step`` in ``c_runtime/fric_ctrl.c``: the same operations in the same
order, each rounded to float.
"""
from __future__ import annotations

import math
from typing import Callable, Optional, Tuple

import numpy as np

from .c_abi import FLAGS, FRICTION_INPUT, LAW
from .gamma import gamma_matrix


def _pair(name: str, value) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if a.shape != (2,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be 2 finite numbers [m_o_hat, k_hat], got {value!r}")
    return a


def _check(name: str, value, low: float, strict: bool = True) -> float:
    value = float(value)
    ok = np.isfinite(value) and (value > low if strict else value >= low)
    if not ok:
        raise ValueError(f"{name} must be {'>' if strict else '>='} {low:g}, got {value}")
    return value


def _project(a, updated, lo, hi):
    """(the updated estimate projected onto [lo, hi], whether it was moved): a NaN
    (inf - inf) keeps ``a`` (``fric_ctrl_project``)."""
    if math.isnan(updated):
        return a, True
    if updated < lo:
        return lo, True
    if updated > hi:
        return hi, True
    return updated, False


#: The controller's sample time (s) unless told: the paper's 1 kHz.
DEFAULT_TS = 1e-3


class AdaptiveBackstepping:
    r"""The adaptive backstepping position controller of section 6 ([C3]-[C14]), sampled at ``ts``.

    Defaults are tuned for ``control.default_axis()`` (2 kg, ~20 N/A, 10 A): with k2 = 40 the
    velocity loop phi k2 / m is ~360 rad/s, so Ts = 1 ms leaves a wide margin (stable up to
    Ts ~ 4 ms); Gamma and delta adapt k_hat within a few seconds.

    Parameters
    ----------
    compensation : callable, optional
        F_Fm(v) in N, e.g. a ``FrictionModel`` or the true ``MultisourceFriction`` ("exact"
        compensation); None: xi_2 = 0, no friction model.
    law : {"a", "b", "c"}
        The adaptation law of [C14] (the paper used "c").
    k1 : float
        Gain of the virtual control v_d = xd' + k1 e1, [C3] (1/s), > 0.
    k2 : float
        Gain of the velocity error in [C11] (A s/m), > 1/2 [C16].
    gamma : float or array_like
        Gamma of [C13]: scalar, diagonal or 2x2 symmetric positive definite.
    delta : float
        Leakage of laws (b) and (c), >= 0 (unused by law a).
    ts : float
        Sampling time (s).
    phi_n : float
        Nominal force constant phi_N (N/A).
    i_max : float
        Current limit (A).
    a0 : tuple of float
        Initial [m_o_hat, k_hat] (m_o in kg A/N, k dimensionless).
    dtype : {"float64", "float32"}
        "float32" is the twin of the C controller.
    friction_input : {"v", "vd", "reference"}
        Evaluate F_Fm at the measured velocity [C10], at v_d [C3], which keeps
        compensating while the axis sticks at a reversal, or at the reference velocity x_d',
        free of the sensor's noise (a dynamic model's stepper does not hunt at rest).
    a_min, a_max : tuple of float
        The intervals [m_o_min, k_min], [m_o_max, k_max] the estimates are projected onto
        (default: m_o_hat in [0.01, 1], k_hat in [0, 10]); a_min < a_max, a0 within.

    Attributes
    ----------
    a_ : ndarray
        The adaptive parameters [m_o_hat, k_hat] (after ``reset()``).
    e1_, e2_, i_, flags_
        After each ``step``: position error (m), velocity error (m/s), current (A) and flags (as
        the C's fric_ctrl_t).

    Notes
    -----
    The control law and the adaptation law (c):

    .. math::

        i = \hat A^T \xi + k_2 e_2 + e_1, \quad \xi = [\dot v_d,\ F_{Fm}(v) / \varphi_N], \quad
        \dot{\hat A} = e_2 \Gamma \xi - \delta \sqrt{e_1^2 + e_2^2}\, \Gamma \hat A

    Examples
    --------
    >>> import fricgen
    >>> ctrl = fricgen.AdaptiveBackstepping(compensation=fricgen.preset("paper3"), ts=1e-3).reset()
    >>> current = ctrl.step(0.0, 0.0, 1e-3, 0.0, 0.0)     # 1 mm behind: push forward
    >>> bool(0 < current <= 10.0)
    True
    """

    def __init__(self, compensation: Optional[Callable] = None, law: str = "c", k1: float = 80.0,
                 k2: float = 40.0, gamma=(1.0, 20.0), delta: float = 0.005, ts: float = DEFAULT_TS,
                 phi_n: float = 20.0, i_max: float = 10.0, a0: Tuple[float, float] = (0.1, 1.0),
                 dtype: str = "float64", friction_input: str = "v",
                 a_min: Tuple[float, float] = (0.01, 0.0), a_max: Tuple[float, float] = (1.0, 10.0)):
        self.compensation = compensation
        self.law = law
        self.k1 = k1
        self.k2 = k2
        self.gamma = gamma
        self.delta = delta
        self.ts = ts
        self.phi_n = phi_n
        self.i_max = i_max
        self.a0 = a0
        self.dtype = dtype
        self.friction_input = friction_input
        self.a_min = a_min
        self.a_max = a_max

    _PARAMS = ("compensation", "law", "k1", "k2", "gamma", "delta", "ts", "phi_n", "i_max", "a0",
               "dtype", "friction_input", "a_min", "a_max")

    def get_params(self) -> dict:
        """The constructor parameters, by name."""
        return {k: getattr(self, k) for k in self._PARAMS}

    def clone(self, **changes) -> "AdaptiveBackstepping":
        """A new, unreset controller with the same parameters except ``changes``."""
        return type(self)(**{**self.get_params(), **changes})

    def validate(self) -> "AdaptiveBackstepping":
        """Check every parameter; raise ValueError naming the first bad one."""
        if self.law not in LAW.keys:
            raise ValueError(f"law must be one of {list(LAW.keys)}, got {self.law!r}")
        _check("k1", self.k1, 0.0)
        _check("k2", self.k2, 0.5)
        gamma_matrix(self.gamma)
        _check("delta", self.delta, 0.0, strict=False)
        _check("ts", self.ts, 0.0)
        _check("phi_n", self.phi_n, 0.0)
        _check("i_max", self.i_max, 0.0)
        a0 = _pair("a0", self.a0)
        lo, hi = _pair("a_min", self.a_min), _pair("a_max", self.a_max)
        if not np.all(lo < hi):
            raise ValueError(f"a_min must be < a_max, got {self.a_min!r} and {self.a_max!r}")
        if not np.all((lo <= a0) & (a0 <= hi)):
            raise ValueError(f"a0 must lie within [a_min, a_max] = [{self.a_min!r}, {self.a_max!r}], "
                             f"got {self.a0!r}")
        if self.compensation is not None and not callable(self.compensation):
            raise ValueError(f"compensation must be None or a callable F(v), "
                             f"got {type(self.compensation).__name__}")
        dt = getattr(self.compensation, "dt", None)           # a stepper's sample time
        if dt is not None and not math.isclose(float(dt), float(self.ts), rel_tol=1e-9):
            raise ValueError(f"the compensation steps at dt = {dt:g} s, the controller samples at "
                             f"ts = {self.ts:g} s: make the stepper at the controller's ts")
        if self.friction_input not in FRICTION_INPUT.keys:
            raise ValueError(f"friction_input must be one of {list(FRICTION_INPUT.keys)}, "
                             f"got {self.friction_input!r}")
        if self.dtype not in ("float64", "float32"):
            raise ValueError(f"dtype must be 'float64' or 'float32', got {self.dtype!r}")
        return self

    def reset(self) -> "AdaptiveBackstepping":
        """Validate, then set the adaptive parameters to ``a0`` (the C ``fric_ctrl_init``)."""
        self.validate()
        f = float if self.dtype == "float64" else np.float32
        self._f = f
        self._sqrt = math.sqrt if f is float else np.sqrt
        g = gamma_matrix(self.gamma)
        self._g = tuple(f(x) for x in g.ravel())
        self._k1, self._k2, self._delta, self._ts, self._phi_n, self._i_max = (
            f(p) for p in (self.k1, self.k2, self.delta, self.ts, self.phi_n, self.i_max))
        self._law = self.law
        self._bounds = tuple((f(lo), f(hi)) for lo, hi in zip(self.a_min, self.a_max))
        self.a_ = [f(a) for a in self.a0]
        self.e1_ = self.e2_ = self.i_ = f(0.0)
        self.flags_ = 0
        if hasattr(self.compensation, "reset"):    # a stepper (``FrictionModel.stepper``)
            self.compensation.reset()
        return self

    def friction_force(self, v) -> float:
        """F_Fm(v) of [C10] in the controller's precision (0 without compensation)."""
        if self.compensation is None:
            return self._f(0.0)
        return self._f(np.asarray(self.compensation(v)).reshape(()))

    @staticmethod
    def _f(value):
        """The controller's float type, which ``reset`` sets; before it, every step stops here."""
        raise RuntimeError("AdaptiveBackstepping: call reset() before the first step (it checks "
                           "the parameters and sets the estimates to a0)")

    def step(self, x, v, xd, xd_dot, xd_ddot) -> float:
        """One sample: measured x, v and the reference; returns the current i, updates A_hat."""
        return self.step_with_force(x, v, xd, xd_dot, xd_ddot,
                                    self.compensation_force(x, v, xd, xd_dot))

    def compensation_force(self, x, v, xd, xd_dot):
        """F_Fm at ``friction_velocity`` in the controller's precision, or 0 where that velocity
        is not finite (the C ``fric_ctrl_step_fn`` does not call the model there)."""
        f = self._f
        u = self.friction_velocity(f(x), f(v), f(xd), f(xd_dot))
        return self.friction_force(u) if math.isfinite(u) else self._f(0.0)

    def friction_velocity(self, x, v, xd, xd_dot):
        """Where F_Fm is evaluated: the measured v [C10], v_d = x_d' + k1 (x_d - x) with
        ``friction_input="vd"`` (compensation that keeps acting while the axis sticks), or x_d'
        with ``"reference"``."""
        if self.friction_input == "vd":
            return xd_dot + self._k1 * (xd - x)
        return xd_dot if self.friction_input == "reference" else v

    def step_with_force(self, x, v, xd, xd_dot, xd_ddot, friction) -> float:
        """``step`` with the compensation force F_Fm(v) given (the C ``fric_ctrl_step``):
        returns the current, ``flags_`` says what happened (see the module doc)."""
        f = self._f
        x, v, xd, xd_dot, xd_ddot, friction = (f(a) for a in (x, v, xd, xd_dot, xd_ddot, friction))
        if not all(math.isfinite(a) for a in (x, v, xd, xd_dot, xd_ddot, friction)):
            return self._fault()
        k1, k2 = self._k1, self._k2
        g00, g01, g10, g11 = self._g
        a0, a1 = self.a_
        e1 = xd - x                                         # tracking error
        vd = xd_dot + k1 * e1                               # [C3]
        e2 = vd - v                                         # [C5]
        vd_dot = xd_ddot + k1 * (e2 - k1 * e1)              # [C7]
        xi0 = vd_dot                                        # [C10]
        xi1 = friction / self._phi_n
        d_hat = a0 * xi0 + a1 * xi1                         # [C9]
        demand = d_hat + k2 * e2 + e1                       # [C11]
        if math.isnan(demand):                              # inf - inf from huge finite inputs
            return self._fault()
        self.e1_, self.e2_ = e1, e2
        if not demand <= self._i_max:
            self.flags_, self.i_ = FLAGS.value("saturated"), self._i_max
            return self.i_
        if not demand >= -self._i_max:
            self.flags_, self.i_ = FLAGS.value("saturated"), -self._i_max
            return self.i_
        if self._law == "a":
            sigma = f(0.0)
        elif self._law == "b":
            sigma = self._delta
        else:
            sigma = self._delta * self._sqrt(e1 * e1 + e2 * e2)
        g_xi0 = g00 * xi0 + g01 * xi1                       # [C14]: Gamma xi, Gamma A
        g_xi1 = g10 * xi0 + g11 * xi1
        g_a0 = g00 * a0 + g01 * a1
        g_a1 = g10 * a0 + g11 * a1
        updated = (a0 + self._ts * (e2 * g_xi0 - sigma * g_a0),
                   a1 + self._ts * (e2 * g_xi1 - sigma * g_a1))
        projected = [_project(a, new, lo, hi) for a, new, (lo, hi) in zip(self.a_, updated, self._bounds)]
        self.a_ = [a for a, _ in projected]
        self.flags_ = FLAGS.value("projected") if any(moved for _, moved in projected) else 0
        self.i_ = demand
        return demand

    def _fault(self):
        """An input fault: 0 A, estimates and errors left as they were."""
        self.flags_, self.i_ = FLAGS.value("input fault"), self._f(0.0)
        return self.i_

    @property
    def adaptive_parameters(self) -> Tuple[float, float]:
        """(m_o_hat, k_hat) as floats."""
        return float(self.a_[0]), float(self.a_[1])
