"""One curve for both directions of motion, or one per direction (the asymmetric model).

``fit_directions`` fits the [F9] data of a sweep either folded (the symmetric model of the
paper) or split by the sign of v, each direction with its own B, v_sat, scaling and network
(a fresh copy of the given estimator, so any network kind). Unless told which, it chooses by
K-fold cross-validation of the force in newtons on held-out rows: the asymmetric model must
beat the symmetric one in every sense of the paired fold comparisons (the mean log ratio of
the fold errors above two standard errors, and the mean gain above CV_MARGIN of the error), so
data of a symmetric axis keep the simpler model. Ratios, not differences: a fold of a log that
holds out a phase of the motion is hard for both models, and its large difference must not
drown the others.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional, Tuple

import numpy as np

from .._progress import Progress
from ..data import MIN_ROWS, Dataset, Sweep, choose_vs_max, prepare
from ..data.training_set import checked_fold
from ..errors import DataError
from ..model import Direction
from .auto import AutoELMRegressor
from .base import as_rng, interleaved_folds
from .default import DefaultRegressor, elm_units, greybox_sources
from .stribeck import StribeckRegressor

#: Folds of the cross-validation that chooses between the models.
CV_FOLDS = 5
#: A log's cross-validation blocks span this many smoothing windows: far beyond the rows that
#: smoothing correlates.
BLOCK_WINDOWS = 10
#: ... and each fold gets at least this many of them (shorter blocks on a short log), so that a
#: fold of a run-up is not one whole range of speeds, which every model would extrapolate to.
BLOCKS_PER_FOLD = 4
#: Training points per direction in a cross-validation fit (binned as ``prepare`` does).
CV_POINTS = 512
#: ``DirectionsFit.chosen_by`` of curves made per direction without cross-validating their
#: symmetry, the textbook laws having already told the directions apart
#: (``law_choice.asymmetry_evident``).
TEXTBOOK_ASYMMETRY = "the textbook laws' asymmetry"
#: The asymmetric model's mean gain must exceed this fraction of the symmetric model's error.
CV_MARGIN = 0.01
#: ... and this many standard errors of the paired fold differences.
CV_SIGMAS = 2.0


def clone(estimator):
    """A fresh, unfitted estimator with the hyperparameters of ``estimator``."""
    return type(estimator)(**estimator.get_params())


@dataclass(frozen=True)
class FittedDirection:
    """One fitted curve: the curve, its [F9] data and the fitted estimator."""

    curve: Direction
    dataset: Dataset
    estimator: object


@dataclass(frozen=True)
class DirectionsFit:
    """The fitted curves ((both) or (positive, negative)) and how the choice was made."""

    fits: Tuple[FittedDirection, ...]
    chosen_by: str      # "forced", "cross-validation [in blocks of time]", "one direction only",
    #                     TEXTBOOK_ASYMMETRY
    cv_rmse: Optional[Tuple[float, float]] = None   # (symmetric, asymmetric), N

    @property
    def asymmetric(self) -> bool:
        return len(self.fits) == 2


def _vs_max(sweep: Sweep, vs_max: Optional[float], blocks: int = 0):
    """``vs_max`` if given, else the choice of ``choose_vs_max`` on the folded sweep (its folds
    from ``interleaved_folds``, or a log's ``blocks`` of time, ``row_folds``), which ``prepare``
    takes in its place."""
    if vs_max is not None:
        return vs_max
    try:
        folded = checked_fold(sweep)
    except DataError:
        return None                     # prepare names the problem
    if np.ptp(folded.v) <= 0:
        return None
    folds = row_folds(len(folded), CV_FOLDS, blocks=blocks) if blocks else \
        interleaved_folds(folded.v, CV_FOLDS)
    return choose_vs_max(folded, folds)


def warm_copy(fitted):
    """An unfitted estimator that repeats ``fitted``'s procedure on data close to its own (a
    fold of them), started from its result where it can be (``warm_copy`` of the default and
    the grey-box), else a fresh copy."""
    return fitted.warm_copy() if hasattr(fitted, "warm_copy") else clone(fitted)


def same_data(a: Dataset, b: Dataset) -> bool:
    """Whether two [F9] training sets are the same points with the same scaling and B."""
    return (a.scaling == b.scaling and a.viscous == b.viscous and a.v_sat == b.v_sat
            and np.array_equal(a.x, b.x) and np.array_equal(a.t, b.t))


def _fit(sweep: Sweep, estimator, vs_max, max_points: Optional[int] = None,
         independence: float = 1.0, fresh=clone,
         done: Optional[FittedDirection] = None) -> FittedDirection:
    """The curve fitted to ``sweep`` (folded) by ``fresh(estimator)``, a fresh copy; ``done``
    itself when it was fitted by the same estimator to the same training set (the
    cross-validation's fit on all rows, when the sweep needed no binning beyond CV_POINTS)."""
    kwargs = {"independence": independence}
    if max_points is not None:
        kwargs["max_points"] = max_points
    dataset = prepare(sweep, vs_max=vs_max, **kwargs)
    if done is not None and same_data(done.dataset, dataset):
        return done
    fitted = fresh(estimator)
    return FittedDirection(Direction.fit(dataset, fitted), dataset, fitted)


def row_folds(n: int, folds: int, seed=0, blocks: int = 0) -> np.ndarray:
    """The fold of each of ``n`` rows: contiguous blocks of ``blocks`` rows dealt to the folds in
    turn (rows in time order, as a log's, whose neighbours share their noise through smoothing;
    many blocks, so that no fold holds out a whole phase of the motion, such as its fastest
    part), or a random partition (``blocks`` 0)."""
    if blocks:
        return (np.arange(n) // max(1, min(int(blocks), n // (BLOCKS_PER_FOLD * folds)))) % folds
    return as_rng(seed).permutation(n) % folds


def cross_validate(sweep: Sweep, estimator, vs_max: Tuple[float, float, float],
                   folds: int = CV_FOLDS, seed=0, per_direction=None, blocks: int = 0,
                   independence: float = 1.0, offset: float = 0.0,
                   progress: Optional[Callable[[str], None]] = None):
    """Held-out mean squared force errors (N^2) per fold (``row_folds``): row 0 the symmetric
    model (fitted to and scored on f - ``offset``, the constant force it leaves out), row 1 the
    asymmetric one (its curves fitted by ``per_direction``, default
    ``estimator``). ``vs_max`` holds (both, positive, negative). Each model's procedure runs
    once on all rows, and each fold's fit repeats it from that result (``warm_copy``: the
    grey-box's candidates refitted and averaged again, without the multi-start). ``progress``
    hears of each fold done when they take long (``fricgen._progress.Progress``). Returns the
    errors and the three fits on all rows (symmetric, positive, negative: ``FittedDirection``)."""
    per_direction = estimator if per_direction is None else per_direction
    report = Progress(progress)
    moving = sweep.v != 0
    v, f = sweep.v[moving], sweep.f[moving]
    whole = Sweep(v, f)
    fold = row_folds(v.size, folds, seed, blocks)
    whole_fits = [_fit(half, model, vs, CV_POINTS, independence) for half, model, vs in
                  zip((Sweep(v, f - offset), whole.direction(1), whole.direction(-1)),
                      (estimator, per_direction, per_direction), vs_max)]
    fitted = [done.estimator for done in whole_fits]
    report("symmetry: fitted on all rows")
    mse = np.zeros((2, folds))
    for k in range(folds):
        train, test = Sweep(v[fold != k], f[fold != k]), fold == k
        both, pos, neg = (_fit(half, model, vs, CV_POINTS, independence, warm_copy).curve
                          for half, model, vs in zip(
                              (Sweep(train.v, train.f - offset), train.direction(1),
                               train.direction(-1)), fitted, vs_max))
        sign, speed, target = np.sign(v[test]), np.abs(v[test]), np.sign(v[test]) * f[test]
        mse[0, k] = np.mean((both.magnitude(speed) - (target - sign * offset)) ** 2)
        asym = np.where(sign > 0, pos.magnitude(speed), neg.magnitude(speed))
        mse[1, k] = np.mean((asym - target) ** 2)
        report(f"symmetry: cross-validated {k + 1} of {folds} folds")
    return mse, whole_fits


def prefers_asymmetric(mse: np.ndarray) -> bool:
    """Whether the paired fold comparisons favour the asymmetric model (see the module)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.log(mse[0]) - np.log(mse[1])
    if not np.all(np.isfinite(ratio)):                  # an exact fit: compare the errors only
        ratio = np.sign(mse[0] - mse[1])
    se = ratio.std(ddof=1) / np.sqrt(ratio.size)
    gain = float(mse[0].mean() - mse[1].mean())
    return bool(ratio.mean() > CV_SIGMAS * se and gain > CV_MARGIN * mse[0].mean())


def _direction_vs_max(half: Sweep, sweep: Sweep, vs_max: Optional[float], blocks: int = 0):
    """The vs_max of one direction: ``vs_max`` if given, else the direction's own choice when
    its training set can be built with it, else the choice of both directions folded."""
    if vs_max is not None:
        return vs_max
    own = _vs_max(half, None, blocks)
    try:
        prepare(half, vs_max=own, max_points=CV_POINTS)
        return own
    except DataError:
        return _vs_max(sweep, None, blocks)


def fit_directions(sweep: Sweep, estimator, vs_max: Optional[float] = None,
                   asymmetric: Optional[bool] = None, seed=0, per_direction=None,
                   blocks: int = 0, independence: float = 1.0, offset: float = 0.0,
                   progress: Optional[Callable[[str], None]] = None,
                   evident: bool = False) -> DirectionsFit:
    """Fit one curve (symmetric) or two (asymmetric, each by ``per_direction``, default
    ``estimator``); ``asymmetric`` None chooses by cross-validation (in contiguous ``blocks`` of
    rows, ``row_folds``, for a log's samples in time order; its folds told to ``progress``),
    or, where the directions are evidently apart (``evident``), takes the two curves without it
    whenever each direction can have its own (``TEXTBOOK_ASYMMETRY``); True or False forces the
    model. Without ``vs_max`` each curve's is chosen on the same kind of folds. ``independence``
    (the share of an independent sample in a row, a smoothed log's) bins each curve's training
    set to its effective samples (``prepare``). With data in one
    direction only the model is symmetric (``DataError`` if the asymmetric one was asked for);
    when a sweep of both directions cannot give each its own curve, ``chosen_by`` says why.
    ``offset`` is a constant force beside the symmetric curve (a log's identified o, compensated
    apart): that curve is fitted to f - ``offset``; the asymmetric curves hold it."""
    per_direction = estimator if per_direction is None else per_direction
    halves = (sweep.direction(1), sweep.direction(-1))
    level = Sweep(sweep.v, sweep.f - offset)            # the symmetric curve's samples
    if asymmetric is not False:
        one_direction = any(len(half) == 0 for half in halves)
        try:
            for half, side in zip(halves, ("v > 0", "v < 0")):
                if len(half) < MIN_ROWS:
                    raise DataError(f"{len(half)} rows with {side}, need at least {MIN_ROWS}")
            vs_dirs = [_direction_vs_max(half, sweep, vs_max, blocks) for half in halves]
            for half, vs in zip(halves, vs_dirs):
                prepare(half, vs_max=vs, max_points=CV_POINTS)
        except DataError as exc:
            if asymmetric:
                raise DataError(f"an asymmetric model needs a sweep of each direction: {exc}") from None
            reason = "one direction only" if one_direction else f"asymmetric model not fittable: {exc}"
            return DirectionsFit((_fit(level, estimator, _vs_max(level, vs_max, blocks), None,
                                       independence),), reason)
    if asymmetric is None and not evident:
        both = _vs_max(level, vs_max, blocks)
        mse, whole = cross_validate(sweep, estimator, (both, *vs_dirs), seed=seed,
                                    per_direction=per_direction, blocks=blocks,
                                    independence=independence, offset=offset, progress=progress)
        cv = tuple(float(np.sqrt(m)) for m in mse.mean(axis=1))
        how = "cross-validation in blocks of time" if blocks else "cross-validation"
        if not prefers_asymmetric(mse):
            return DirectionsFit((_fit(level, estimator, both, None, independence,
                                       done=whole[0]),), how, cv)
        return DirectionsFit(tuple(_fit(h, per_direction, vs, None, independence, done=done)
                                   for h, vs, done in zip(halves, vs_dirs, whole[1:])), how, cv)
    if asymmetric is False:
        return DirectionsFit((_fit(level, estimator, _vs_max(level, vs_max, blocks), None,
                                   independence),), "forced")
    return DirectionsFit(tuple(_fit(h, per_direction, vs, None, independence)
                               for h, vs in zip(halves, vs_dirs)),
                         "forced" if asymmetric else TEXTBOOK_ASYMMETRY)


def within_budget(estimator, budget: int):
    """A copy of a chosen-size estimator (the default, elm_auto, the grey-box) that fits at most
    ``budget`` parameters (``DefaultRegressor.max_parameters``); an ELM of a given size as it is."""
    estimator = clone(estimator)
    if isinstance(estimator, DefaultRegressor):
        return estimator.set_params(max_parameters=budget)
    if isinstance(estimator, AutoELMRegressor):
        cap = elm_units(budget)
        return estimator.set_params(max_neurons=min(cap, estimator.max_neurons or cap))
    if isinstance(estimator, StribeckRegressor):
        return estimator.set_params(sources=greybox_sources(budget, estimator.sources))
    return estimator


def fit_friction(sweep: Sweep, estimator, per_direction=None, ident=None, vs_max=None,
                 asymmetric=None, seed=0, progress=None, evident: bool = False) -> DirectionsFit:
    """``fit_directions`` as ``fricgen train`` runs it. For a log (``ident``, its
    ``Identification``): cross-validation in blocks of BLOCK_WINDOWS smoothing windows of time,
    training sets binned to the
    effective samples, and at most the parameters they support (``within_budget``; each
    direction has about half of them). A symmetric curve leaves the offset still in the
    friction samples out (``Identification.offset_in_friction``, ``fit_directions``' ``offset``)."""
    if ident is None:
        return fit_directions(sweep, estimator, vs_max=vs_max, asymmetric=asymmetric, seed=seed,
                              per_direction=per_direction, progress=progress, evident=evident)
    per_direction = estimator if per_direction is None else per_direction
    return fit_directions(sweep, within_budget(estimator, ident.parameter_budget), vs_max=vs_max,
                          asymmetric=asymmetric, seed=seed,
                          per_direction=within_budget(per_direction, ident.parameter_budget // 2),
                          blocks=BLOCK_WINDOWS * ident.window,
                          independence=ident.independent / ident.n_kept,
                          offset=ident.offset_in_friction,
                          progress=progress)
