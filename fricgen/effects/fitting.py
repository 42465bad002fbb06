"""The numerics the named effects' fits share: least squares on the rows fitted, a search
over one nonlinear parameter (a grid, refined by bounded Brent between the best point's
neighbours), and the choice among nested bases by blocked cross-validation."""
from __future__ import annotations

from typing import Tuple

import numpy as np
from scipy.optimize import minimize_scalar

from .base import Effect


def lstsq(basis: np.ndarray, target: np.ndarray) -> Tuple[np.ndarray, float]:
    """The least-squares coefficients of ``basis`` for ``target``, and the residual sum of squares."""
    coef, *_ = np.linalg.lstsq(basis, target, rcond=None)
    return coef, float(np.sum((target - basis @ coef) ** 2))


def refine(objective, lo: float, hi: float) -> float:
    """Minimize a 1-D objective on [lo, hi] (bounded Brent)."""
    res = minimize_scalar(objective, bounds=(lo, hi), method="bounded", options={"xatol": 1e-4 * (hi - lo)})
    return float(res.x)


def grid_then_refine(rss_of, grid: np.ndarray) -> float:
    """The grid point with the least RSS, refined between its neighbours."""
    rss = np.array([rss_of(g) for g in grid])
    k = int(np.argmin(rss))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    if hi <= lo:
        return float(grid[k])
    best = refine(rss_of, lo, hi)
    return best if rss_of(best) <= rss[k] else float(grid[k])


def fit_linear(template: "Effect", problem, rows) -> "Effect":
    """``template`` with its linear parameters (``Effect.linear``) fitted by least squares."""
    regressors, _ = template.linear(problem.signals)
    coef, _ = lstsq(problem.at_rows(regressors, rows), problem.target[rows])
    return template.with_coefficients(coef)


#: Contiguous blocks of the blocked cross-validation inside a fit (``choose_by_cross_validation``).
FIT_FOLDS = 10


def choose_by_cross_validation(designs, target: np.ndarray, folds: int = FIT_FOLDS) -> int:
    """How many of the ``designs`` (each an (n, k) basis, simplest first: nested, or as a
    position series orders its fundamentals' series by harmonics) to take: the
    simplest whose blocked cross-validated mean square (least squares fitted on the other
    contiguous blocks of the rows) is within one standard error of the best's, the standard
    error of the best's mean over the blocks (the one-standard-error rule of Breiman et al.):
    a term that lowers the held-out error by less than the blocks' spread is not taken.
    Returns 1..len."""
    blocks = np.array_split(np.arange(target.size), folds)
    errors = np.empty((len(designs), len(blocks)))
    for j, block in enumerate(blocks):
        train = np.ones(target.size, bool)
        train[block] = False
        for m, X in enumerate(designs):
            coef, _ = lstsq(X[train], target[train])
            errors[m, j] = float(np.mean((target[block] - X[block] @ coef) ** 2))
    return one_standard_error_choice(errors)


def one_standard_error_choice(errors: np.ndarray) -> int:
    """Of candidates ordered simplest first, each with its held-out mean squares over the blocks
    (a row of ``errors``), the simplest whose mean is within one standard error of the best's
    (Breiman et al.). Returns 1..len."""
    mean = errors.mean(axis=1)
    best = int(np.argmin(mean))
    limit = mean[best] + errors[best].std(ddof=1) / np.sqrt(errors.shape[1])
    return int(np.flatnonzero(mean <= limit)[0]) + 1


def block_grams(design: np.ndarray, target: np.ndarray, folds: int = FIT_FOLDS) -> list:
    """Per contiguous block of the rows (``folds`` of them): X'X, X'y, y'y and its row count,
    from which a least-squares fit without any one block costs O(p^3), not a pass over the rows."""
    blocks = [slice(b[0], b[-1] + 1) for b in np.array_split(np.arange(target.size), folds)]
    return [(design[b].T @ design[b], design[b].T @ target[b], float(target[b] @ target[b]),
             b.stop - b.start) for b in blocks]


def nested_cross_validation(design: np.ndarray, target: np.ndarray, sizes, folds: int = FIT_FOLDS) -> int:
    """``choose_by_cross_validation`` of the nested designs ``design[:, :p]`` for p in ``sizes``,
    through each block's Gram matrix: O(folds p^2) per design after one pass over the rows (for
    long logs). Returns 1..len(sizes)."""
    grams = block_grams(design, target, folds)
    g_all = sum(g[0] for g in grams)
    b_all = sum(g[1] for g in grams)
    errors = np.empty((len(sizes), folds))
    for m, p in enumerate(sizes):
        for j, (g, b, yy, n) in enumerate(grams):
            coef = np.linalg.lstsq((g_all - g)[:p, :p], (b_all - b)[:p], rcond=None)[0]
            errors[m, j] = (yy - 2 * coef @ b[:p] + coef @ g[:p, :p] @ coef) / n
    return one_standard_error_choice(errors)
