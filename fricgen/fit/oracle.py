"""The oracle: eq. (1) itself fitted to the data, the best any method can do with the benchmark.

In the normalized coordinates of eq. (9), eq. (1) with S sources of a known shape g reads
t(x) = c + sum_k a_k g(x, xs_k) + d x: linear in (c, a_k, d) (the constant gathers every f_ck,
the slope d absorbs the error of the identified B) and nonlinear in the S Stribeck velocities
xs_k = K_in v_sk. The linear part is eliminated (variable projection) and the xs_k are found by
multi-start nonlinear least squares from every S-subset of a log grid.
"""
from __future__ import annotations

import itertools
import time

import numpy as np
from scipy.optimize import least_squares

from .._validate import integer
from ..friction import SHAPES
from ..networks.stribeck import StribeckCurve
from .base import Estimator


def _basis(shape, x, xs):
    g = SHAPES[shape]
    return np.column_stack([np.ones_like(x)] + [g(x, s) for s in xs] + [x])


class OracleRegressor(Estimator):
    """Multi-start separable least squares of eq. (1) with ``n_sources`` sources of ``shape``.

    ``grid`` Stribeck velocities (normalized, log-spaced in [xs_min, xs_max]) give
    C(grid, n_sources) starts. After ``fit``: ``network_`` (a ``StribeckCurve``), ``cost_``,
    ``n_starts_``, ``fit_seconds_``.
    """

    def __init__(self, shape: str = "gauss", n_sources: int = 3, grid: int = 6,
                 xs_min: float = 0.01, xs_max: float = 1.0):
        self.shape = shape
        self.n_sources = n_sources
        self.grid = grid
        self.xs_min = xs_min
        self.xs_max = xs_max

    def fit(self, x, t) -> "OracleRegressor":
        if self.shape not in SHAPES:
            raise ValueError(f"shape must be one of {sorted(SHAPES)}, got {self.shape!r}")
        integer("n_sources", self.n_sources)
        x, t = self._inputs(x, t)
        start = time.perf_counter()
        lo, hi = np.log(self.xs_min / 10.0), np.log(self.xs_max * 3.0)

        def residual(theta):
            A = _basis(self.shape, x, np.exp(theta))
            coef, *_ = np.linalg.lstsq(A, t, rcond=None)
            return A @ coef - t

        best = None
        grid = np.log(np.geomspace(self.xs_min, self.xs_max, int(self.grid)))
        starts = list(itertools.combinations(grid, int(self.n_sources)))
        for theta0 in starts:
            sol = least_squares(residual, np.array(theta0), bounds=(lo, hi), method="trf")
            if best is None or sol.cost < best.cost:
                best = sol
        xs = np.exp(best.x)
        coef, *_ = np.linalg.lstsq(_basis(self.shape, x, xs), t, rcond=None)
        order = np.argsort(xs)
        self.network_ = StribeckCurve(self.shape, float(coef[0]), coef[1:-1][order], xs[order],
                                    float(coef[-1]))
        self.cost_ = float(best.cost)
        self.n_starts_ = len(starts)
        self.fit_seconds_ = time.perf_counter() - start
        return self
