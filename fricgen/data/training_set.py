"""From a sweep to the eq. (9) training set: B identification, vs_max, normalization."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from .._validate import float32_scale
from ..errors import DataError
from ..model import Scaling
from .outliers import OUTLIER_SIGMAS, gross_outliers, robust_scale
from .sweep import MIN_ROWS, Sweep

#: Fewest high-speed rows (|v| > v_sat) the regression for B needs.
MIN_HIGH_SPEED_ROWS = 5
#: v_sat = SAT_FACTOR * vs_max: beyond it g(v, v_s) ~ 0 and eq. (3) saturates the network input.
SAT_FACTOR = 3.0
#: Rows in [0, v_sat] beyond which the training set is binned (``bin_equal_counts``).
MAX_TRAINING_POINTS = 4096


def _theil_sen(v: np.ndarray, f: np.ndarray, most: int = 400) -> Tuple[float, float]:
    """A line through (v, f) that gross outliers cannot move: the median of pairwise slopes
    over at most ``most`` rows spread over the velocity order, and the median intercept."""
    order = np.argsort(v)
    pick = order[np.unique(np.linspace(0, v.size - 1, min(most, v.size)).astype(int))]
    dv = v[pick][:, None] - v[pick][None, :]
    df = f[pick][:, None] - f[pick][None, :]
    with np.errstate(invalid="ignore", over="ignore"):
        slopes = (df / dv)[np.triu(dv != 0, 1)]
    slope = float(np.median(slopes[np.isfinite(slopes)])) if np.isfinite(slopes).any() else 0.0
    with np.errstate(over="ignore", invalid="ignore"):
        return slope, float(np.median(f - slope * v))


def identify_viscous(high: Sweep) -> Tuple[float, float, int]:
    """B and the intercept of the line f = F0 + B v through high-speed folded data (section 2),
    and the number of rows rejected as gross outliers.

    Rows whose residual from a robust (Theil-Sen) line exceeds OUTLIER_SIGMAS robust standard
    deviations (1.4826 MAD) are dropped; least squares on the others gives B, in the centred and
    scaled speed (v - mean) / sd, so that any unit of v and f gives the same line. Bounded
    noise, such as the benchmark's, is never rejected (its largest residual is under 1.4
    robust sd)."""
    if len(high) < MIN_HIGH_SPEED_ROWS:
        raise DataError(f"no high-speed data for B: {len(high)} rows beyond v_sat, "
                        f"need at least {MIN_HIGH_SPEED_ROWS}")
    if np.ptp(high.v) <= 0:
        raise DataError("high-speed data for B spans no velocity range")
    slope, intercept = _theil_sen(high.v, high.f)
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


def check_float32_scale(what: str, value: float, unit: str) -> None:
    """``DataError`` unless |value| lies where the emitted float32 C computes reliably."""
    float32_scale(what, value, unit, "rescale the data's units", DataError)


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
    if np.ptp(v[fast]) <= 0:
        raise DataError(f"the fastest quarter of the data is all at one speed ({v[-1]:.6g} m/s): "
                        "cannot estimate vs_max; pass --vs-max, or sweep a range of speeds")
    coef = np.polyfit(v[fast], f[fast], 1)
    resid = f - np.polyval(coef, v)
    sigma = max(np.std(resid[fast]), 1e-12 * float(np.median(np.abs(f))))   # noise-free data
    edges = np.quantile(v, np.linspace(0.0, 0.75, 16))
    edge = edges[1]
    starts = np.searchsorted(v, edges)          # v is sorted: bin [lo, hi) is one slice of it
    for lo, hi, k0, k1 in zip(edges[:-1], edges[1:], starts[:-1], starts[1:]):
        if k1 - k0 >= 3 and resid[k0:k1].mean() > 3 * sigma / np.sqrt(k1 - k0):
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
    n_outliers: int = 0
    #: Rows in [0, v_sat] before binning (x.size - 2 when the sweep was not binned).
    n_rows: int = 0

    @property
    def binned(self) -> bool:
        """Whether the rows in [0, v_sat] were averaged into MAX_TRAINING_POINTS bins."""
        return self.n_rows > self.x.size - 2

    def targets(self, v, f) -> Tuple[np.ndarray, np.ndarray]:
        """Eq. (9) applied to other (folded) data: (K_in v, K_out (f - B v))."""
        v = np.asarray(v, dtype=float)
        return self.scaling.k_in * v, self.scaling.k_out * (np.asarray(f, dtype=float) - self.viscous * v)


def prepare(sweep: Sweep, vs_max: Optional[float] = None, f_sat: Optional[float] = None,
            viscous: Optional[float] = None, max_points: int = MAX_TRAINING_POINTS,
            independence: float = 1.0) -> Dataset:
    """Turn a sweep into the eq. (9) training set of section 2.

    The sweep is folded (symmetric model). Rows with |v| > v_sat = 3 vs_max identify B by linear
    regression (unless ``viscous`` is given); rows within [0, v_sat] become training data, with
    the two added points (0, mean force of the four slowest rows) and (v_sat, f_sat), where f_sat
    defaults to the high-speed line evaluated at v_sat. K_in = 1/v_sat, K_out = 1/max(t) over
    the points that are no gross outliers (``fricgen.data.outliers``), which the default
    estimator sets aside.
    Beyond ``max_points`` rows in [0, v_sat] the rows are binned (``bin_equal_counts``), and
    into as many bins as independent samples when a row is only ``independence`` of one (a
    smoothed log's rows): each training point then stands for one sample, as eq. (9)'s fits
    and their cross-validations assume.
    """
    if vs_max is not None and not (np.isfinite(vs_max) and vs_max > 0):
        raise DataError(f"vs_max must be > 0, got {vs_max}")
    if len(sweep) < MIN_ROWS:
        raise DataError(f"sweep has {len(sweep)} rows, need at least {MIN_ROWS}")
    folded = sweep.folded()
    if len(folded) < MIN_ROWS:
        raise DataError(f"{len(folded)} rows with v != 0, need at least {MIN_ROWS}: a friction "
                        "sweep needs motion")
    if np.count_nonzero(folded.f < 0) > folded.f.size / 2:
        raise DataError("the force has the opposite sign of v in most rows, yet friction acts "
                        "with the sign of v (eq. 1): check the sign of v, force or i (or --scale)")
    check_float32_scale("the sweep's median speed", float(np.median(folded.v)), "m/s")
    check_float32_scale("the sweep's median force", float(np.median(np.abs(folded.f))) or 1.0, "N")
    estimated = vs_max is None
    if estimated:
        vs_max = estimate_vs_max(folded)
        try:
            return _prepare(folded, vs_max, f_sat, viscous, max_points, estimated, independence)
        except DataError as exc:
            raise DataError(f"{exc} (with vs_max estimated as {vs_max:.4g} m/s; pass --vs-max to "
                            "set it)") from None
    return _prepare(folded, vs_max, f_sat, viscous, max_points, estimated, independence)


def _prepare(folded: Sweep, vs_max: float, f_sat, viscous, max_points: int, estimated: bool,
             independence: float = 1.0) -> Dataset:
    """``prepare`` of the folded sweep once vs_max is known."""
    v_sat = SAT_FACTOR * vs_max
    high = Sweep(folded.v[folded.v > v_sat], folded.f[folded.v > v_sat])
    low = Sweep(folded.v[folded.v <= v_sat], folded.f[folded.v <= v_sat])
    n_outliers = 0
    if viscous is None:
        viscous, f0, n_outliers = identify_viscous(high)
    else:
        f0 = float(np.mean(high.f - viscous * high.v)) if len(high) else None
    if len(low) < MIN_ROWS:
        raise DataError(f"{len(low)} rows within [0, v_sat = {v_sat:g}], need at least {MIN_ROWS}")
    if f_sat is None:
        if f0 is None:
            raise DataError("no high-speed data to anchor the force at v_sat")
        f_sat = f0 + viscous * v_sat
    n_rows = len(low)
    bins = min(max_points, max(MIN_ROWS, int(n_rows * independence)))
    slowest = np.argsort(low.v)[:4] if n_rows <= bins else None   # binned: low.f[0] instead
    low = bin_equal_counts(low, bins)
    v = np.concatenate([[0.0], low.v, [v_sat]])
    f = np.concatenate([[low.f[slowest].mean() if n_rows == len(low) else low.f[0]], low.f, [f_sat]])
    k_in = 1.0 / v_sat
    t_raw = f - viscous * v
    peak = np.max(t_raw[~gross_outliers(v, t_raw)])         # a spike must not set the scale
    if not peak > 0:
        raise DataError("friction minus viscous part is never positive: not a friction sweep")
    check_float32_scale("v_sat", v_sat, "m/s")
    check_float32_scale("the friction force scale", peak, "N")
    if viscous != 0:
        check_float32_scale("the viscous coefficient B", viscous, "N s/m")
    scaling = Scaling(k_in=float(k_in), k_out=float(1.0 / peak))
    return Dataset(x=k_in * v, t=scaling.k_out * t_raw, scaling=scaling, viscous=float(viscous),
                   v_sat=float(v_sat), vs_max_estimated=estimated, n_high_speed=len(high),
                   n_outliers=n_outliers, n_rows=n_rows)
