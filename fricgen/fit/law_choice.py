"""The default's choice of law: the textbook laws first, richer models only where the data ask.

Candidates, simplest first: Coulomb + viscous (one curve, then one per direction), Coulomb +
viscous + one Stribeck term (likewise; ``fit.textbook``), then fricgen's multi-source fit (the
grey-box [F1] or the automatic ELM, its symmetry chosen as ``fit.directions`` does) where the
data hold enough points for it. Each is refitted without each fold of one cross-validation and
scored in newtons on the held-out points (CV_FOLDS folds; a log's in contiguous blocks of time,
``row_folds``). A sweep of up to LOO_POINTS points is judged leaving out one point at a time,
each within the speeds its fit saw: the slowest and the fastest point of each direction are
always fitted, for a line through two points carried a decade beyond them scores the
extrapolation, not the law. There the Stribeck laws of curves of few points (PIN_POINTS) keep
the shape and v_s of their fit on all points and refit their levels: a fold with as many points
as parameters fits v_s exactly through them, and its held-out error measures that instability
instead. A Stribeck law whose drop F_s - F_c the points do not determine
(``LawFit.drop_determined``) is no candidate. The simplest candidate whose mean held-out
squared error is within one standard error of the paired fold differences of the best one's is
kept (the one-standard-error rule), so that no richer model is kept for a gain within the noise
and the default is never clearly worse than the textbook fit.
The per-direction Coulomb + viscous law is the floor: another candidate, simpler or richer,
replaces it only when it beats it by more than that noise.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Dict, List, Optional, Tuple

import numpy as np

from ..data.idim import friction_basis
from ..data.sweep import Sweep
from ..data.outliers import (MEDIAN_WINDOW, OUTLIER_SIGMAS, gross_outliers, inner_points,
                              line_outliers, robust_scale, unexplained)
from ..data.training_set import check_friction_sign
from ..errors import DataError
from ..metrics import rmse
from .directions import (CV_FOLDS, CV_POINTS, DirectionsFit, FittedDirection, _fit, row_folds,
                         warm_copy)
from .textbook import DROP_SE, MIN_POINTS, PARAMETERS, LawFit, fit_law
from .textbook_laws import (SLOPE_CHI2, TextbookLaw, curve_points, short_direction_differs,
                            signed_force, slope_rejected, textbook_fit)

#: Sweeps of up to this many points are cross-validated leaving one point out.
LOO_POINTS = 30
#: ... and a Stribeck law's v_s is pinned in those folds on curves of fewer points than this;
#: from it a fold leaves enough points to fit v_s again (a v_s fitted with the held-out point
#: sees it: the law then beat the textbook floor by chance on 4 of 20 straight sweeps of 10).
PIN_POINTS = 8
#: A candidate is kept when its mean held-out squared error exceeds the best one's by at most
#: this many standard errors of their paired fold differences.
SE_RULE = 1.0
#: ... and the multi-source fit must also lower the best textbook law's held-out RMS error by
#: this fraction: its many parameters are determined where the data are and free beyond them
#: (below a log's slowest steady speed), which held-out folds of the same motion do not test.
RICH_MARGIN = 0.05
#: A sweep's multi-source fit is tried only where the textbook law's residuals run in fewer
#: sign runs than chance by this many standard deviations (a one-sided 2.3 % test) ...
STRUCTURE_Z = 2.0
#: ... on a curve of at least this many points (fewer give the test no power) ...
STRUCTURE_POINTS = 10
#: ... or where the law's RMS residual is this many times that of each point predicted from its
#: two neighbours (``from_neighbours``): under a right law with noise alone the ratio stays
#: below 1.3 (400 simulated sweeps of 10-40 points, additive and growing noise); a drag rising
#: by decades, which leaves long runs of small residuals and a few large ones, gives 7-13.
NEIGHBOURS_BEAT = 2.0
#: Fewest paired held-out folds on which one candidate can beat another: the standard error of
#: fewer differences is itself a guess (a sweep of 3 points a side holds out its 2 middle ones).
MIN_PAIRED = 3
#: The textbook floor: kept unless another candidate beats it clearly (the law of the
#: engineer's spreadsheet; symmetric Coulomb + viscous where the data move one way).
ANCHOR = "Coulomb + viscous, per direction"


def textbook_outliers(sweep: Sweep) -> np.ndarray:
    """Gross outliers of a sweep: per direction, the points off a running median by more than
    OUTLIER_SIGMAS robust standard deviations (``data.outliers``), and the fastest point (which
    no running median judges), that neither Coulomb + viscous nor (from 5 points) its Stribeck
    law, fitted to the others, nor the line through its two neighbours in speed (``between``:
    a curve bending beyond the textbook laws, a drag, is no outlier) explains; nor, where the
    forces are all > 0, that line in log speed and log force, judged against the spread of the
    logarithms (a force whose noise grows with it, a drag rising by decades over log-spaced
    speeds: the line between neighbours cuts the bend, by far more than the slow points'
    noise). A direction of too few points for the running median's window has its suspects off
    a Theil-Sen line (``line_outliers``; the slowest and the fastest point never), and their
    neighbours' lines are drawn through the other points alone: in a few points a suspect is
    its neighbours' neighbour, and would bend the very lines that judge it. There a spike is
    also looked for alone (``_spike``)."""
    out = np.zeros(len(sweep), dtype=bool)
    for speed, magnitude, rows in curve_points(sweep, np.arange(len(sweep)), asymmetric=True):
        few = speed.size < 2 * MEDIAN_WINDOW
        if few:
            out[rows] |= _spike(speed, magnitude)
        suspects = line_outliers(speed, magnitude) if few else gross_outliers(speed, magnitude)
        if not few:
            suspects[np.argmax(speed)] = True
        kept = int((~suspects).sum())
        if suspects.any() and kept >= MIN_POINTS[False]:
            laws = [fit_law(speed[~suspects], magnitude[~suspects], stribeck=s, errors=False)
                    for s in (False, True) if kept >= MIN_POINTS[s]]
            others = ~suspects if few else None
            confirmed = unexplained(magnitude, suspects, [law.magnitude(speed) for law in laws]
                                    + [between(speed, magnitude, others)])
            if np.all(magnitude > 0):
                log_speed, log_force = np.log(speed), np.log(magnitude)
                confirmed &= unexplained(log_force, suspects, [between(log_speed, log_force, others)])
            out[rows] |= confirmed
    return out


def _spike(speed: np.ndarray, magnitude: np.ndarray) -> np.ndarray:
    """The one inner point of a direction of few points that lies furthest off the line through
    its two neighbours (``between``), where that is more than OUTLIER_SIGMAS robust standard
    deviations of all points' such distances, and the better textbook law fitted to every
    point, itself included, leaves it more than OUTLIER_SIGMAS robust standard deviations of
    the other points' residuals off (a law bends through a sharp drop, not to a spike). On 12
    log-spaced points a side of a Stribeck curve, a spike 50 times the noise hid in the
    Theil-Sen line's spread (``line_outliers``) and was kept on 51 of 100 sweeps, 19 now."""
    out = np.zeros(speed.size, dtype=bool)
    if speed.size < MIN_POINTS[True]:
        return out
    off = np.abs(magnitude - between(speed, magnitude))
    i = int(np.argmax(np.where(inner_points(speed), off, -1.0)))
    if not off[i] > OUTLIER_SIGMAS * robust_scale(off, magnitude):
        return out
    others = np.arange(speed.size) != i
    residuals = [np.abs(magnitude - fit_law(speed, magnitude, stribeck=s, errors=False).magnitude(speed))
                 for s in (False, True) if speed.size > PARAMETERS[s]]
    best = min(residuals, key=lambda r: robust_scale(r[others], magnitude))
    out[i] = best[i] > OUTLIER_SIGMAS * robust_scale(best[others], magnitude)
    return out


def between(x: np.ndarray, y: np.ndarray, kept: Optional[np.ndarray] = None) -> np.ndarray:
    """Each point's value on the line through its two neighbours in x (the two nearest at an
    end), the point itself left out; ``kept`` (a mask): the neighbours only among those points,
    so that a suspect bends no other point's line."""
    if kept is not None and 2 <= int(kept.sum()) < kept.size:
        out = np.empty(np.size(y), dtype=float)
        out[kept] = between(x[kept], y[kept])
        order = np.argsort(x[kept], kind="stable")
        xs, ys = x[kept][order], y[kept][order]
        right = np.clip(np.searchsorted(xs, x[~kept]), 1, xs.size - 1)
        out[~kept] = _line(xs, ys, right - 1, right, x[~kept])
        return out
    order = np.argsort(x, kind="stable")
    xs, ys = x[order], y[order]
    left = np.clip(np.arange(xs.size) - 1, 0, None)
    right = np.clip(np.arange(xs.size) + 1, None, xs.size - 1)
    left[0], right[0] = 1, min(2, xs.size - 1)
    left[-1], right[-1] = max(xs.size - 3, 0), xs.size - 2
    out = np.empty_like(ys)
    out[order] = _line(xs, ys, left, right, xs)
    return out


def _line(xs: np.ndarray, ys: np.ndarray, left: np.ndarray, right: np.ndarray, at: np.ndarray):
    """The lines through (xs, ys)[left] and [right] at ``at`` (flat where the two x coincide)."""
    span = xs[right] - xs[left]
    slope = np.divide(ys[right] - ys[left], span, out=np.zeros_like(span), where=span != 0)
    return ys[left] + slope * (at - xs[left])


def runs_z(residual: np.ndarray) -> float:
    """The Wald-Wolfowitz statistic of the residuals' signs in their order: (R - E[R]) / sd(R)
    for R runs; strongly negative where the signs come in long runs (a curve the law misses)."""
    signs = np.sign(residual)[residual != 0] > 0
    n1, n = int(signs.sum()), signs.size
    n2 = n - n1
    if n1 == 0 or n2 == 0:
        return -np.inf if n >= STRUCTURE_POINTS else 0.0
    runs = 1 + int(np.count_nonzero(signs[1:] != signs[:-1]))
    mean = 2.0 * n1 * n2 / n + 1.0
    variance = 2.0 * n1 * n2 * (2.0 * n1 * n2 - n) / (n * n * (n - 1.0))
    return (runs - mean) / np.sqrt(variance) if variance > 0 else 0.0


def _curves(sweep: Sweep, weight: np.ndarray):
    """The curves ``shows_structure`` tests: per direction where the sweep has both."""
    two_way = bool(np.any(sweep.v > 0) and np.any(sweep.v < 0))
    return curve_points(sweep, weight, asymmetric=two_way)


def testable(sweep: Sweep) -> bool:
    """Whether ``shows_structure`` can test a curve of ``sweep`` (one of STRUCTURE_POINTS)."""
    return any(speed.size >= STRUCTURE_POINTS for speed, _, _ in _curves(sweep, np.ones(len(sweep))))


def from_neighbours(speed: np.ndarray, magnitude: np.ndarray) -> np.ndarray:
    """Each point predicted from its two neighbours in speed (``between``), in log speed and
    log force where the forces are all > 0 (a curve rising by decades is nearly straight
    there), else in speed and force."""
    if np.all(magnitude > 0) and np.all(speed > 0):
        return np.exp(between(np.log(speed), np.log(magnitude)))
    return between(speed, magnitude)


def shows_structure(sweep: Sweep, weight: Optional[np.ndarray] = None) -> bool:
    """Whether the richest textbook law the points allow (per direction where the sweep has
    both) leaves residuals with structure along the speed, on a curve of at least
    STRUCTURE_POINTS points: fewer sign runs than chance by STRUCTURE_Z standard deviations
    (``runs_z``), or an RMS residual NEIGHBOURS_BEAT times that of the points predicted from
    their neighbours (``from_neighbours``: a curve the law misses, if in few points).
    Where it does not, no richer curve has anything to find."""
    weight = np.ones(len(sweep)) if weight is None else weight
    for speed, magnitude, w in _curves(sweep, weight):
        if speed.size < STRUCTURE_POINTS:
            continue
        order = np.argsort(speed, kind="stable")
        law = fit_law(speed, magnitude, w, stribeck=speed.size >= MIN_POINTS[True],
                      errors=False).magnitude(speed)
        if runs_z((magnitude - law)[order]) < -STRUCTURE_Z:
            return True
        if rmse(law, magnitude) > NEIGHBOURS_BEAT * rmse(from_neighbours(speed, magnitude), magnitude):
            return True
    return False


def folds_for(v: np.ndarray, seed, blocks: int) -> np.ndarray:
    """The fold of each moving row of velocity ``v``: a log's contiguous blocks, else
    ``row_folds``' random partition (``cross_validate``'s own); on a small sweep one point
    each, the slowest and the fastest point of each direction in none (-1: always fitted),
    unless that leaves fewer than two points to hold out."""
    if blocks or v.size > LOO_POINTS:
        return row_folds(v.size, CV_FOLDS, seed, blocks)
    inside = np.ones(v.size, dtype=bool)
    for sign in (1, -1):
        speed = np.where(np.sign(v) == sign, np.abs(v), np.nan)
        if not np.all(np.isnan(speed)):
            inside &= (speed != np.nanmin(speed)) & (speed != np.nanmax(speed))
    if inside.sum() < 2:
        return np.arange(v.size)
    folds = np.full(v.size, -1)
    folds[inside] = np.arange(int(inside.sum()))
    return folds


def _fold_mse(predict_fold: Callable, sweep: Sweep, weight: np.ndarray, folds: np.ndarray):
    """Per-fold weighted mean squared held-out error of a procedure (``predict_fold(train,
    weight)`` returns a predictor of the signed force); None where a fold cannot be fitted."""
    mse = np.empty(int(folds.max()) + 1)
    for k in range(mse.size):
        out = folds == k
        try:
            predict = predict_fold(Sweep(sweep.v[~out], sweep.f[~out]), weight[~out])
        except (ValueError, DataError):
            return None
        e = predict(sweep.v[out]) - sweep.f[out]
        mse[k] = np.sum(weight[out] * e ** 2) / np.sum(weight[out])
    return mse


def _vs(fitted: FittedDirection):
    """The vs_max a curve was fitted with: the choice made on all rows (with its B where the data
    have no linear high-speed region), or v_sat / 3."""
    return fitted.dataset.stribeck_range or fitted.dataset.v_sat / 3


def fold_offset(train: Sweep, weight: np.ndarray) -> float:
    """A log's constant force o as a fold's own rows give it: the even part of their force, o
    fitted beside an odd stand-in for the friction (``friction_basis``, as ``data.idim`` fits it
    on all rows). A symmetric curve leaves o out; given the o of all rows, each fold's curve
    had seen what the held-out rows hold, and beat the per-direction law it equals (Coulomb per
    direction and one viscous) on UR10e and Panda joint logs by up to 4 %."""
    basis = np.column_stack([friction_basis(train.v, odd=True), np.ones(len(train))])
    root = np.sqrt(weight)
    coef, *_ = np.linalg.lstsq(basis * root[:, None], train.f * root, rcond=None)
    return float(coef[-1])


def rich_predictor(rich: DirectionsFit, independence: float, offset: float) -> Callable:
    """Refits of the multi-source curves on a fold, started from their fit on all rows
    (``warm_copy``), in the symmetry chosen on all rows; a symmetric one's offset from the
    fold's rows (``fold_offset``) where the log has one."""
    def predict_fold(train: Sweep, weight):
        if rich.asymmetric:
            curves = [_fit(train.direction(s), f.estimator, _vs(f), CV_POINTS, independence,
                           warm_copy).curve for s, f in zip((1, -1), rich.fits)]
            return lambda v: signed_force(v, curves[0].magnitude, curves[1].magnitude)
        f = rich.fits[0]
        own = fold_offset(train, weight) if offset else 0.0
        curve = _fit(Sweep(train.v, train.f - own), f.estimator, _vs(f), CV_POINTS,
                     independence, warm_copy).curve
        return lambda v: signed_force(v, curve.magnitude) + own
    return predict_fold


@dataclass(frozen=True)
class LawChoice:
    """What the default chose, the candidates' cross-validated RMS errors (N), why some
    were not candidates, and the points it fitted (``kept``: the moving ones less the gross
    outliers)."""

    fit: DirectionsFit
    name: str
    cv_rmse: Tuple[Tuple[str, float], ...]
    left_out: Tuple[str, ...]
    folds: int
    kept: Optional[Sweep] = None
    one_out: bool = False
    #: Why the law kept is not the one of the least held-out error ("" where it is)
    why: str = ""

    def line(self, unit: str = "N") -> str:
        """The report's line: the law kept and each candidate's held-out error (in ``unit``),
        why it is kept where another's error is lower, and the candidates left out."""
        errors = ", ".join(f"{n} {e:.4g}" for n, e in self.cv_rmse)
        kind = "leave-one-out" if self.one_out else f"{self.folds}-fold"
        text = f"law       {self.name}, by {kind} held-out RMS ({unit}): {errors}"
        text += f"\nkept      {self.why}" if self.why else ""
        return text + "".join(f"\nleft out  {why}" for why in self.left_out)


@dataclass(frozen=True)
class Scored:
    """What ``asymmetry_evident`` found that ``choose_law`` would find again on the same sweep:
    the gross outliers of its moving points (``_scored``) and textbook laws' held-out errors
    per fold, by law name."""

    outliers: np.ndarray
    errors: Dict[str, np.ndarray]


def choose_law(sweep: Sweep, weight: Optional[np.ndarray] = None, rich: Optional[DirectionsFit] = None,
               rich_reason: str = "", independence: float = 1.0, offset: float = 0.0,
               seed=0, blocks: int = 0, asymmetric: Optional[bool] = None,
               known: Optional[Scored] = None, reversals: Optional[Sweep] = None) -> LawChoice:
    """The simplest candidate within the noise of the best (see the module). ``rich``: the
    multi-source fit on all rows (None, with ``rich_reason``, where the data could not give
    one); ``offset``: the constant force the textbook curves and the symmetric multi-source
    curve leave out (a log's, compensated apart);
    ``asymmetric`` True or False: only the candidates of that symmetry; ``known``: what
    ``asymmetry_evident`` found on this sweep; ``reversals``: a log's samples near its reversals
    (``Identification.reversals``), which the final fit of a kept Coulomb + viscous law adds (a
    Stribeck term would take their transient friction, pre-sliding after each reversal, for the
    steady friction of slow speeds: a UR10e joint's held-out sweep error doubled)."""
    moving = sweep.v != 0
    if not np.any(moving):
        raise DataError("no row with v != 0: a friction sweep needs motion")
    if not np.any(sweep.f[moving]):
        raise DataError("the force is 0 at every moving point: the data hold no friction")
    if asymmetric and not (np.any(sweep.v > 0) and np.any(sweep.v < 0)):
        raise DataError("an asymmetric model needs a sweep of each direction: the data move one "
                        "way only")
    if np.ptp(np.abs(sweep.v[moving])) <= 0:
        raise DataError("the points are all at one speed: a friction law needs two speeds or more")
    check_friction_sign(Sweep(sweep.v, sweep.f - offset).folded())   # a load beside it apart
    sweep, weight, outliers = _scored(sweep, weight, blocks, None if known is None else known.outliers)
    level = Sweep(sweep.v, sweep.f - offset)
    folds = folds_for(sweep.v, seed, blocks)
    one_out = not blocks and len(sweep) <= LOO_POINTS
    candidates: List[tuple] = []
    left_out = [rich_reason] if rich is None and rich_reason else []
    resting = int(np.count_nonzero(~moving))
    if resting:
        left_out.append(f"{resting} point{'s' * (resting > 1)} at v = 0: the law is the friction "
                        "of sliding, a force at rest (a breakaway) is none of its points")
    if outliers.any():
        count = int(outliers.sum())
        left_out.append(f"{count} point{'s' * (count > 1)}: gross outliers (off a running median, "
                        "or a robust line or their neighbours' where a direction has few points, "
                        "and off the textbook laws)")
    one_way = not (np.any(sweep.v > 0) and np.any(sweep.v < 0))
    if one_way and asymmetric is not False:
        left_out.append(f"per direction: the {'log moves' if blocks else 'sweep moves'} one way "
                        "only; its curve is mirrored to the other direction, which the data do not show")
    per_direction = TextbookLaw(False, True)
    if not one_way and asymmetric is not False and not per_direction.feasible(sweep):  # 1-2 points
        chi2 = slope_rejected(sweep, weight)
        per_direction = TextbookLaw(False, True, chi2 is None, chi2 is not None)
        if chi2 is not None:
            left_out.append(f"{TextbookLaw(False, True, True).name}: the 2 points of a direction reject "
                            f"the other's slope (chi-square {chi2:.3g} > {SLOPE_CHI2:g}); their own line, "
                            "which no held-out point checks")
    sizes = [np.count_nonzero(sweep.v > 0), np.count_nonzero(sweep.v < 0)]
    differs = None if one_way or asymmetric is False else short_direction_differs(level, weight)
    for law in (TextbookLaw(False, False), per_direction, TextbookLaw(True, False),
                TextbookLaw(True, True)):
        if asymmetric is not None and law.asymmetric != asymmetric:
            continue
        if law.asymmetric and one_way:
            continue
        if differs is not None and not law.asymmetric:
            left_out.append(f"{law.name}: the {'point' if min(sizes) == 1 else 'points'} of the "
                            f"direction with fewer reject one curve for both (chi-square {differs:.3g} "
                            "against the other direction's curve)")
            continue
        if law.shared_viscous:
            left_out.append(f"{TextbookLaw(False, True).name}: fewer than {MIN_POINTS[False]} points "
                            "in a direction; its F_c alone per direction, F_v from all points")
        if not law.feasible(sweep):
            need = MIN_POINTS[law.stribeck]
            left_out.append(f"{law.name}: " + ("4 points in all needed" if law.shared_viscous else
                            f"fewer than {need} points" + (" in a direction" if law.asymmetric else "")))
            continue
        fitted = law.fits(level, weight) if law.stribeck else None
        if law.stribeck and not all(curve.drop_determined for curve in fitted):
            left_out.append(f"{law.name}: its drop F_s - F_c is not determined by the data "
                            f"(not {DROP_SE:g} standard errors clear of 0"
                            f"{' in a direction' if law.asymmetric else ''})")
            continue
        mse = known.errors.get(law.name) if known is not None and not offset else None
        mse = _law_mse(law, sweep, weight, folds, one_out, offset, fitted) if mse is None else mse
        if mse is None:
            left_out.append(f"{law.name}: a fold leaves too few points to fit it")
            continue
        candidates.append((law.name, mse, lambda law=law, mse=mse: textbook_fit(
            law, *_with_reversals(level, weight, None if law.stribeck else reversals, offset),
            float(np.sqrt(mse.mean())))))
    if rich is not None and differs is not None and not rich.asymmetric:
        left_out.append("multi-source symmetric: the direction with fewer points rejects one curve for both")
        rich = None
    if rich is not None:
        mse = _fold_mse(rich_predictor(rich, independence, offset), sweep, weight, folds)
        name = "multi-source " + ("per direction" if rich.asymmetric else "symmetric")
        if mse is None:
            left_out.append(f"{name}: a fold leaves too few points to fit it")
        else:
            candidates.append((name, mse, lambda: rich))
    if not candidates:
        simplest = next((line for line in left_out if not line.startswith("multi-source")),
                        f"{len(sweep)}, need {MIN_POINTS[False]} (Coulomb + viscous)")
        raise DataError(f"too few moving points for any friction law: {simplest}")
    textbook_best = min((m.mean() for n, m, _ in candidates if not n.startswith("multi-source")),
                        default=np.inf)
    scored = candidates
    if candidates[-1][0].startswith("multi-source") and len(candidates) > 1 and \
            np.sqrt(candidates[-1][1].mean()) > (1 - RICH_MARGIN) * np.sqrt(textbook_best):
        left_out.append(f"{candidates[-1][0]}: its held-out RMS is not {RICH_MARGIN:.0%} below "
                        "the best textbook law's")
        candidates = candidates[:-1]
    floor = next((i for i, (n, _, _) in enumerate(candidates) if n == ANCHOR), 0)
    chosen = _choose([m for _, m, _ in candidates], floor)
    name, _, make = candidates[chosen]
    return LawChoice(make(), name, tuple((n, float(np.sqrt(m.mean()))) for n, m, _ in scored),
                     tuple(left_out), int(folds.max()) + 1, sweep, one_out,
                     _why_kept([(n, m) for n, m, _ in candidates], chosen, floor))


def _with_reversals(level: Sweep, weight: np.ndarray, reversals: Optional[Sweep], offset: float):
    """The points and weights of a textbook law's final fit: ``level`` and a log's ``reversals``
    (less ``offset``, as ``level``), each of those of weight 1, as a row of the log is."""
    if reversals is None or len(reversals) == 0:
        return level, weight
    return (Sweep(np.concatenate([level.v, reversals.v]), np.concatenate([level.f, reversals.f - offset])),
            np.concatenate([weight, np.ones(len(reversals))]))


def _scored(sweep: Sweep, weight: Optional[np.ndarray], blocks: int,
            outliers: Optional[np.ndarray] = None):
    """The points ``choose_law`` scores, their weights and the gross outliers left out of them
    (``textbook_outliers``, or ``outliers`` where they are found already; none in a log's
    samples): the moving ones less those outliers."""
    moving = sweep.v != 0
    weight = np.ones(len(sweep)) if weight is None else np.asarray(weight, float)
    sweep, weight = Sweep(sweep.v[moving], sweep.f[moving]), weight[moving]
    if outliers is None:
        outliers = textbook_outliers(sweep) if not blocks else np.zeros(len(sweep), dtype=bool)
    return Sweep(sweep.v[~outliers], sweep.f[~outliers]), weight[~outliers], outliers


def _law_mse(law: "TextbookLaw", sweep: Sweep, weight: np.ndarray, folds: np.ndarray,
             one_out: bool, offset: float = 0.0,
             fitted: Optional[Tuple[LawFit, ...]] = None) -> Optional[np.ndarray]:
    """A textbook law's held-out errors per fold (``_fold_mse``); left out one point at a time
    from a curve of fewer than PIN_POINTS points, a Stribeck law keeps the shape and v_s of its
    fit on all points (see the module; ``fitted``: that fit where it is made already). A
    symmetric law's ``offset`` (a log's) comes from each fold's own rows (``fold_offset``)."""
    level = Sweep(sweep.v, sweep.f - offset)
    few = min(speed.size for speed, _, _ in curve_points(level, weight, law.asymmetric)) < PIN_POINTS
    pinned = (fitted or law.fits(level, weight, errors=False)) if one_out and law.stribeck and few else None
    def predict_fold(train: Sweep, w: np.ndarray) -> Callable:
        own = fold_offset(train, w) if offset and not law.asymmetric else offset
        return law.predictor(train, w, own, pinned)
    return _fold_mse(predict_fold, sweep, weight, folds)


def asymmetry_evident(sweep: Sweep, weight: Optional[np.ndarray] = None, seed=0,
                      outliers: Optional[np.ndarray] = None) -> Tuple[bool, Scored]:
    """Whether a sweep's directions differ beyond the noise already for the textbook laws: the
    per-direction law (with the Stribeck term where both directions allow it, else Coulomb +
    viscous) beats its symmetric twin (``_beats``) on the folds ``choose_law`` scores. A
    multi-source fit then need not be cross-validated for its symmetry: no curve shared by the
    two directions holds what the simplest curves already tell apart. Also what was found on
    the way (``Scored``: ``choose_law``'s ``known``). ``outliers``: the sweep's gross outliers
    where found already (``textbook_outliers``)."""
    sweep, weight, outliers = _scored(sweep, weight, 0, outliers)
    if not (np.any(sweep.v > 0) and np.any(sweep.v < 0)):
        return False, Scored(outliers, {})
    folds = folds_for(sweep.v, seed, 0)
    one_out = len(sweep) <= LOO_POINTS
    for stribeck in (True, False):
        pair = [TextbookLaw(stribeck, asymmetric) for asymmetric in (False, True)]
        if all(law.feasible(sweep) for law in pair):
            symmetric, per_direction = (_law_mse(law, sweep, weight, folds, one_out) for law in pair)
            if symmetric is not None and per_direction is not None:
                return _beats(per_direction, symmetric), Scored(outliers, {
                    pair[0].name: symmetric, pair[1].name: per_direction})
    return False, Scored(outliers, {})


def _why_kept(candidates: List[Tuple[str, np.ndarray]], chosen: int, floor: int) -> str:
    """Why ``_choose`` kept ``chosen`` where another candidate's mean held-out error is lower:
    too few held-out folds to tell (fewer than MIN_PAIRED), a lower error that does not beat the
    floor beyond the noise, or one within the noise of the kept one's; "" where the kept one's
    is the lowest."""
    lowest = min(range(len(candidates)), key=lambda k: candidates[k][1].mean())
    if lowest == chosen:
        return ""
    (kept, _), (other, errors) = candidates[chosen], candidates[lowest]
    if errors.size < MIN_PAIRED:
        return (f"{kept}, the floor: {errors.size} held-out point{'s' * (errors.size != 1)} "
                f"cannot show {other} better ({MIN_PAIRED} needed)")
    if lowest != floor and not _beats(errors, candidates[floor][1]):
        return (f"{kept}: {other}'s lower held-out error does not beat the floor, "
                f"{candidates[floor][0]}, by {SE_RULE:g} standard error of their paired fold "
                "differences")
    return (f"{kept}: {other}'s lower held-out error is within {SE_RULE:g} standard error of "
            "their paired fold differences")


def _beats(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether fold errors ``a`` are below ``b`` by more than the noise: the mean of their paired
    differences above SE_RULE standard errors, on MIN_PAIRED folds or more."""
    d = b - a
    return d.size >= MIN_PAIRED and d.mean() > SE_RULE * d.std(ddof=1) / np.sqrt(d.size)


def _choose(mse: List[np.ndarray], floor: int) -> int:
    """The candidate kept (indices into ``mse``, simplest first): ``floor`` (the textbook
    floor) unless others beat it (``_beats``); then, among those, the simplest within SE_RULE
    standard errors of the best."""
    better = [k for k in range(len(mse)) if k == floor or _beats(mse[k], mse[floor])]
    best = min(better, key=lambda k: mse[k].mean())
    return next(k for k in better if k == best or not _beats(mse[best], mse[k]))
