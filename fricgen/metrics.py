"""Error measures of section 2."""
from __future__ import annotations

import numpy as np


def rmse(y, t) -> float:
    """Root-mean-square error, [F4]-[F6]."""
    return float(np.sqrt(np.mean((np.asarray(y) - np.asarray(t)) ** 2)))


def least_squares_errors(X: np.ndarray, y: np.ndarray, independent: float):
    """Least-squares coefficients of y ~ X and their standard errors, the residual variance
    scaled by n / ``independent`` (samples correlated by smoothing count as fewer)."""
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    r = y - X @ coef
    n, p = X.shape
    cov = np.linalg.pinv(X.T @ X) * float(r @ r) / max(n - p, 1) * n / max(independent, 4.0)
    return coef, np.sqrt(np.maximum(np.diag(cov), 0.0))
