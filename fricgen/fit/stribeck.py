"""The grey-box estimator: [F1] itself, with S sources of one shape g, fitted to the data.

In the normalized coordinates of [F9], with B identified from the high-speed rows, [F1]
reads t(x) = c + sum_k a_k g(x, xs_k): linear in (c, a_k) (c gathers every f_ck, a_k the
f_sk - f_ck) and nonlinear in the S Stribeck velocities xs_k = K_in v_sk. ``fit_sources``
eliminates the linear part (variable projection, with Kaufman's Jacobian) and finds
theta_k = log xs_k by multi-start nonlinear least squares from every S-subset of a log grid.
``StribeckRegressor`` averages the fits of every S and g close in Akaike's criterion (AICc) and
reports every parameter of the result with its standard error.
"""
from __future__ import annotations

import itertools
import time
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .._validate import integer, positive
from ..data.outliers import inner_points
from ..data.training_set import SAT_FACTOR
from ..direction import CHECK_SPEEDS, opposes_motion
from ..friction import SHAPES
from ..metrics import rmse
from ..networks.stribeck import StribeckCurve
from .base import Estimator, interleaved_folds

#: Largest normalized Stribeck velocity: v_s <= vs_max = v_sat / SAT_FACTOR (``--vs-max``).
XS_MAX = 1.0 / SAT_FACTOR
#: Smallest normalized Stribeck velocity searched (a drop within 0.1 % of v_sat).
XS_MIN = 1e-3
#: Singular values of the Jacobian below this fraction of the largest leave their parameters
#: undetermined (an infinite standard error).
UNDETERMINED = 1e-9
#: Bounds on the normalized Stribeck velocities ``StribeckRegressor`` searches below: vs_max,
#: then v_sat (a broad source, for curves that are no sum of Stribeck curves).
XS_BOUNDS = (XS_MAX, 1.0)
#: Largest sum_k |a_k| of an admissible fit (normalized; the data's peak is 1). Sources that
#: nearly coincide can cancel with huge opposite amplitudes: meaningless, and float32 would
#: lose eps32 sum_k |a_k| to rounding. Multi-starts prefer fits within it; the estimator drops
#: the others.
AMPLITUDE_MAX = 10.0
#: Candidates whose AIC on all points is further than this from the best are not refitted in
#: cross-validation (a fold, with 4/5 of the points, practically never prefers them).
AIC_CONTENDERS = 10.0
#: The number of sources ``StribeckRegressor`` considers by default.
SOURCES = (1, 2, 3, 4)
#: The contenders are averaged with weights exp(-(AICc - best) / AVERAGING_SCALE): Akaike's
#: weights at twice their usual scale of 2, because the AICc of fits that differ in shape or S
#: by a source the noise hides differ by noise of a few units (set on sweeps of seeds 200-229).
AVERAGING_SCALE = 4.0
#: The curve that stands for the average has no source narrower than SEEN_BY times the
#: SEEN_POINTS-th slowest point's x: a source no more than two points see follows their noise.
SEEN_BY = 0.5
SEEN_POINTS = 3
#: Points of the dense grid over [0, 1] on which the average is matched by one curve.
AVERAGING_GRID = 201
#: ``bounded_least_squares`` stops at a step that lowers the cost by less than this fraction
#: ... or moves theta by less than this (relative): scipy's least_squares tests its defaults of
#: 1e-8 the same way; these are looser, far below what moves the AICc or the curve.
STOP_GAIN = 1e-6
STOP_STEP = 1e-6


def measured(x) -> np.ndarray:
    """A mask of the points [F1] is fitted to: x > 0. No friction is measured at v = 0; the
    [F9] set puts there the mean of the slowest rows (section 2), which lies below F(0) wherever
    g has a slope at 0 (exponential, rational), and a narrow negative source at XS_MIN would
    follow it. [F1] extrapolates to v = 0 instead."""
    return np.asarray(x) > 0


def shape_and_slope(shape: str, x: np.ndarray, xs: float):
    """g(x, xs) and its derivative with respect to theta = log xs."""
    u = x / xs
    g = SHAPES[shape](x, xs)
    if shape == "gauss":
        return g, 2.0 * u * u * g
    if shape == "exponential":
        return g, u * g
    return g, u * g * g                                  # rational: g = 1 / (1 + u)


def _basis(shape: str, x: np.ndarray, xs: Sequence[float]):
    """[1, g(x, xs_1), ..., g(x, xs_S)] and the derivative of each g column by its theta."""
    pairs = [shape_and_slope(shape, x, s) for s in xs]
    A = np.column_stack([np.ones_like(x)] + [g for g, _ in pairs])
    dA = np.column_stack([d for _, d in pairs]) if pairs else np.zeros((x.size, 0))
    return A, dA


@dataclass(frozen=True)
class SourcesFit:
    """One fit of [F1]: the curve, its residuals and the full Jacobian."""

    curve: StribeckCurve
    residuals: np.ndarray      # t - curve(x)
    jacobian: np.ndarray       # d curve / d (c, a_1..a_S, theta_1..theta_S), theta = log xs
    n_starts: int

    @property
    def theta(self) -> np.ndarray:
        return np.log(self.curve.stribeck)

    @property
    def rmse(self) -> float:
        return rmse(self.residuals, 0.0)

    @property
    def admissible(self) -> bool:
        """Whether sum_k |a_k| <= AMPLITUDE_MAX."""
        return _amplitude_sum(np.append(0.0, self.curve.amplitudes)) <= AMPLITUDE_MAX

    @property
    def opposes_motion(self) -> bool:
        """Whether the curve opposes the motion on [0, 1] as the loader's check asks
        (``direction.opposes_motion``). A source below the slowest speed measured, its amplitude
        undetermined, can take the level at rest below 0 (-19.7 N on a fleet log), and the model
        would be refused after training."""
        return opposes_motion(self.curve(CHECK_SPEEDS))

    @property
    def aic(self) -> float:
        """Akaike's criterion with the small-sample correction (AICc), n log(RSS / n) + 2 p +
        2 p (p + 1) / (n - p - 1), for the p = 2 S + 1 parameters: what chooses S and g."""
        n, p = self.jacobian.shape
        rss = max(float(self.residuals @ self.residuals) / n, 1e-300)
        return n * float(np.log(rss)) + 2 * p + 2 * p * (p + 1) / max(n - p - 1, 1)

    def standard_errors(self) -> dict:
        """Standard errors of c, a_k, xs_k and of the peak c + sum a_k from sigma^2 (J^T J)^-1,
        sigma^2 = RSS / (n - p);
        infinite for a parameter along which J is rank-deficient (singular values below
        ``UNDETERMINED`` of the largest): the data do not determine it, e.g. a Stribeck velocity
        below every measured speed but v = 0, where g's slope is 0."""
        n, p = self.jacobian.shape
        sigma2 = float(self.residuals @ self.residuals) / max(n - p, 1)
        _, sv, vt = np.linalg.svd(self.jacobian, full_matrices=False)
        kept = sv > UNDETERMINED * sv[0]
        variance = sigma2 * np.sum((vt[kept] / sv[kept, None]) ** 2, axis=0)
        undetermined = np.any(np.abs(vt[~kept]) > 1e-6, axis=0)
        se = np.where(undetermined, np.inf, np.sqrt(variance))
        s = self.curve.n_sources
        # the peak c + sum a_k (the static friction of [F1], normalized), from the covariance
        peak = np.r_[np.ones(1 + s), np.zeros(s)]
        peak_se = (np.inf if np.any(np.abs(vt[~kept] @ peak) > 1e-6) else
                   float(np.sqrt(sigma2 * np.sum((vt[kept] @ peak / sv[kept]) ** 2))))
        return {"offset": float(se[0]), "amplitudes": se[1:1 + s],
                "stribeck": self.curve.stribeck * se[1 + s:], "peak": peak_se}

    def undetermined_sources(self) -> np.ndarray:
        """The indices k of the sources whose a_k or xs_k the data do not determine (an
        infinite standard error), and of two sources whose Stribeck velocities coincide within
        a standard error of either (log xs): the data do not tell them apart, and their
        amplitudes can grow without bound in opposite directions (15.4 and -15.5 N, each
        +- 1.4e5, on a fleet log)."""
        se = self.standard_errors()
        bad = ~(np.isfinite(se["amplitudes"]) & np.isfinite(se["stribeck"]))
        theta, log_se = self.theta, se["stribeck"] / self.curve.stribeck
        for i, j in itertools.combinations(np.flatnonzero(~bad), 2):
            if abs(theta[i] - theta[j]) < max(log_se[i], log_se[j]):
                bad[[i, j]] = True
        return np.flatnonzero(bad)


def as_fit(curve: StribeckCurve, x, t, n_starts: int = 0) -> SourcesFit:
    """``curve`` as a fit to the points (x, t): its residuals and its Jacobian there."""
    A, dA = _basis(curve.shape, x, curve.stribeck)
    return SourcesFit(curve, t - curve(x), np.column_stack([A, dA * curve.amplitudes]), n_starts)


def akaike_weights(aic: dict) -> dict:
    """{key: weight} of the contenders (within AIC_CONTENDERS of the best AICc): exp(-delta /
    AVERAGING_SCALE), summing to 1."""
    best = min(aic.values())
    raw = {k: np.exp(-(a - best) / AVERAGING_SCALE) for k, a in aic.items()
           if a <= best + AIC_CONTENDERS}
    total = sum(raw.values())
    return {k: w / total for k, w in raw.items()}


def _amplitude_sum(coef: np.ndarray) -> float:
    return float(np.sum(np.abs(coef[1:])))


def start_grid(grid: int, xs_min: float = XS_MIN, xs_max: float = XS_MAX) -> np.ndarray:
    """``grid`` log-spaced starting values of theta = log xs in [max(2 xs_min, xs_max / 50), xs_max]."""
    return np.linspace(np.log(max(2 * xs_min, xs_max / 50)), np.log(xs_max), int(grid))


def all_subsets(grid: int, n_sources: int) -> list:
    """Every ``n_sources``-subset of the start grid: the exhaustive multi-start."""
    return list(itertools.combinations(start_grid(grid), int(n_sources)))


def _damped_step(H: np.ndarray, gradient: np.ndarray, damping: float) -> np.ndarray:
    """-(H + damping I)^-1 gradient, the Levenberg-Marquardt step: solved directly (H + damping I
    is positive definite for damping > 0), by least squares where rounding makes it singular."""
    if gradient.size == 1:
        return -gradient / (H[0, 0] + damping)
    damped = H + damping * np.eye(gradient.size)
    try:
        return np.linalg.solve(damped, -gradient)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(damped, -gradient, rcond=None)[0]


def bounded_least_squares(residual, jacobian, theta, lo: float, hi: float,
                          max_iterations: int = 200):
    """Levenberg-Marquardt (Nielsen's damping) on ``residual`` within lo <= theta <= hi (a
    parameter at a bound that the gradient pushes out of it is held there for the step): the
    minimizer reached from ``theta`` and its cost, half the squared residual. Far cheaper than a
    general solver for the 1-4 parameters of [F1]'s Stribeck velocities; it stops when a step
    gains less than STOP_GAIN of the cost or moves theta by less than STOP_STEP."""
    theta = np.clip(np.asarray(theta, dtype=float), lo, hi)
    r = residual(theta)
    cost, damping, growth = 0.5 * float(r @ r), None, 2.0
    for _ in range(max_iterations):
        J = jacobian(theta)
        gradient, H = J.T @ r, J.T @ J
        free = ~(((theta <= lo) & (gradient > 0)) | ((theta >= hi) & (gradient < 0)))
        if not free.any():
            break
        Hf, gf = H[np.ix_(free, free)], gradient[free]
        curvature = float(np.max(np.diag(Hf)))
        if not (curvature > 0 and np.all(np.isfinite(Hf)) and np.all(np.isfinite(gf))):
            break                             # theta moves nothing (stationary), or overflowed
        damping = 1e-3 * curvature if damping is None else max(damping, 1e-12 * curvature)
        while True:
            step = np.zeros_like(theta)
            step[free] = _damped_step(Hf, gf, damping)
            trial = np.clip(theta + step, lo, hi)
            if np.all(np.isfinite(trial)):
                r_trial = residual(trial)
                trial_cost = 0.5 * float(r_trial @ r_trial)
            else:                             # the solve overflowed: damp harder
                trial_cost = np.inf
            taken = trial - theta
            predicted = -(gradient @ taken) - 0.5 * taken @ H @ taken
            if trial_cost < cost and predicted > 0:
                rho = (cost - trial_cost) / predicted
                damping *= max(1.0 / 3.0, 1.0 - (2.0 * min(rho, 2.0) - 1.0) ** 3) \
                    if np.isfinite(rho) else 1.0 / 3.0
                growth = 2.0
                break
            damping *= growth
            growth *= 2.0
            if not damping <= 1e12 * curvature:              # (or not finite)
                return theta, cost
        done = cost - trial_cost <= STOP_GAIN * cost or \
            np.linalg.norm(taken) <= STOP_STEP * (STOP_STEP + np.linalg.norm(theta))
        theta, r, cost = trial, r_trial, trial_cost
        if done:
            break
    return theta, cost


def fit_sources(x, t, shape: str, starts, xs_min: float = XS_MIN,
                xs_max: float = XS_MAX, along_line: bool = False) -> SourcesFit:
    """[F1] with S = len(start) sources of ``shape`` by variable projection: the Stribeck
    velocities within [xs_min, xs_max], from every start in ``starts`` (vectors of theta =
    log xs); the best optimum wins. ``along_line``: the starts lie in order along a line (a
    grid of one source's velocity), and only those whose projected cost is a local minimum
    along it are polished (one per basin the line crosses), the others only when none of
    those gave an admissible fit."""
    x, t = np.asarray(x, dtype=float), np.asarray(t, dtype=float)
    lo, hi = np.log(xs_min), np.log(xs_max)

    cache = {}

    def project(theta):                                    # residual and jacobian share it
        key = theta.tobytes()
        if key not in cache:
            A, dA = _basis(shape, x, np.exp(theta))
            Q, R = np.linalg.qr(A)
            diag = np.abs(np.diag(R))
            if diag.min() > 1e-10 * diag.max():
                coef = np.linalg.solve(R, Q.T @ t)
            else:                                          # coinciding sources
                coef = np.linalg.lstsq(A, t, rcond=None)[0]
            cache.clear()
            cache[key] = (A, dA, Q, coef, t - A @ coef)
        return cache[key]

    def residual(theta):
        return project(theta)[4]

    def jacobian(theta):                                   # Kaufman: -(I - P) dA/dtheta a
        A, dA, Q, coef, r = project(theta)
        D = dA * coef[1:]
        return -(D - Q @ (Q.T @ D))

    starts = [np.clip(np.asarray(s, dtype=float), lo, hi) for s in starts]
    polish = list(range(len(starts)))
    if along_line and len(starts) > 2:                    # the basins the line crosses first
        cost = [float(np.sum(residual(s) ** 2)) for s in starts]
        basins = [i for i in polish if cost[i] <= min(cost[max(i - 1, 0):i + 2])]
        polish = basins + [i for i in polish if i not in basins]
        polish_first = len(basins)
    best, best_key = None, None
    for n, i in enumerate(polish):
        if along_line and n >= polish_first and best_key is not None and not best_key[0]:
            break                                         # the basins held an admissible fit
        theta, cost = bounded_least_squares(residual, jacobian, starts[i], lo, hi)
        key = (_amplitude_sum(project(theta)[3]) > AMPLITUDE_MAX, cost)
        if best is None or key < best_key:
            best, best_key = theta, key
    xs = np.exp(best)
    order = np.argsort(xs)
    xs = xs[order]
    A, _ = _basis(shape, x, xs)
    coef, *_ = np.linalg.lstsq(A, t, rcond=None)
    return as_fit(StribeckCurve(shape, float(coef[0]), coef[1:], xs), x, t, len(starts))


def drop_undetermined(fit: SourcesFit, refit):
    """``fit`` without the sources of [F1] that the data do not determine: one at a time (of
    those, the one with the smallest |a_k|, so that of two coinciding sources one stays), the
    others refitted from their Stribeck velocities by ``refit(theta)``, until every source is
    determined. None when not one source would be left."""
    while True:
        bad = fit.undetermined_sources()
        if bad.size == 0:
            return fit
        if fit.curve.n_sources == 1:
            return None
        drop = bad[np.argmin(np.abs(fit.curve.amplitudes[bad]))]
        fit = refit(np.delete(fit.theta, drop))


def _better(a, b):
    """The better of two fits with the same number of sources (either may be None): admissible
    first, then the lower AIC."""
    if a is None or b is None:
        return a if b is None else b
    return min(a, b, key=lambda f: (not f.admissible, f.aic))


def cross_validated_residuals(x, t, fit: SourcesFit, folds: np.ndarray, xs_min: float = XS_MIN,
                              xs_max: float = XS_MAX):
    """``fit``'s model refitted without each fold (started from ``fit``'s Stribeck velocities):
    the residual at each point of the refit without its fold, and each refit's AIC by fold."""
    x, t = np.asarray(x, dtype=float), np.asarray(t, dtype=float)
    held_out = np.empty_like(t)
    aics = {}
    for k in np.unique(folds):
        out = folds == k
        train = ~out & measured(x)
        refit = fit_sources(x[train], t[train], fit.curve.shape, [fit.theta], xs_min, xs_max)
        held_out[out] = refit.curve(x[out]) - t[out]
        aics[int(k)] = refit.aic if refit.admissible else np.inf
    return held_out, aics


class StribeckRegressor(Estimator):
    r"""The grey-box estimator: [F1] itself, with S sources of one shape g, fitted to the data.

    Every S in ``sources`` and g in ``shapes`` is fitted by variable projection to the points at
    x > 0 (``measured``); the fits close in Akaike's criterion (AICc) are averaged with Akaike
    weights and the average is matched by one curve of [F1]: picking the single best fit lets a
    wrong shape with an extra source win on noise. A source the data do not determine (infinite
    standard error) is dropped and the rest refitted. x and t are the normalized data of [F9].

    Parameters
    ----------
    shapes : sequence of str
        The g of [F2] to try: "gauss", "exponential", "rational".
    sources : sequence of int
        The numbers of sources S to try.
    xs_bounds : sequence of float
        Upper bounds of the normalized Stribeck velocities, searched in turn: the first is
        vs_max (1 / SAT_FACTOR); a larger one lets a source stand for a broad non-linear viscous
        part, at one more parameter in the AIC.
    grid : int
        Log-spaced start values of the Stribeck velocity (multi-start).
    n_folds : int
        Folds of the cross-validation of the whole procedure (``cv_rmse_``); 0 for none
        (``cv_residuals_`` None, ``cv_rmse_`` nan).
    starts : dict, optional
        {(shape, S, bound): Stribeck velocities theta = log xs}: fit exactly these candidates,
        each from its own start, instead of the multi-start (``warm_copy``).
    spare : dict, optional
        More candidates as ``starts``, fitted only when none of those is admissible.

    Attributes
    ----------
    network_ : StribeckCurve
        The fitted [F1] in normalized units, the AIM of [F3].
    shape_ : str
        Its g; ``n_sources_`` (int): its S.
    xs_max_, xs_min_ : float
        The largest bound among the contenders and the smallest Stribeck velocity allowed
        (normalized velocity, x units).
    candidates_ : dict
        {(shape, S, bound): AICc} of the admissible fits; ``fits_``: each one's fit;
        ``best_``: the key of the smallest AICc; ``weights_``: the contenders' Akaike weights.
    cv_residuals_ : ndarray
        Held-out residuals on interleaved folds (units of t).
    cv_rmse_, train_rmse_ : float
        Cross-validated and training RMSE (units of t, normalized force).
    standard_errors_ : dict
        Standard errors of offset, amplitudes, Stribeck velocities and peak (normalized units).
    fit_seconds_ : float
        Wall time of ``fit`` (s).

    Notes
    -----
    In normalized units the curve is [F1] for v > 0 without the viscous part (removed by
    [F9]), plus a slope d for an error of the identified B:
    :math:`t(x) = c + \sum_{k=1}^S a_k g(x, x_{sk}) + d x`, with :math:`x_{sk} = K_{in} v_{sk}`.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import StribeckRegressor
    >>> x = np.linspace(0, 1, 40)
    >>> t = 0.5 + 0.5 * np.exp(-(x / 0.2) ** 2)
    >>> grey = StribeckRegressor(shapes=("gauss",), sources=(1, 2)).fit(x, t)
    >>> grey.shape_, grey.n_sources_, round(float(grey.network_.stribeck[0]), 3)
    ('gauss', 1, 0.2)
    """

    activation = "stribeck"
    scheme = "grey-box"

    def __init__(self, shapes: Sequence[str] = tuple(SHAPES), sources: Sequence[int] = SOURCES,
                 xs_bounds: Sequence[float] = XS_BOUNDS, grid: int = 7, n_folds: int = 5,
                 starts=None, spare=None):
        self.shapes = shapes
        self.sources = sources
        self.xs_bounds = xs_bounds
        self.grid = grid
        self.n_folds = n_folds
        self.starts = starts
        self.spare = spare

    def warm_copy(self) -> "StribeckRegressor":
        """An unfitted copy that refits this fit's contenders (``weights_``: the others, beyond
        AIC_CONTENDERS, practically never win on data close to these; they are ``spare``, for a
        fold where no contender is admissible), each from its Stribeck
        velocities (one start instead of the multi-start), without cross-validating itself: the
        whole procedure again (AICc, averaging, dropping) at a fraction of the cost, for data
        close to these (a fold of them)."""
        thetas = {k: tuple(f.theta) for k, f in self.fits_.items()}
        return StribeckRegressor(self.shapes, self.sources, self.xs_bounds, self.grid, 0,
                                 {k: thetas[k] for k in self.weights_},
                                 {k: v for k, v in thetas.items() if k not in self.weights_})

    def fit(self, x, t) -> "StribeckRegressor":
        shapes = list(self.shapes)
        if not shapes or any(s not in SHAPES for s in shapes):
            raise ValueError(f"shapes must be a non-empty list of {sorted(SHAPES)}, got {shapes!r}")
        sources = [integer("sources", s) for s in self.sources]
        bounds = [positive("xs_bounds", b) for b in self.xs_bounds]
        if not sources or not bounds:
            raise ValueError("sources and xs_bounds must not be empty")
        integer("grid", self.grid, minimum=2)
        if self.n_folds != 0:
            integer("n_folds", self.n_folds, minimum=2)
        x_all, t_all = self._inputs(x, t)
        x, t = x_all[measured(x_all)], t_all[measured(x_all)]
        start = time.perf_counter()
        fits, tried = {}, 0
        self.xs_min_ = xs_min = XS_MIN

        def keep(found: SourcesFit, xs_max: float) -> SourcesFit:
            """``found`` kept by its (shape, S, bound) once its undetermined sources are dropped."""
            shape = found.curve.shape
            kept = drop_undetermined(found, lambda theta: fit_sources(
                x, t, shape, [theta], xs_min, xs_max))
            if kept is not None:
                key = (shape, kept.curve.n_sources, xs_max)
                fits[key] = _better(fits.get(key), kept)
            return found

        for given in (self.starts or {}), (self.spare or {}):
            if any(f.admissible for f in fits.values()):
                break
            for (shape, _, xs_max), theta in given.items():
                tried += 1
                keep(fit_sources(x, t, shape, [np.asarray(theta)], xs_min, xs_max), xs_max)
        for xs_max in bounds if self.starts is None else ():
            if xs_max <= xs_min:
                continue
            grid = start_grid(self.grid, xs_min, xs_max)
            for shape in shapes:
                previous = None
                for s in sorted(sources):
                    if 2 * s + 1 >= x.size:
                        break
                    starts = [np.append(previous.theta, g) for g in grid] if previous else \
                        [np.array([g]) for g in grid]
                    previous = keep(fit_sources(x, t, shape, starts, xs_min, xs_max,
                                                along_line=True), xs_max)
                    tried += 1
        if not tried:
            raise ValueError(f"{x.size} points at v > 0 are too few for [F1] with {min(sources)} "
                             "sources")
        if not fits:
            raise ValueError("the data determine no source of [F1]: every Stribeck velocity "
                             "fitted lies where no sample constrains it")
        self._penalty = {b: 2.0 * i for i, b in enumerate(bounds)}
        # the fits that oppose the motion, where there are any (data that are no friction curve
        # may have none: the default's other candidates then take them)
        opposing = {k for k, f in fits.items() if f.admissible and f.opposes_motion}
        self.candidates_ = {k: f.aic + self._penalty[k[2]] for k, f in fits.items()
                            if f.admissible and (k in opposing or not opposing)}
        if not self.candidates_:
            raise ValueError(f"no fit of [F1] keeps sum |a_k| <= {AMPLITUDE_MAX:g}")
        self.fits_ = fits
        self.weights_ = akaike_weights(self.candidates_)
        self.best_ = min(self.candidates_, key=lambda k: (self.candidates_[k], k[1]))
        best = self._average(x, t, shapes, sources)
        self.network_ = best.curve
        self.shape_, self.n_sources_ = best.curve.shape, best.curve.n_sources
        self.xs_max_ = max(k[2] for k in self.weights_)
        self.cv_residuals_, self.cv_rmse_ = None, float("nan")
        if self.n_folds:
            self.cv_residuals_ = self.held_out_residuals(x_all, t_all,
                                                         interleaved_folds(x_all, self.n_folds))
            self.cv_rmse_ = rmse(self.cv_residuals_[inner_points(x_all)], 0.0)
        self.train_rmse_ = best.rmse
        self.standard_errors_ = best.standard_errors()
        self.fit_seconds_ = time.perf_counter() - start
        return self

    def _average(self, x, t, shapes, sources) -> SourcesFit:
        """The contenders' average (``weights_``) as one curve of [F1]: the curve nearest the
        average on the points and a dense grid, of the contenders themselves and of the closest
        match (one shape and S from the smallest contender's to the largest contender's, fitted
        to the average from the fits of that shape and S), its undetermined sources dropped;
        of those, only curves each of whose sources more than two points see (SEEN_BY): a narrow
        source at the two slowest points follows their noise, and a contender that holds one
        passes it on to the average. The best contender alone when it is the only one (or no
        curve is left).

        The nearest curve, not the one with the fewest sources close to it: the fits averaged
        are those the noise cannot tell apart, so a curve with a source fewer lies as close to
        the average as the noise allows and yet may be twice as far from the truth (Table 1's
        three gaussian sources matched by two). Where the match's sources are too close for
        the points to determine them, dropping one moves it off the average, and a contender
        is nearer."""
        if len(self.weights_) == 1:
            return self.fits_[self.best_]
        grid = np.union1d(x, np.linspace(x.min(), x.max(), AVERAGING_GRID))
        target = sum(w * self.fits_[k].curve(grid) for k, w in self.weights_.items())
        bound = max(k[2] for k in self.weights_)
        smallest, largest = (f(k[1] for k in self.weights_) for f in (min, max))
        nearest = [self.fits_[k] for k in self.weights_]
        matches = []
        for shape in shapes:
            for s in (s for s in sources if smallest <= s <= largest):
                starts = [f.theta for k, f in self.fits_.items() if k[:2] == (shape, s)]
                if starts:
                    match = fit_sources(grid, target, shape, starts, self.xs_min_, bound)
                    if match.admissible:
                        matches.append(match)
        if matches:
            curve = min(matches, key=lambda m: m.rmse).curve
            match = drop_undetermined(as_fit(curve, x, t, len(matches)), lambda theta: as_fit(
                fit_sources(grid, target, curve.shape, [theta], self.xs_min_, bound).curve, x, t))
            if match is not None:
                nearest.insert(0, match)
        narrowest = SEEN_BY * np.sort(x)[min(SEEN_POINTS, x.size) - 1]
        seen = [f for f in nearest if np.all(f.curve.stribeck >= narrowest)]
        return min(seen or [self.fits_[self.best_]], key=lambda f: rmse(f.curve(grid), target))

    def held_out_residuals(self, x, t, folds) -> np.ndarray:
        """The whole procedure validated on ``folds`` of the points it was fitted to: without
        each fold, every contender (``weights_``) is refitted (started from its full fit) and the
        contenders are averaged again by the fold's AICc; the residual at each point is that of
        the fold's average."""
        x, t = self._inputs(x, t)
        keys = list(self.weights_)
        refits = [cross_validated_residuals(x, t, self.fits_[k], folds, self.xs_min_, k[2])
                  for k in keys]
        held_out = np.empty_like(t)
        for fold in np.unique(folds):
            out = folds == fold
            aic = {j: refits[j][1][int(fold)] + self._penalty[k[2]] for j, k in enumerate(keys)}
            aic = {j: a for j, a in aic.items() if np.isfinite(a)} or {keys.index(self.best_): 0.0}
            held_out[out] = sum(w * refits[j][0][out] for j, w in akaike_weights(aic).items())
        return held_out

    @property
    def n_hidden(self) -> int:
        """The number of sources S (what the fit report calls the model's size)."""
        return self.n_sources_
