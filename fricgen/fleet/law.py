"""The fleet's monitoring law: one fixed law per direction, fitted to every log of every axis so
that their parameters compare,

    F(|v|) = F_c + (F_s - F_c) g(|v| / v_s) + B |v|,

[F1] with one source of ``shape`` and the viscous term, all four parameters from the folded rows
of one direction at once (variable projection over v_s), with standard errors from the Jacobian
of all four, so that B's uncertainty is in F_c's. The trained model's structure (its shape and
number of sources, and the vs_max that splits its rows between the Stribeck curve and B) may
change between two logs of one axis, and its Coulomb level with it; this law's does not.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import minimize_scalar

from ..data.sweep import Sweep
from ..data.viscous import bin_equal_counts
from ..fit.stribeck import shape_and_slope
from ..friction import SHAPES

#: The law's g of [F2].
LAW_SHAPE = "exponential"
#: v_s is searched over this many decades below the fastest speed, on a grid of GRID points
#: refined by Brent's method around the best.
DECADES, GRID = 3.0, 31


def _basis(shape: str, v: np.ndarray, theta: float) -> np.ndarray:
    return np.column_stack([np.ones_like(v), SHAPES[shape](v, np.exp(theta)), v])


def _rss(shape: str, v, f, theta) -> float:
    A = _basis(shape, v, theta)
    coef = np.linalg.lstsq(A, f, rcond=None)[0]
    r = f - A @ coef
    return float(r @ r)


def fit_law(half: Sweep, samples: float, shape: str = LAW_SHAPE) -> dict:
    """The law fitted to one direction's folded rows ``half`` (speeds >= 0), averaged into
    ``samples`` bins (its independent samples, ``bin_equal_counts``): ``coulomb``, ``static``,
    ``stribeck``, ``viscous`` (N, N, m/s, N s/m), each with ``_se`` (NaN when the rows do not
    determine it).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen.data.sweep import Sweep
    >>> from fricgen.fleet.law import fit_law
    >>> v = np.linspace(0.001, 0.2, 400)
    >>> law = fit_law(Sweep(v, 4 + 2 * np.exp(-v / 0.02) + 10 * v), 400)
    >>> [round(law[k], 4) for k in ("coulomb", "static", "stribeck", "viscous")]
    [4.0, 6.0, 0.02, 10.0]
    """
    data = bin_equal_counts(half, max(int(samples), 8))
    v, f = data.v, data.f
    top = float(np.max(v))
    grid = np.linspace(np.log(top) - DECADES * np.log(10.0), np.log(top), GRID)
    rss = [_rss(shape, v, f, th) for th in grid]
    k = int(np.argmin(rss))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, GRID - 1)]
    theta = float(minimize_scalar(lambda th: _rss(shape, v, f, th), bounds=(lo, hi),
                                  method="bounded", options={"xatol": 1e-6}).x)
    A = _basis(shape, v, theta)
    (c, a, b), *_ = np.linalg.lstsq(A, f, rcond=None)
    _, slope = shape_and_slope(shape, v, float(np.exp(theta)))
    J = np.column_stack([A, a * slope])                      # d F / d (c, a, B, theta)
    r = f - A @ np.array([c, a, b])
    sigma2 = float(r @ r) / max(v.size - 4, 1)
    try:
        cov = sigma2 * np.linalg.inv(J.T @ J)
    except np.linalg.LinAlgError:
        cov = np.full((4, 4), np.nan)
    var = np.diag(cov)
    peak = cov[0, 0] + 2 * cov[0, 1] + cov[1, 1]
    root = lambda x: float(np.sqrt(x)) if x >= 0 else float("nan")   # noqa: E731
    return {"coulomb": float(c), "coulomb_se": root(var[0]),
            "static": float(c + a), "static_se": root(peak),
            "stribeck": float(np.exp(theta)), "stribeck_se": float(np.exp(theta)) * root(var[3]),
            "viscous": float(b), "viscous_se": root(var[2])}
