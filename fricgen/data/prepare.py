"""From a sweep to the eq. (9) training set: B identification, vs_max, normalization."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from ..errors import DataError
from ..model import Scaling
from .sweep import MIN_ROWS, Sweep

#: Fewest high-speed rows (|v| > v_sat) the regression for B needs.
MIN_HIGH_SPEED_ROWS = 5
#: v_sat = SAT_FACTOR * vs_max: beyond it g(v, v_s) ~ 0 and eq. (3) saturates the network input.
SAT_FACTOR = 3.0


def identify_viscous(high: Sweep) -> Tuple[float, float]:
    """B and the intercept of the line f = F0 + B v through high-speed folded data (section 2)."""
    if len(high) < MIN_HIGH_SPEED_ROWS:
        raise DataError(f"no high-speed data for B: {len(high)} rows beyond v_sat, "
                        f"need at least {MIN_HIGH_SPEED_ROWS}")
    if np.ptp(high.v) <= 0:
        raise DataError("high-speed data for B spans no velocity range")
    A = np.column_stack([np.ones_like(high.v), high.v])
    (f0, B), *_ = np.linalg.lstsq(A, high.f, rcond=None)
    return float(B), float(f0)


def estimate_vs_max(folded: Sweep) -> float:
    """Estimate vs_max from a folded sweep when the user gives none.

    A line is fitted to the fastest quarter of the data (assumed free of the Stribeck effect);
    the excess force over that line is averaged in velocity bins, and the fastest bin whose
    excess still stands 3 standard errors above zero marks the end of the Stribeck region.
    Eq. (2) shapes have fallen to a few percent at 2 v_s, so vs_max is taken as half that edge.
    """
    order = np.argsort(folded.v)
    v, f = folded.v[order], folded.f[order]
    fast = v >= np.quantile(v, 0.75)
    if fast.sum() < MIN_HIGH_SPEED_ROWS:
        raise DataError("too few data to estimate vs_max; pass --vs-max")
    coef = np.polyfit(v[fast], f[fast], 1)
    resid = f - np.polyval(coef, v)
    sigma = max(np.std(resid[fast]), 1e-12)
    edges = np.quantile(v, np.linspace(0.0, 0.75, 16))
    edge = edges[1]
    for lo, hi in zip(edges[:-1], edges[1:]):
        inside = (v >= lo) & (v < hi)
        if inside.sum() >= 3 and resid[inside].mean() > 3 * sigma / np.sqrt(inside.sum()):
            edge = hi
    return float(edge / 2.0)


@dataclass(frozen=True)
class Dataset:
    """Normalized training data of eq. (9) with what eq. (3) needs to rebuild forces."""

    x: np.ndarray
    t: np.ndarray
    scaling: Scaling
    viscous: float
    v_sat: float
    vs_max_estimated: bool = False
    n_high_speed: int = 0

    def targets(self, v, f) -> Tuple[np.ndarray, np.ndarray]:
        """Eq. (9) applied to other (folded) data: (K_in v, K_out (f - B v))."""
        v = np.asarray(v, dtype=float)
        return self.scaling.k_in * v, self.scaling.k_out * (np.asarray(f, dtype=float) - self.viscous * v)


def prepare(sweep: Sweep, vs_max: Optional[float] = None, f_sat: Optional[float] = None,
            viscous: Optional[float] = None) -> Dataset:
    """Turn a sweep into the eq. (9) training set of section 2.

    The sweep is folded (symmetric model). Rows with |v| > v_sat = 3 vs_max identify B by linear
    regression (unless ``viscous`` is given); rows within [0, v_sat] become training data, with
    the two added points (0, mean force of the four slowest rows) and (v_sat, f_sat), where f_sat
    defaults to the high-speed line evaluated at v_sat. K_in = 1/v_sat, K_out = 1/max(t).
    """
    if vs_max is not None and not (np.isfinite(vs_max) and vs_max > 0):
        raise DataError(f"vs_max must be > 0, got {vs_max}")
    if len(sweep) < MIN_ROWS:
        raise DataError(f"sweep has {len(sweep)} rows, need at least {MIN_ROWS}")
    folded = sweep.folded()
    estimated = vs_max is None
    if estimated:
        vs_max = estimate_vs_max(folded)
    v_sat = SAT_FACTOR * vs_max
    high = Sweep(folded.v[folded.v > v_sat], folded.f[folded.v > v_sat])
    low = Sweep(folded.v[folded.v <= v_sat], folded.f[folded.v <= v_sat])
    if viscous is None:
        viscous, f0 = identify_viscous(high)
    else:
        f0 = float(np.mean(high.f - viscous * high.v)) if len(high) else None
    if len(low) < MIN_ROWS:
        raise DataError(f"{len(low)} rows within [0, v_sat = {v_sat:g}], need at least {MIN_ROWS}")
    if f_sat is None:
        if f0 is None:
            raise DataError("no high-speed data to anchor the force at v_sat")
        f_sat = f0 + viscous * v_sat
    slowest = np.argsort(low.v)[:4]
    v = np.concatenate([[0.0], low.v, [v_sat]])
    f = np.concatenate([[low.f[slowest].mean()], low.f, [f_sat]])
    k_in = 1.0 / v_sat
    t_raw = f - viscous * v
    peak = np.max(t_raw)
    if not peak > 0:
        raise DataError("friction minus viscous part is never positive: not a friction sweep")
    scaling = Scaling(k_in=float(k_in), k_out=float(1.0 / peak))
    return Dataset(x=k_in * v, t=scaling.k_out * t_raw, scaling=scaling, viscous=float(viscous),
                   v_sat=float(v_sat), vs_max_estimated=estimated, n_high_speed=len(high))
