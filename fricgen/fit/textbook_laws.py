"""The textbook laws as candidates of the default's choice (``fit.law_choice``): Coulomb +
viscous and Coulomb + viscous + one Stribeck term (``fit.textbook``), one curve for both
directions or one per direction, and for a sweep with a direction of 1 or 2 points each
direction's Coulomb level with one viscous slope (or, where those points reject it, their own
line); their fits to a sweep's points as a model's curves, and the weights of those points from
their spread.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional, Tuple

import numpy as np
from scipy import stats

from ..data.sweep import Sweep
from ..data.training_set import Dataset
from .directions import DirectionsFit, FittedDirection
from .textbook import MIN_POINTS, PARAMETERS, LawFit, TextbookRegressor, fit_law, fit_shared_viscous


def signed_force(v: np.ndarray, magnitude: Callable, negative: Optional[Callable] = None) -> np.ndarray:
    """The signed force of curves of |v|: one for both directions, or one per direction."""
    speed, sign = np.abs(v), np.sign(v)
    if negative is None:
        return sign * magnitude(speed)
    return np.where(sign > 0, magnitude(speed), -negative(speed))


def curve_points(sweep: Sweep, weight: np.ndarray, asymmetric: bool):
    """Each curve's points as (|v|, the force's magnitude sgn(v) f, weight): the moving rows
    folded for one curve, or those of v > 0 and of v < 0 for two (``Sweep.folded``,
    ``Sweep.direction``)."""
    signs = np.sign(sweep.v)
    masks = (signs == 1, signs == -1) if asymmetric else (signs != 0,)
    return [(np.abs(sweep.v[m]), (signs * sweep.f)[m], weight[m]) for m in masks]


@dataclass(frozen=True)
class TextbookLaw:
    """A textbook candidate: with or without the Stribeck term, one curve or one per direction."""

    stribeck: bool
    asymmetric: bool
    #: F_c per direction, one F_v (``fit_shared_viscous``; ``asymmetric`` and not ``stribeck``).
    shared_viscous: bool = False
    #: A curve of 2 points is fitted (its line through them), not refused (``asymmetric``).
    lines_of_two: bool = False

    @property
    def name(self) -> str:
        if self.shared_viscous:
            return "Coulomb per direction + one viscous"
        law = "Coulomb + viscous + Stribeck" if self.stribeck else "Coulomb + viscous"
        return f"{law}, {'per direction' if self.asymmetric else 'symmetric'}"

    def fits(self, sweep: Sweep, weight: np.ndarray, pinned: Optional[Tuple[LawFit, ...]] = None,
             errors: bool = True) -> Tuple[LawFit, ...]:
        """The law's curves fitted to ``sweep`` (``ValueError`` where a curve has too few points);
        ``pinned``: earlier fits of the curves whose Stribeck shape and v_s are kept; ``errors``
        False: without standard errors (``fit_law``)."""
        points = curve_points(sweep, weight, self.asymmetric)
        if self.shared_viscous:
            return fit_shared_viscous(points, errors)
        keep = [None] * len(points) if pinned is None else [(law.shape, law.v_s) for law in pinned]
        return tuple(fit_law(speed, magnitude, w, self.stribeck, k, errors)
                     for (speed, magnitude, w), k in zip(points, keep))

    def predictor(self, sweep: Sweep, weight: np.ndarray, offset: float = 0.0,
                  pinned: Optional[Tuple[LawFit, ...]] = None) -> Callable:
        """The signed force of the law fitted to ``sweep`` less ``offset``, plus ``offset``."""
        laws = self.fits(Sweep(sweep.v, sweep.f - offset), weight, pinned, errors=False)
        return lambda v: signed_force(v, laws[0].magnitude, laws[-1].magnitude if self.asymmetric
                                 else None) + offset

    def feasible(self, sweep: Sweep) -> bool:
        sizes = [speed.size for speed, _, _ in curve_points(sweep, np.ones(len(sweep)), self.asymmetric)]
        if self.shared_viscous:                   # its 3 parameters, and one point to judge them
            return min(sizes) >= 1 and sum(sizes) > 3
        if self.lines_of_two:
            return min(sizes) >= 2 and sum(sizes) > 4
        return min(sizes) >= MIN_POINTS[self.stribeck]


#: The chi-square (1 degree of freedom, 1 %) beyond which a direction of 2 points rejects the
#: other direction's viscous slope (``slope_rejected``).
SLOPE_CHI2 = 6.63
#: How many standard errors below 0 a direction's force must reach at v = 0 to push the axis
#: (``rest_levels``).
PUSH_SE = 3.0


def _best_fit(speed: np.ndarray, magnitude: np.ndarray, w: np.ndarray) -> Tuple[LawFit, float]:
    """A direction's own curve and noise variance: of its Coulomb + viscous and, from 2 points
    more than its parameters, Stribeck fits, the one of least residual variance per degree of
    freedom (a curving direction's straight line took its curvature for noise)."""
    fits = [(law, law.rms ** 2 * speed.size / (speed.size - PARAMETERS[stribeck]))
            for stribeck in (False, True) if speed.size >= PARAMETERS[stribeck] + 2
            for law in (fit_law(speed, magnitude, w, stribeck, errors=False),)]
    return min(fits, key=lambda fit: fit[1])


def slope_rejected(sweep: Sweep, weight: np.ndarray) -> Optional[float]:
    """Where one direction has 2 points (at two speeds) and the other 3 or more: the chi-square
    of the 2 points' residuals under the one viscous slope of ``fit_shared_viscous``, in the
    noise of the other direction (``_best_fit``), where it exceeds SLOPE_CHI2 (the directions'
    slopes differ: a new user's sweep of 0.015 and 0.25 m/s at v < 0 had its F_v printed
    7.74 +- 0.21 for a true 5); else None."""
    points = curve_points(sweep, weight, True)
    sizes = [p[0].size for p in points]
    short = int(np.argmin(sizes))
    speed, magnitude, w = points[short]
    if speed.size != 2 or np.ptp(speed) <= 0 or sizes[1 - short] < MIN_POINTS[False]:
        return None
    scale = np.mean(np.concatenate([p[2] for p in points]))
    noise = _best_fit(*points[1 - short])[1] * np.mean(points[1 - short][2]) / scale
    shared = fit_shared_viscous(points, errors=False)[short]
    chi2 = float(np.sum(w / scale * (magnitude - shared.magnitude(speed)) ** 2)) / max(noise, 1e-300)
    return chi2 if chi2 > SLOPE_CHI2 else None


def short_direction_differs(sweep: Sweep, weight: np.ndarray) -> Optional[float]:
    """Where one direction has 1 or 2 points and the other 2 more than Coulomb + viscous needs:
    the chi-square of the short direction's magnitudes against the long direction's own curve
    at their speeds (``_best_fit``), in that curve's noise and
    uncertainty, where it exceeds the 1 % level of as many degrees of freedom as points; else
    None. Held-out scoring never leaves out a direction's end points, so it never judged such a
    direction against one curve for both (a new user's sweep of 15 Stribeck points forward and
    2 flat ones backward kept one curve, 38 noise levels off the 2)."""
    points = curve_points(sweep, weight, True)
    sizes = [p[0].size for p in points]
    short = int(np.argmin(sizes))
    long_speed, long_magnitude, long_w = points[1 - short]
    if not 1 <= sizes[short] <= 2 or sizes[1 - short] < PARAMETERS[False] + 2:
        return None
    own, variance = _best_fit(long_speed, long_magnitude, long_w)
    p = PARAMETERS[own.stribeck]
    scale = np.mean(np.concatenate([pt[2] for pt in points]))
    noise = variance * (1 + p / long_speed.size) * np.mean(long_w) / scale
    speed, magnitude, w = points[short]
    chi2 = float(np.sum(w / scale * (magnitude - own.magnitude(speed)) ** 2)) / max(noise, 1e-300)
    return chi2 if chi2 > stats.chi2.ppf(0.99, sizes[short]) else None


def _rest_level(speed: np.ndarray, magnitude: np.ndarray, w: np.ndarray) -> Tuple[float, float]:
    """A direction's force magnitude extrapolated to v = 0 and its standard error: unconstrained
    weighted least squares of 1, |v| (and v^2 from 7 points) on its points (3 or more)."""
    design = np.column_stack([np.ones_like(speed), speed] + ([speed ** 2] if speed.size >= 7 else []))
    root = np.sqrt(w / np.mean(w))
    a, b = design * root[:, None], magnitude * root
    coef, *_ = np.linalg.lstsq(a, b, rcond=None)
    residual = b - a @ coef
    covariance = np.linalg.pinv(a.T @ a) * float(residual @ residual) / (speed.size - design.shape[1])
    return float(coef[0]), float(np.sqrt(max(covariance[0, 0], 0.0)))


def rest_levels(sweep: Sweep, weight: np.ndarray) -> Optional[list]:
    """Each direction's (v > 0, then v < 0; those with points) force magnitude extrapolated to
    v = 0 with its standard error (``_rest_level``), where one of them is below 0 by more than
    PUSH_SE standard errors: a force that pushes the axis at rest, which no friction does (a
    constant force beside it, or columns swapped). None where none is, or a direction has
    fewer than 3 points (a vertical axis's sweep of 3 speeds each way, its load 4 times its
    Coulomb level, had trained a downward curve of 0 and been refused as in other units)."""
    points = [p for p in curve_points(sweep, weight, asymmetric=True) if p[0].size]
    if any(p[0].size < 3 for p in points):
        return None
    levels = [_rest_level(*p) for p in points]
    return levels if any(level + PUSH_SE * se < 0 for level, se in levels) else None


def textbook_fit(law: TextbookLaw, sweep: Sweep, weight: np.ndarray,
                 cv_rmse: float = float("nan")) -> DirectionsFit:
    """The law's fit as the curves of a model (``DirectionsFit``), each with its points in the
    coordinates of [F9] for the report (``cv_rmse``: the law's held-out RMS error, N)."""
    fitted = []
    for curve_law, (speed, magnitude, _) in zip(law.fits(sweep, weight),
                                                curve_points(sweep, weight, law.asymmetric)):
        curve = curve_law.direction()
        x, t = curve.network_input(speed), curve.scaling.k_out * (magnitude - curve.viscous * speed)
        dataset = Dataset(x=x, t=t, scaling=curve.scaling, viscous=curve.viscous,
                          v_sat=curve.v_sat, n_rows=int(speed.size))
        estimator = TextbookRegressor.from_law(curve_law, curve)
        estimator.cv_rmse_ = cv_rmse * curve.scaling.k_out
        fitted.append(FittedDirection(curve, dataset, estimator))
    return DirectionsFit(tuple(fitted), "textbook")


def point_weights(sweep: Sweep, f_std=None, n=None) -> Optional[np.ndarray]:
    """Weights of a sweep's points from their spread: 1 / (f_std^2 / n + tau^2), the variance of
    each point's mean plus the scatter tau^2 between points that no point's own spread explains
    (position-dependent friction, drift), estimated from the residual variance of Coulomb +
    viscous fitted unweighted, per direction where each has the points for it (one curve for
    both took the directions' difference for scatter: a new user's asymmetric sweep had its
    weights flattened to 0.92-1 instead of 0.03-1); n alone weights as n; None without either."""
    if f_std is None:
        return None if n is None else np.asarray(n, dtype=float)
    variance = np.asarray(f_std, float) ** 2 / (1.0 if n is None else np.asarray(n, float))
    per_direction = TextbookLaw(False, True).feasible(sweep)
    curves = curve_points(sweep, variance, asymmetric=per_direction)
    squares = sum(fit_law(speed, magnitude, errors=False).rms ** 2 * speed.size
                  for speed, magnitude, _ in curves)
    points = sum(speed.size for speed, _, _ in curves)
    residual = squares / max(points - PARAMETERS[False] * len(curves), 1)
    moving_variance = np.concatenate([v for _, _, v in curves])
    return 1.0 / (variance + max(residual - float(np.mean(moving_variance)), 0.0))
