"""The textbook friction laws of drive manuals, fitted by least squares in newtons.

Per direction of motion (or once for both, the sweep folded) the magnitude of the friction is

    F(|v|) = F_c + F_v |v|                                  (Coulomb + viscous)
    F(|v|) = F_c + (F_s - F_c) g(|v| / v_s) + F_v |v|       (+ one Stribeck term, [F1] with S = 1)

with g of [F2] (Gaussian or exponential, whichever fits better). F_c, F_s and F_v are fitted by
bounded linear least squares (all >= 0: friction opposes the motion and does not fall with the
speed beyond the Stribeck drop), v_s by a grid and a bounded scalar search around its best point.
Points may carry weights (a sweep's ``F_std`` or ``n``). Standard errors come from the Jacobian at
the optimum, the residual variance estimated from the fit (infinite where the data do not
determine a parameter).

A fitted law is a ``Direction`` of [F3] like any other curve: its AIM is a ``StribeckCurve`` in
the coordinates of [F9] with v_sat the fastest speed of the data, and B = F_v carried beyond it.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Optional, Tuple

import numpy as np
from scipy.optimize import lsq_linear, minimize_scalar

from ..friction import SHAPES
from ..model import Direction, Scaling
from ..networks import StribeckCurve
from .base import Estimator

#: The shapes g of [F2] tried for the Stribeck term.
STRIBECK_SHAPES = ("gauss", "exponential")
#: Points of the grid of Stribeck velocities, from the slowest speed (below it the drop's height
#: is an extrapolation the data do not hold) to VS_FASTEST of the fastest: the drop is over
#: (g < 1e-4 at three v_s) within the data, as v_sat = 3 vs_max of section 2 has it.
VS_GRID = 24
VS_FASTEST = 1.0 / 3.0
#: The Stribeck drop must exceed this many of its standard errors for the data to show it.
DROP_SE = 2.0
#: Parameters of a curve without and with the Stribeck term.
PARAMETERS = {False: 2, True: 4}
#: Fewest points per curve for the law to be a candidate: one more than its parameters, so
#: that a point is left to judge it.
MIN_POINTS = {stribeck: n + 1 for stribeck, n in PARAMETERS.items()}


@dataclass(frozen=True)
class LawFit:
    """One fitted textbook curve: F(|v|) = F_c + (F_s - F_c) g(|v| / v_s) + F_v |v| (``stribeck``)
    or F_c + F_v |v|, with standard errors (same keys) and the data's fastest speed; ``drop_se``:
    the standard error of the drop F_s - F_c (infinite without the Stribeck term)."""

    coulomb: float
    viscous: float
    static: Optional[float]
    v_s: Optional[float]
    shape: Optional[str]
    standard_errors: Dict[str, float]
    fastest: float
    rms: float
    drop_se: float = float("inf")

    @property
    def drop_determined(self) -> bool:
        """Whether the data tell the Stribeck drop F_s - F_c from 0: by more than DROP_SE of
        its standard errors (False without the Stribeck term). A rise (F_s < F_c) counts: the
        joints of real arms rub less at their slowest speeds, and their held-out errors rose by
        up to 11 % where it was left out."""
        return self.stribeck and abs(self.static - self.coulomb) > DROP_SE * self.drop_se

    @property
    def stribeck(self) -> bool:
        return self.static is not None

    def magnitude(self, speed) -> np.ndarray:
        s = np.abs(np.asarray(speed, dtype=float))
        f = self.coulomb + self.viscous * s
        if self.stribeck:
            f = f + (self.static - self.coulomb) * SHAPES[self.shape](s, self.v_s)
        return f

    def direction(self) -> Direction:
        """The curve as a ``Direction`` of [F3]: AIM = K_out (F_c + (F_s - F_c) g) on
        x = |v| / v_sat, B = F_v (the same force on [0, v_sat], the law's line beyond)."""
        v_sat = self.fastest
        speeds = np.linspace(0.0, v_sat, 65)
        top = float(np.max(self.magnitude(speeds) - self.viscous * speeds))
        k_out = 1.0 / top if top > 0 else 1.0
        if self.stribeck:
            aim = StribeckCurve(self.shape, k_out * self.coulomb, [k_out * (self.static - self.coulomb)],
                                [self.v_s / v_sat])
        else:                                    # no drop: amplitude 0 (one exact zero term)
            aim = StribeckCurve("exponential", k_out * self.coulomb, [0.0], [1.0])
        return Direction(aim=aim, scaling=Scaling(k_in=1.0 / v_sat, k_out=k_out),
                         viscous=self.viscous, v_sat=v_sat)

    def describe(self, units) -> str:
        """One line of the law, each parameter with its standard error, in ``units``
        (``fricgen.units``); "not determined" where the error exceeds the value tenfold; "at
        its bound" where the fit holds it at 0 (the data want it below: a static friction 0 is
        no measurement of none)."""
        def est(name, symbol, unit):
            value, se = getattr(self, name), self.standard_errors[name]
            if value == 0:
                return f"{symbol} = 0 {unit} (at its bound: the data want it below 0)"
            if not se <= 10 * abs(value) and not (value == 0 and se < np.inf):
                return f"{symbol} = {value:.5g} {unit} (not determined by the data)"
            return f"{symbol} = {value:.5g} +- {se:.2g} {unit}"
        parts = [est("coulomb", "F_c", units.force), est("viscous", "F_v", units.viscous)]
        if self.stribeck:
            parts += [est("static", "F_s", units.force), est("v_s", "v_s", units.speed) + f" ({self.shape})"]
        return ", ".join(parts)


def _solve(columns: np.ndarray, force: np.ndarray, root_w: np.ndarray):
    """Non-negative weighted least squares: coefficients and weighted residual sum of squares."""
    a = columns * root_w[:, None]
    b = force * root_w
    sol = lsq_linear(a, b, bounds=(0.0, np.inf), method="bvls")
    r = a @ sol.x - b
    return sol.x, float(r @ r)


def _grid_rss(speed, force, root_w, shape: str, grid: np.ndarray) -> np.ndarray:
    """The weighted residual sum of squares of the Stribeck law at each v_s of ``grid``, as
    ``_solve`` gives it: the unconstrained least squares of all grid points at once (the
    non-negative solution wherever its coefficients are all >= 0), ``_solve`` at the others."""
    g = SHAPES[shape](speed[None, :], grid[:, None])
    a = np.stack([1.0 - g, g, np.broadcast_to(speed, g.shape)], axis=2) * root_w[None, :, None]
    b = force * root_w
    at = a.transpose(0, 2, 1)
    try:
        coef = np.linalg.solve(at @ a, (at @ b)[:, :, None])[:, :, 0]
    except np.linalg.LinAlgError:
        coef = np.full((grid.size, 3), -1.0)
    r = np.einsum("knj,kj->kn", a, coef) - b
    rss = np.einsum("kn,kn->k", r, r)
    for k in np.flatnonzero(~(np.all(coef >= 0, axis=1) & np.isfinite(rss))):
        rss[k] = _solve(_design(speed, grid[k], shape), force, root_w)[1]
    return rss


def _design(speed, v_s=None, shape=None) -> np.ndarray:
    if v_s is None:
        return np.column_stack([np.ones_like(speed), speed])
    g = SHAPES[shape](speed, v_s)
    return np.column_stack([1.0 - g, g, speed])


def _covariance(speed, weight, params: Dict[str, float], shape, rss: float) -> np.ndarray:
    """The covariance of ``params`` from the weighted Jacobian (central differences) and the
    residual variance rss / (n - p); None where the data do not determine it (no residual
    degree of freedom, a singular normal matrix)."""
    names = list(params)
    def magnitude(p):
        return LawFit(p["coulomb"], p["viscous"], p.get("static"), p.get("v_s"), shape, {}, 0.0,
                      0.0).magnitude(speed)
    jac = np.empty((speed.size, len(names)))
    for j, k in enumerate(names):
        h = 1e-6 * max(abs(params[k]), 1e-9)
        up, down = {**params, k: params[k] + h}, {**params, k: params[k] - h}
        jac[:, j] = (magnitude(up) - magnitude(down)) / (2 * h)
    return _least_squares_covariance(jac, weight, rss)


def _least_squares_covariance(jac: np.ndarray, weight: np.ndarray, rss: float) -> Optional[np.ndarray]:
    """rss / (n - p) (J' W J)^-1 of a weighted least squares with Jacobian ``jac`` (n x p);
    None where the data do not determine it (no residual degree of freedom, a singular normal
    matrix)."""
    dof = jac.shape[0] - jac.shape[1]
    if dof <= 0:
        return None
    jw = jac * np.sqrt(weight)[:, None]
    try:
        return rss / dof * np.linalg.inv(jw.T @ jw)
    except np.linalg.LinAlgError:
        return None


def _error(variance: float) -> float:
    """A standard error from a variance: infinite where it is not finite or < 0 (ill-posed)."""
    return float(np.sqrt(variance)) if np.isfinite(variance) and variance >= 0 else float("inf")


def _standard_errors(speed, weight, params: Dict[str, float], shape, rss: float):
    """Standard errors of ``params`` (``_covariance``; infinite where the data do not determine
    one) and, where ``params`` hold "static", the standard error of the drop F_s - F_c
    (var F_s + var F_c - 2 cov)."""
    names = list(params)
    cov = _covariance(speed, weight, params, shape, rss)
    if cov is None:
        return {k: float("inf") for k in names}, float("inf")
    se = {k: _error(cov[j, j]) for j, k in enumerate(names)}
    if "static" not in params:
        return se, float("inf")
    c, s = names.index("coulomb"), names.index("static")
    return se, _error(cov[s, s] + cov[c, c] - 2.0 * cov[s, c])


def fit_law(speed, force, weight=None, stribeck: bool = False,
            pinned: Optional[Tuple[str, float]] = None, errors: bool = True) -> LawFit:
    """The textbook curve fitted to (|v|, F) points (``weight``: relative weights, default 1).
    ``pinned``: the Stribeck term's (shape, v_s) kept from an earlier fit, only F_c, F_s and
    F_v refitted. ``errors`` False: no standard errors (a cross-validation fold's, which only
    predicts).

    ``ValueError`` with fewer points than parameters (``PARAMETERS``)."""
    speed = np.abs(np.asarray(speed, dtype=float))
    force = np.asarray(force, dtype=float)
    weight = np.ones_like(speed) if weight is None else np.asarray(weight, dtype=float)
    if speed.size < PARAMETERS[stribeck]:
        raise ValueError(f"{speed.size} points, the law needs {PARAMETERS[stribeck]}")
    weight = weight / np.mean(weight)
    root_w = np.sqrt(weight)
    fastest = float(speed.max())
    if not stribeck:
        (fc, fv), rss = _solve(_design(speed), force, root_w)
        se = _standard_errors(speed, weight, {"coulomb": fc, "viscous": fv}, None, rss)[0] \
            if errors else {}
        return LawFit(float(fc), float(fv), None, None, None, se, fastest,
                      float(np.sqrt(rss / speed.size)))
    slowest = float(speed[speed > 0].min()) if np.any(speed > 0) else fastest
    grid = np.geomspace(slowest, max(VS_FASTEST * fastest, 1.01 * slowest), VS_GRID)
    best = None
    if pinned is not None:
        shape, vs = pinned
        coef, rss = _solve(_design(speed, vs, shape), force, root_w)
        best = (rss, shape, vs, coef)
    for shape in STRIBECK_SHAPES if pinned is None else ():
        scores = _grid_rss(speed, force, root_w, shape, grid)
        k = int(np.argmin(scores))
        lo, hi = np.log(grid[max(k - 1, 0)]), np.log(grid[min(k + 1, grid.size - 1)])
        found = minimize_scalar(lambda u: _solve(_design(speed, np.exp(u), shape), force, root_w)[1],
                                bounds=(lo, hi), method="bounded", options={"xatol": 1e-3})
        vs = float(np.exp(found.x)) if found.fun <= scores[k] else float(grid[k])
        coef, rss = _solve(_design(speed, vs, shape), force, root_w)
        if best is None or rss < best[0]:
            best = (rss, shape, vs, coef)
    rss, shape, vs, (fc, fs, fv) = best
    se, drop = _standard_errors(speed, weight, {"coulomb": fc, "viscous": fv, "static": fs,
                                                "v_s": vs}, shape, rss) if errors else ({}, np.inf)
    return LawFit(float(fc), float(fv), float(fs), vs, shape, se, fastest,
                  float(np.sqrt(rss / speed.size)), drop)


def fit_shared_viscous(curves, errors: bool = True) -> Tuple[LawFit, LawFit]:
    """Coulomb + viscous with F_c per direction and one F_v: ``curves`` the (|v|, F, weight)
    points of v > 0 and of v < 0; the two ``LawFit``s, F_v and its standard error shared. The
    law of a sweep with a direction of one or two points, too few for its own F_v: a Coulomb
    level of each direction, the slope from all points.

    ``ValueError`` with fewer than 3 points or a direction without one."""
    (sp, fp, wp), (sn, fn, wn) = curves
    if sp.size < 1 or sn.size < 1 or sp.size + sn.size < 3:
        raise ValueError(f"{sp.size} and {sn.size} points, the law needs one a side and 3 in all")
    speed = np.abs(np.concatenate([sp, sn]))
    weight = np.concatenate([wp, wn]).astype(float)
    weight = weight / np.mean(weight)
    side = np.arange(speed.size) < sp.size
    design = np.column_stack([side * 1.0, ~side * 1.0, speed])
    coef, rss = _solve(design, np.concatenate([fp, fn]), np.sqrt(weight))
    cov = _least_squares_covariance(design, weight, rss) if errors else None
    se = [float("inf")] * 3 if cov is None else [_error(c) for c in np.diag(cov)]
    return tuple(LawFit(float(coef[k]), float(coef[2]), None, None, None,
                        {"coulomb": se[k], "viscous": se[2]} if errors else {},
                        float(np.abs(points).max()), float(np.sqrt(rss / speed.size)))
                 for k, points in ((0, sp), (1, sn)))


class TextbookRegressor(Estimator):
    """A fitted textbook curve as an estimator of [F9] (``law``: its ``LawFit``), so that the
    report and the training record treat it as any other curve. ``fit`` is not how it is made:
    ``from_law`` wraps a law fitted in newtons."""

    activation = "stribeck"
    scheme = "textbook"

    def __init__(self, stribeck: bool = False):
        self.stribeck = stribeck

    @classmethod
    def from_law(cls, law: LawFit, curve: Direction) -> "TextbookRegressor":
        est = cls(stribeck=law.stribeck)
        est.law_ = law
        est.network_ = curve.aim
        return est

    #: The held-out RMS error of the choice (normalized as t; ``fit.law_choice``).
    cv_rmse_ = float("nan")

    def fit(self, x, t):
        raise TypeError("TextbookRegressor is fitted in newtons by fit_law, not on [F9] data")

    def predict(self, x) -> np.ndarray:
        return self.network_(np.asarray(x, dtype=float))

    @property
    def n_hidden(self) -> int:
        return self.network_.n_sources
