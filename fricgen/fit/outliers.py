"""Gross outliers of the eq. (9) training set: spikes that no friction curve explains.

A running median over the points in order of x follows any smooth curve, the Stribeck drop
included, and no isolated spike moves it. Points further from it than OUTLIER_SIGMAS robust
standard deviations (1.4826 MAD of the residuals, ``robust_scale``) are gross outliers, the rule the high-speed
rows of B already follow (``fricgen.data.training_set.identify_viscous``). Bounded noise, such as
the benchmark's uniform +-0.5 N, is never rejected.
"""
from __future__ import annotations

import numpy as np

from ..data.training_set import OUTLIER_SIGMAS, robust_scale
from .base import inner_points

#: Points in the running median's window (odd): a spike is outvoted unless 4 meet in one window.
MEDIAN_WINDOW = 7


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
