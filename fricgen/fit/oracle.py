"""The honest oracle: eq. (1) itself, with the true shape and number of sources, fitted to the
data; the best any method can do on a benchmark whose friction is known.

In the normalized coordinates of eq. (9), with B identified from the high-speed rows like every
other estimator, eq. (1) reads t(x) = c + sum_k a_k g(x, xs_k): nothing else is fitted (no
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
    """Variable projection of eq. (1) with ``n_sources`` sources of ``shape``, from every
    ``n_sources``-subset of ``grid`` log-spaced Stribeck velocities.

    After ``fit``: ``network_`` (a ``StribeckCurve``), ``cost_`` (half the residual sum of
    squares), ``n_starts_``, ``fit_seconds_``.
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
