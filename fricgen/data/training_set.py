"""From a sweep to the [F9] training set: B identification, vs_max, normalization."""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional, Tuple, Union

import numpy as np

from .._validate import float32_scale
from ..errors import DataError
from ..model import Scaling
from .outliers import gross_outliers
from .stribeck_range import StribeckRange, choose_vs_max
from .sweep import MIN_ROWS, Sweep
from .viscous import (MIN_HIGH_SPEED_ROWS, SAT_FACTOR, bin_equal_counts,  # noqa: F401 (re-exported)
                      identify_viscous)

#: Rows in [0, v_sat] beyond which the training set is binned (``bin_equal_counts``).
MAX_TRAINING_POINTS = 4096


def check_float32_scale(what: str, value: float, unit: str) -> None:
    """``DataError`` unless |value| lies where the emitted float32 C computes reliably."""
    float32_scale(what, value, unit, "rescale the data's units", DataError)


@dataclass(frozen=True)
class Dataset:
    r"""Normalized training data of [F9] with what [F3] needs to rebuild forces (``prepare``).

    Parameters
    ----------
    x : ndarray
        x = K_in v, in [0, 1] (dimensionless).
    t : ndarray
        t = K_out (F - B v), at most 1 outside gross outliers (dimensionless).
    scaling : Scaling
        K_in (s/m) and K_out (1/N).
    viscous : float
        The identified B (N s/m).
    v_sat : float
        3 vs_max (m/s): where the network input saturates in [F3].
    n_high_speed : int
        Rows beyond v_sat (the regression of B).
    n_outliers : int
        High-speed rows rejected as gross outliers.
    n_rows : int
        Rows in [0, v_sat] before binning.
    stribeck_range : StribeckRange, optional
        How vs_max was chosen when not given, else None.

    Notes
    -----
    .. math::

        (x_i, t_i) = (K_{in} v_i,\ K_{out} (\hat F_F(v_i) - B v_i)) \quad (9)

    Examples
    --------
    >>> import fricgen
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> float(data.x.max()), float(data.t.max()), round(data.viscous)
    (1.0, 1.0, 57)
    """

    x: np.ndarray
    t: np.ndarray
    scaling: Scaling
    viscous: float
    v_sat: float
    n_high_speed: int = 0
    n_outliers: int = 0
    #: Rows in [0, v_sat] before binning (x.size - 2 when the sweep was not binned).
    n_rows: int = 0
    #: How vs_max was chosen when not given (``choose_vs_max``), else None.
    stribeck_range: Optional[StribeckRange] = None

    @property
    def vs_max_estimated(self) -> bool:
        """Whether vs_max was chosen from the data (not given)."""
        return self.stribeck_range is not None

    @property
    def binned(self) -> bool:
        """Whether the rows in [0, v_sat] were averaged into MAX_TRAINING_POINTS bins."""
        return self.n_rows > self.x.size - 2

    def targets(self, v, f) -> Tuple[np.ndarray, np.ndarray]:
        """[F9] applied to other (folded) data: (K_in v, K_out (f - B v))."""
        v = np.asarray(v, dtype=float)
        return self.scaling.k_in * v, self.scaling.k_out * (np.asarray(f, dtype=float) - self.viscous * v)


def check_friction_sign(folded: Sweep) -> None:
    """``DataError`` when the folded force (sgn(v) f) is negative in most rows."""
    if np.count_nonzero(folded.f < 0) > folded.f.size / 2:
        raise DataError("the force has the opposite sign of v in most rows, yet friction acts "
                        "with the sign of v [F1]: check the sign of v, force or i (or --scale)")


def magnitudes_hint(sweep: Sweep) -> str:
    """Where a sweep of both directions has a force of one sign at every moving point (as a
    spreadsheet writes magnitudes), the words a refusal adds to ask whether the forces at v < 0
    are magnitudes; else "". A load beside the friction gives the same signs (a vertical axis),
    so this is said only where the sweep is refused for holding no friction."""
    moving = sweep.f[sweep.v != 0]
    if not (np.any(sweep.v > 0) and np.any(sweep.v < 0)) or not (np.all(moving > 0) or np.all(moving < 0)):
        return ""
    return "; or are the forces at v < 0 magnitudes, where friction opposes the motion and is negative"


#: The median relative difference of the forces at a speed a sweep holds more than once beyond
#: which its passes are said to disagree (a drift between passes stays within it).
REPEAT_SPREAD = 0.1
#: The fewest speeds held more than once in a direction for that to be said.
REPEATED_SPEEDS = 3


def repeated_speeds_note(sweep: Sweep, units) -> str:
    """Where a direction of a sweep holds REPEATED_SPEEDS speeds or more more than once and
    their forces differ by a median REPEAT_SPREAD of their level or more, the warning that says
    so; else "". Both directions written as magnitudes read as one direction with every speed
    twice: a new user's sweep (10 and 14 N forward, 7 and 10 N back) trained one curve
    between the two, 100 of the points' own standard errors from each, with no word."""
    for sign in (1, -1):
        v, f = sweep.v[np.sign(sweep.v) == sign], np.abs(sweep.f[np.sign(sweep.v) == sign])
        speeds, index, counts = np.unique(v, return_inverse=True, return_counts=True)
        repeated = np.flatnonzero(counts > 1)
        if repeated.size < REPEATED_SPEEDS:
            continue
        low = np.array([f[index == k].min() for k in repeated])
        high = np.array([f[index == k].max() for k in repeated])
        relative = float(np.median((high - low) / np.maximum(high, np.finfo(float).tiny)))
        if relative >= REPEAT_SPREAD:
            return (f"warning: the sweep holds {repeated.size} speeds {'v > 0' if sign > 0 else 'v < 0'} more "
                    f"than once, their forces a median {relative:.0%} apart (up to "
                    f"{float(np.max(high - low)):.3g} {units.force}): one curve is fitted between them. Two "
                    "passes that disagree, or both directions written as magnitudes (then give v "
                    "and f at v < 0 their sign)?")
    return ""


def checked_fold(sweep: Sweep) -> Sweep:
    """The folded sweep, if it can be friction data at all; else ``DataError``: too few rows or
    moving rows, a force against the motion, or speeds or forces beyond the float32 C."""
    if len(sweep) < MIN_ROWS:
        raise DataError(f"sweep has {len(sweep)} rows, need at least {MIN_ROWS}")
    folded = sweep.folded()
    if len(folded) < MIN_ROWS:
        raise DataError(f"{len(folded)} rows with v != 0, need at least {MIN_ROWS}: a friction "
                        "sweep needs motion")
    check_friction_sign(folded)
    check_float32_scale("the sweep's median speed", float(np.median(folded.v)), "m/s")
    check_float32_scale("the sweep's median force", float(np.median(np.abs(folded.f))) or 1.0, "N")
    return folded


def prepare(sweep: Sweep, vs_max: Union[None, float, StribeckRange] = None, f_sat: Optional[float] = None,
            viscous: Optional[float] = None, max_points: int = MAX_TRAINING_POINTS,
            folds=None, independence: float = 1.0) -> Dataset:
    """Turn a sweep into the [F9] training set of section 2.

    The sweep is folded (symmetric model). Rows with |v| > v_sat = 3 vs_max identify B by linear
    regression (unless ``viscous`` is given); rows within [0, v_sat] become training data, with the
    two added points (0, mean force of the four slowest rows less their B v: the curve less its
    viscous line held flat from them to rest) and (v_sat, f_sat). K_in = 1/v_sat,
    K_out = 1/max(t) over the points that are no gross outliers. Without ``vs_max`` it is chosen by
    cross-validation (``choose_vs_max``); where the data have no linear high-speed region, B is
    fitted with the rest and v_sat is the fastest speed.

    Parameters
    ----------
    sweep : Sweep
        The measured sweep (any sign of v).
    vs_max : float or StribeckRange, optional
        v_smax (m/s), or a choice made before; None: chosen from the data.
    f_sat : float, optional
        The force at v_sat (N); default: the high-speed line there.
    viscous : float, optional
        B (N s/m); default: identified from the rows beyond v_sat.
    max_points : int
        Beyond so many rows in [0, v_sat] the rows are averaged into equal-count bins.
    folds : array_like of int, optional
        The cross-validation fold of each moving row for ``choose_vs_max``.
    independence : float
        The fraction of an independent sample each row is (a smoothed log's rows are less than
        one): binned into as many points as independent samples.

    Returns
    -------
    Dataset
        ``DataError`` when the sweep cannot be friction data.

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.data import prepare
    >>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
    >>> data = prepare(sweep, vs_max=0.02)
    >>> round(data.v_sat, 3), round(data.viscous), data.x.shape
    (0.06, 57, (202,))
    """
    chosen = vs_max if isinstance(vs_max, StribeckRange) else None
    vs_max = None if chosen else vs_max
    if vs_max is not None and not (np.isfinite(vs_max) and vs_max > 0):
        raise DataError(f"vs_max must be > 0, got {vs_max}")
    folded = checked_fold(sweep)
    if vs_max is not None:
        return _prepare(folded, vs_max, f_sat, viscous, max_points, independence)
    if chosen is None:
        if np.ptp(folded.v) <= 0:
            raise DataError(f"the data are all at one speed ({folded.v[0]:.6g} m/s): cannot "
                            "choose vs_max; pass --vs-max, or sweep a range of speeds")
        chosen = choose_vs_max(folded, folds)
    if not chosen.linear_region:
        viscous = chosen.viscous if viscous is None else viscous
        f_sat = chosen.f_sat if f_sat is None else f_sat
    try:
        dataset = _prepare(folded, chosen.vs_max, f_sat, viscous, max_points, independence)
    except DataError as exc:
        raise DataError(f"{exc} (with vs_max chosen as {chosen.vs_max:.4g} m/s; pass --vs-max to "
                        "set it)") from None
    return replace(dataset, stribeck_range=chosen)


def _prepare(folded: Sweep, vs_max: float, f_sat, viscous, max_points: int,
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
    rest = (low.f[slowest] - viscous * low.v[slowest]).mean() if n_rows == len(low) else \
        low.f[0] - viscous * low.v[0]           # at v = 0: no B v of the slowest rows' speed
    f = np.concatenate([[rest], low.f, [f_sat]])
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
                   v_sat=float(v_sat), n_high_speed=len(high),
                   n_outliers=n_outliers, n_rows=n_rows)
