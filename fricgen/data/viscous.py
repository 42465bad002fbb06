"""The viscous coefficient B from the high-speed rows of a folded sweep (section 2), and the
binning of many rows into means of equal counts."""
from __future__ import annotations

import numpy as np

from ..errors import DataError
from .outliers import OUTLIER_SIGMAS, robust_scale, theil_sen
from .sweep import Sweep

#: Fewest high-speed rows (|v| > v_sat) the regression for B needs.
MIN_HIGH_SPEED_ROWS = 5
#: v_sat = SAT_FACTOR * vs_max: beyond it g(v, v_s) ~ 0 and [F3] saturates the network input.
SAT_FACTOR = 3.0


def identify_viscous(high: Sweep) -> Tuple[float, float, int]:
    """B and the intercept of the line f = F0 + B v through high-speed folded data (section 2), and
    the number of rows rejected as gross outliers.

    Rows whose residual from a robust (Theil-Sen) line exceeds OUTLIER_SIGMAS robust standard
    deviations (1.4826 MAD) are dropped; least squares on the others gives B. Bounded noise, such
    as the benchmark's, is never rejected.

    Parameters
    ----------
    high : Sweep
        Folded rows beyond v_sat (at least MIN_HIGH_SPEED_ROWS, over a range of speeds).

    Returns
    -------
    viscous : float
        B (N s/m).
    intercept : float
        F0 (N), the sum of the Coulomb forces f_ck where g is ~0.
    n_outliers : int
        Rows rejected.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import Sweep
    >>> from fricgen.data import identify_viscous
    >>> v = np.linspace(0.1, 0.2, 20)
    >>> B, f0, rejected = identify_viscous(Sweep(v, 15.0 + 57.5 * v))
    >>> round(B, 1), round(f0, 1), rejected
    (57.5, 15.0, 0)
    """
    if len(high) < MIN_HIGH_SPEED_ROWS:
        raise DataError(f"no high-speed data for B: {len(high)} rows beyond v_sat, "
                        f"need at least {MIN_HIGH_SPEED_ROWS}")
    if np.ptp(high.v) <= 0:
        raise DataError("high-speed data for B spans no velocity range")
    slope, intercept = theil_sen(high.v, high.f)
    with np.errstate(over="ignore", invalid="ignore"):
        residual = np.abs(high.f - intercept - slope * high.v)
    scale = robust_scale(residual, high.f)
    keep = np.isfinite(residual) & (residual <= OUTLIER_SIGMAS * scale) if scale > 0 \
        else np.isfinite(residual)
    if keep.sum() < MIN_HIGH_SPEED_ROWS or np.ptp(high.v[keep]) <= 0:
        raise DataError(f"high-speed data for B: only {int(keep.sum())} of {len(high)} rows "
                        "lie on a line")
    v = high.v[keep]
    centre, spread = float(np.mean(v)), float(np.std(v))
    A = np.column_stack([np.ones(v.size), (v - centre) / spread])
    (mean_f, slope), *_ = np.linalg.lstsq(A, high.f[keep], rcond=None)
    B = slope / spread
    return float(B), float(mean_f - B * centre), int(len(high) - keep.sum())


def viscous_se(high: Sweep, viscous: float, independence: float = 1.0) -> float:
    """The standard error (N s/m) of the slope B of the line through the high-speed folded rows
    ``high`` (least squares, as ``identify_viscous``), each row ``independence`` of an
    independent sample (a smoothed log's); NaN with fewer than MIN_HIGH_SPEED_ROWS rows."""
    if len(high) < MIN_HIGH_SPEED_ROWS or np.ptp(high.v) <= 0:
        return float("nan")
    residual = high.f - viscous * high.v
    residual = residual - residual.mean()
    n = len(high) * independence
    spread = float(np.sum((high.v - high.v.mean()) ** 2)) * independence
    return float(np.sqrt(np.sum(residual ** 2) * independence / max(n - 2, 1) / spread))


def bin_equal_counts(sweep: Sweep, bins: int) -> Sweep:
    """``sweep`` itself if it has at most ``bins`` rows; else the means of v and f over
    ``bins`` groups of consecutive speeds with equal counts (+-1).

    Equal counts keep the least-squares objective of the full data (each bin mean stands for
    the same number of rows), and each mean carries sqrt(count) times less noise. Within a bin
    the curve is nearly linear: the averaging bias, f'' w^2 / 24 for a bin of width w, is far
    below the noise for the bins of a dense sweep."""
    if len(sweep) <= bins:
        return sweep
    order = np.argsort(sweep.v, kind="stable")
    starts = np.linspace(0, len(sweep), bins + 1).astype(int)[:-1]
    counts = np.diff(np.append(starts, len(sweep)))
    return Sweep(np.add.reduceat(sweep.v[order], starts) / counts,
                 np.add.reduceat(sweep.f[order], starts) / counts)
