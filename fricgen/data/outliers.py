"""Gross outliers: spikes that no friction curve explains, found by one rule.

A point is a gross outlier when its residual from a robust fit lies further than
OUTLIER_SIGMAS robust standard deviations (1.4826 MAD, ``robust_scale``) from it. The high-speed
rows of B are judged against a Theil-Sen line (``fricgen.data.training_set.identify_viscous``),
the [F9] training set against a running median over the points in order of x, which no
isolated spike moves (a Theil-Sen line where the points are too few for its window:
``line_outliers``). A running median lags where the curve is steepest (a narrow Stribeck drop
next to v = 0), so its suspects are confirmed against a smooth model fitted to every point (``unexplained``;
the default's [F1], which no isolated spike bends): a suspect that it explains within
OUTLIER_SIGMAS of its robust residual spread on the other points is kept. Bounded noise, such as the benchmark's uniform +-0.5 N, is never
rejected.
"""
from __future__ import annotations

from typing import Tuple

import numpy as np

#: Points further than this many robust standard deviations from the robust fit are outliers.
OUTLIER_SIGMAS = 6.0
#: The least robust standard deviation, relative to the values' median magnitude: on noise-free
#: data no deviation below OUTLIER_SIGMAS times this (0.6 % of a typical force) is gross.
SCALE_FLOOR = 1e-3
#: Points in the running median's window (odd): a spike is outvoted unless 4 meet in one window.
MEDIAN_WINDOW = 7
#: Fewest points ``line_outliers`` judges: with fewer, a line through the others is no judge.
LINE_POINTS = 5


def robust_scale(residual: np.ndarray, values: np.ndarray) -> float:
    """A robust standard deviation of the absolute residuals of ``values``: 1.4826 times their
    median, or, when most are 0 (a quantized force), times the values' quantum (the median step
    between their distinct values: a few spikes among the rare nonzero residuals would set a
    median of those alone); never below ``SCALE_FLOOR`` of the values' median magnitude
    (noise-free data: the curve's own bend off a line or a running median is no outlier)."""
    typical = float(np.median(np.abs(values)))
    scale = 1.4826 * float(np.median(residual))
    if not scale > 0:
        steps = np.diff(np.unique(np.asarray(values, dtype=float)))
        scale = 1.4826 * float(np.median(steps)) if steps.size else 0.0
    return max(scale, SCALE_FLOOR * typical)


def inner_points(x) -> np.ndarray:
    """A mask of every point but those at the smallest and the largest x: in the [F9] set
    these are the two boundary points of section 2 (the mean of the slowest rows at x = 0 and
    the high-speed line at x = 1), not measurements. Outlier rejection leaves them alone and
    cross-validation scores the others only (a narrow Stribeck source decides the value at
    x = 0 alone, so leaving that one point out says nothing about the fit)."""
    inner = np.ones(np.size(x), dtype=bool)
    if inner.size:
        inner[[int(np.argmin(x)), int(np.argmax(x))]] = False
    return inner


def running_median(x: np.ndarray, t: np.ndarray, window: int = MEDIAN_WINDOW) -> np.ndarray:
    """The median of t over the ``window`` nearest points in order of x (fewer at the ends)."""
    order = np.argsort(x, kind="stable")
    ts = np.asarray(t, dtype=float)[order]
    half = window // 2
    padded = np.concatenate([np.full(half, np.nan), ts, np.full(half, np.nan)])
    windows = np.lib.stride_tricks.sliding_window_view(padded, window)
    smooth = np.empty_like(ts)
    smooth[order] = np.nanmedian(windows, axis=1)
    return smooth


def gross_outliers(x, t, sigmas: float = OUTLIER_SIGMAS, window: int = MEDIAN_WINDOW) -> np.ndarray:
    """A mask of the points more than ``sigmas`` robust standard deviations off the running
    median (none when the residuals have no spread or there are too few points). The points
    at the smallest and the largest x are never rejected (``inner_points``)."""
    x, t = np.asarray(x, dtype=float), np.asarray(t, dtype=float)
    if x.size < 2 * window:
        return np.zeros(x.size, dtype=bool)
    residual = np.abs(t - running_median(x, t, window))
    scale = robust_scale(residual, t)
    if not scale > 0:
        return np.zeros(x.size, dtype=bool)
    return (residual > sigmas * scale) & inner_points(x)


def theil_sen(v: np.ndarray, f: np.ndarray, most: int = 400) -> Tuple[float, float]:
    """A line through (v, f) that gross outliers cannot move: the median of pairwise slopes
    over at most ``most`` rows spread over the velocity order, and the median intercept."""
    order = np.argsort(v)
    pick = order[np.unique(np.linspace(0, v.size - 1, min(most, v.size)).astype(int))]
    dv = v[pick][:, None] - v[pick][None, :]
    df = f[pick][:, None] - f[pick][None, :]
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):   # ties: masked out
        slopes = (df / dv)[np.triu(dv != 0, 1)]
    slope = float(np.median(slopes[np.isfinite(slopes)])) if np.isfinite(slopes).any() else 0.0
    with np.errstate(over="ignore", invalid="ignore"):
        return slope, float(np.median(f - slope * v))


def line_outliers(x, t, sigmas: float = OUTLIER_SIGMAS) -> np.ndarray:
    """``gross_outliers`` for points too few for a running median (LINE_POINTS up to 2
    MEDIAN_WINDOW): those off the Theil-Sen line (``theil_sen``) by more than ``sigmas`` robust
    standard deviations of its residuals, the points at the smallest and the largest x never. A
    curve that bends off a line gives suspects too: ``unexplained`` confirms them."""
    x, t = np.asarray(x, dtype=float), np.asarray(t, dtype=float)
    if x.size < LINE_POINTS:
        return np.zeros(x.size, dtype=bool)
    slope, intercept = theil_sen(x, t)
    residual = np.abs(t - intercept - slope * x)
    return (residual > sigmas * robust_scale(residual, t)) & inner_points(x)


def unexplained(t, suspects, predictions, sigmas: float = OUTLIER_SIGMAS) -> np.ndarray:
    """The ``suspects`` (a mask) that no model explains: off each of ``predictions`` (smooth
    models evaluated at every point) by more than ``sigmas`` robust standard deviations of that
    model's residuals on the other points."""
    t = np.asarray(t, dtype=float)
    confirmed = np.asarray(suspects, dtype=bool).copy()
    for prediction in predictions:
        residual = np.abs(t - prediction)
        scale = robust_scale(residual[~suspects], t)
        confirmed &= residual > sigmas * scale
    return confirmed
