"""One curve for both directions of motion, or one per direction (the asymmetric model).

``fit_directions`` fits the eq. (9) data of a sweep either folded (the symmetric model of the
paper) or split by the sign of v, each direction with its own B, v_sat, scaling and network
(a fresh copy of the given estimator, so any network kind). Unless told which, it chooses by
K-fold cross-validation of the force in newtons on held-out rows: the asymmetric model must
beat the symmetric one in every sense of the paired fold differences (mean gain above two
standard errors and above CV_MARGIN of the error), so data of a symmetric axis keep the
simpler model.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional, Tuple

import numpy as np

from ..data import MIN_ROWS, Dataset, Sweep, estimate_vs_max, prepare
from ..errors import DataError
from ..model import Direction
from .base import as_rng

#: Folds of the cross-validation that chooses between the models.
CV_FOLDS = 5
#: Training points per direction in a cross-validation fit (binned as ``prepare`` does).
CV_POINTS = 512
#: The asymmetric model's mean gain must exceed this fraction of the symmetric model's error.
CV_MARGIN = 0.01
#: ... and this many standard errors of the paired fold differences.
CV_SIGMAS = 2.0


def clone(estimator):
    """A fresh, unfitted estimator with the hyperparameters of ``estimator``."""
    return type(estimator)(**estimator.get_params())


@dataclass(frozen=True)
class FittedDirection:
    """One fitted curve: the curve, its eq. (9) data and the fitted estimator."""

    curve: Direction
    dataset: Dataset
    estimator: object


@dataclass(frozen=True)
class DirectionsFit:
    """The fitted curves ((both) or (positive, negative)) and how the choice was made."""

    fits: Tuple[FittedDirection, ...]
    chosen_by: str                      # "forced", "cross-validation" or "one direction only"
    cv_rmse: Optional[Tuple[float, float]] = None   # (symmetric, asymmetric), N

    @property
    def asymmetric(self) -> bool:
        return len(self.fits) == 2


def _vs_max(sweep: Sweep, vs_max: Optional[float]) -> float:
    return vs_max if vs_max is not None else estimate_vs_max(sweep.folded())


def _fit(sweep: Sweep, estimator, vs_max: Optional[float],
         max_points: Optional[int] = None, estimated: bool = False) -> FittedDirection:
    """The curve fitted to ``sweep`` (folded) by a fresh copy of ``estimator``; ``estimated``:
    ``vs_max`` is an estimate from the data (so the dataset says, as ``prepare`` does)."""
    kwargs = {} if max_points is None else {"max_points": max_points}
    dataset = prepare(sweep, vs_max=vs_max, **kwargs)
    if estimated:
        dataset = replace(dataset, vs_max_estimated=True)
    fitted = clone(estimator)
    return FittedDirection(Direction.fit(dataset, fitted), dataset, fitted)


def cross_validate(sweep: Sweep, estimator, vs_max: Tuple[float, float, float],
                   folds: int = CV_FOLDS, seed=0) -> np.ndarray:
    """Held-out mean squared force errors (N^2) per fold: row 0 the symmetric model, row 1
    the asymmetric one (each curve a fresh copy of ``estimator``). ``vs_max`` holds (both,
    positive, negative)."""
    moving = sweep.v != 0
    v, f = sweep.v[moving], sweep.f[moving]
    fold = as_rng(seed).permutation(v.size) % folds
    mse = np.zeros((2, folds))
    for k in range(folds):
        train, test = Sweep(v[fold != k], f[fold != k]), fold == k
        both = _fit(train, estimator, vs_max[0], CV_POINTS).curve
        pos = _fit(train.direction(1), estimator, vs_max[1], CV_POINTS).curve
        neg = _fit(train.direction(-1), estimator, vs_max[2], CV_POINTS).curve
        sign, speed, target = np.sign(v[test]), np.abs(v[test]), np.sign(v[test]) * f[test]
        mse[0, k] = np.mean((both.magnitude(speed) - target) ** 2)
        asym = np.where(sign > 0, pos.magnitude(speed), neg.magnitude(speed))
        mse[1, k] = np.mean((asym - target) ** 2)
    return mse


def prefers_asymmetric(mse: np.ndarray) -> bool:
    """Whether the paired fold differences favour the asymmetric model (see the module)."""
    gain = mse[0] - mse[1]
    se = gain.std(ddof=1) / np.sqrt(gain.size)
    return bool(gain.mean() > CV_SIGMAS * se and gain.mean() > CV_MARGIN * mse[0].mean())


def _direction_vs_max(half: Sweep, sweep: Sweep, vs_max: Optional[float]) -> float:
    """The vs_max of one direction: ``vs_max`` if given, else the direction's own estimate when
    its training set can be built with it, else the estimate of both directions folded."""
    if vs_max is not None:
        return vs_max
    own = _vs_max(half, None)
    try:
        prepare(half, vs_max=own, max_points=CV_POINTS)
        return own
    except DataError:
        return _vs_max(sweep, None)


def fit_directions(sweep: Sweep, estimator, vs_max: Optional[float] = None,
                   asymmetric: Optional[bool] = None, seed=0) -> DirectionsFit:
    """Fit one curve (symmetric) or two (asymmetric, each by its own copy of ``estimator``, so
    the default chooses its model per direction); ``asymmetric`` None chooses by
    cross-validation, True or False forces the model. With data in one direction only the model
    is symmetric (``DataError`` if the asymmetric one was asked for); when a sweep of both
    directions cannot give each its own curve, ``chosen_by`` says why."""
    halves = (sweep.direction(1), sweep.direction(-1))
    if asymmetric is not False:
        one_direction = any(len(half) == 0 for half in halves)
        try:
            for half, side in zip(halves, ("v > 0", "v < 0")):
                if len(half) < MIN_ROWS:
                    raise DataError(f"{len(half)} rows with {side}, need at least {MIN_ROWS}")
            vs_dirs = [_direction_vs_max(half, sweep, vs_max) for half in halves]
            for half, vs in zip(halves, vs_dirs):
                prepare(half, vs_max=vs, max_points=CV_POINTS)
        except DataError as exc:
            if asymmetric:
                raise DataError(f"an asymmetric model needs a sweep of each direction: {exc}") from None
            reason = "one direction only" if one_direction else f"asymmetric model not fittable: {exc}"
            return DirectionsFit((_fit(sweep, estimator, vs_max),), reason)
    if asymmetric is None:
        mse = cross_validate(sweep, estimator, (_vs_max(sweep, vs_max), *vs_dirs), seed=seed)
        cv = tuple(float(np.sqrt(m)) for m in mse.mean(axis=1))
        if not prefers_asymmetric(mse):
            return DirectionsFit((_fit(sweep, estimator, vs_max),), "cross-validation", cv)
        return DirectionsFit(_fit_halves(halves, estimator, vs_dirs, vs_max), "cross-validation", cv)
    if not asymmetric:
        return DirectionsFit((_fit(sweep, estimator, vs_max),), "forced")
    return DirectionsFit(_fit_halves(halves, estimator, vs_dirs, vs_max), "forced")


def _fit_halves(halves, estimator, vs_dirs, vs_max: Optional[float]) -> Tuple[FittedDirection, ...]:
    """The curves of the two directions, each with its vs_max (estimated unless ``vs_max``)."""
    return tuple(_fit(h, estimator, vs, estimated=vs_max is None) for h, vs in zip(halves, vs_dirs))
