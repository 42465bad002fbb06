"""The honest oracle: [F1] itself, with the true shape and number of sources, fitted to the
data; the best any method can do on a benchmark whose friction is known.

In the normalized coordinates of [F9], with B identified from the high-speed rows like every
other estimator, [F1] reads t(x) = c + sum_k a_k g(x, xs_k): nothing else is fitted (no
slope, no extra source). The linear part (c, a_k) is eliminated (variable projection) and the
xs_k are found by multi-start nonlinear least squares from every S-subset of a log grid
(``fricgen.fit.stribeck.fit_sources``), each within [XS_MIN, vs_max] (``--vs-max`` bounds the
Stribeck velocities).
"""
from __future__ import annotations

import itertools
import time

from .._validate import integer
from ..friction import SHAPES
from .base import Estimator
from .stribeck import XS_MAX, XS_MIN, fit_sources, start_grid


class OracleRegressor(Estimator):
    """The honest oracle: [F1] with the true shape and number of sources, fitted by variable
    projection from every ``n_sources``-subset of ``grid`` log-spaced Stribeck velocities.

    Parameters
    ----------
    shape : str
        The true g of [F2].
    n_sources : int
        The true S.
    grid : int
        Start values of the Stribeck velocity (>= n_sources).

    Attributes
    ----------
    network_ : StribeckCurve
        The fitted [F1], normalized (the AIM of [F3]).
    cost_ : float
        Half the residual sum of squares (units of t squared).
    n_starts_ : int
        Starts tried.
    fit_seconds_ : float
        Wall time of ``fit`` (s).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen.fit import OracleRegressor
    >>> x = np.linspace(0, 1, 40)
    >>> oracle = OracleRegressor(n_sources=1, grid=4).fit(x, 0.5 + 0.5 * np.exp(-(x / 0.2) ** 2))
    >>> round(float(oracle.network_.stribeck[0]), 3), bool(oracle.cost_ < 1e-12)
    (0.2, True)
    """

    def __init__(self, shape: str = "gauss", n_sources: int = 3, grid: int = 8):
        self.shape = shape
        self.n_sources = n_sources
        self.grid = grid

    def fit(self, x, t) -> "OracleRegressor":
        if self.shape not in SHAPES:
            raise ValueError(f"shape must be one of {sorted(SHAPES)}, got {self.shape!r}")
        n_sources = integer("n_sources", self.n_sources)
        grid = integer("grid", self.grid, minimum=n_sources)
        x, t = self._inputs(x, t)
        start = time.perf_counter()
        starts = itertools.combinations(start_grid(grid, XS_MIN, XS_MAX), n_sources)
        best = fit_sources(x, t, self.shape, list(starts), XS_MIN, XS_MAX)
        self.network_ = best.curve
        self.cost_ = 0.5 * float(best.residuals @ best.residuals)
        self.n_starts_ = best.n_starts
        self.fit_seconds_ = time.perf_counter() - start
        return self
