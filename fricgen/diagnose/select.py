"""Selection's fits: candidates cross-validated one by one, effect sets fitted jointly
(backfitting with the linear parameters solved together) and ranked by Akaike's criterion,
and the beam of sets grown one named effect at a time."""
from __future__ import annotations

import itertools
import math
from typing import List, Sequence, Tuple

import numpy as np

from ..effects import EFFECTS, MEMORIES, Effect
from .residual import ResidualProblem
from .steps import Candidate

#: Most backfitting sweeps of a joint fit, and the relative fall of its mean square below
#: which a sweep ends it (slow pairs such as a drift beside an extra source need many).
BACKFIT_SWEEPS = 8
BACKFIT_TOLERANCE = 1e-3
#: Sets of named effects kept at each size to grow the next size from (beam search).
BEAM = 5


def cross_validated_mse(problem: ResidualProblem, cls, folds: int) -> float:
    """Blocked K-fold cross-validation of one candidate over the fit rows."""
    blocks = np.array_split(problem.fit_rows, folds)
    err = 0.0
    for j, block in enumerate(blocks):
        train = np.concatenate([b for k, b in enumerate(blocks) if k != j])
        effect = cls.fit(problem, train)
        err += float(np.sum((problem.target[block] - problem.predict(effect, block)) ** 2))
    return err / problem.fit_rows.size


def rank(q: ResidualProblem, classes, folds: int) -> List[Candidate]:
    """The candidate ``classes`` by name, best first by ``cross_validated_mse``."""
    ranked = [Candidate(name, cross_validated_mse(q, cls, folds)) for name, cls in classes.items()]
    return sorted(ranked, key=lambda c: c.mse)


def joint_fit(p: ResidualProblem, chosen: List[Effect], cls) -> List[Effect]:
    """``cls`` fitted to the residual after ``chosen``, then every effect refitted to the
    residual after all the others (backfitting), on the fit rows, until a sweep lowers the
    mean square by less than ``BACKFIT_TOLERANCE`` (at most ``BACKFIT_SWEEPS`` sweeps)."""
    effects = list(chosen) + [cls.fit(p.after(chosen), p.fit_rows)]
    if len(effects) == 1:
        return effects
    effects = joint_linear(p, effects)
    mse = mean_square(p, effects)
    for _ in range(BACKFIT_SWEEPS):
        swept = list(effects)
        for j in range(len(swept)):
            others = p.after(swept, skip=swept[j])
            swept[j] = type(swept[j]).fit(others, p.fit_rows)
        swept = joint_linear(p, swept)
        new = mean_square(p, swept)
        if not new < mse:
            break
        converged = new > (1.0 - BACKFIT_TOLERANCE) * mse
        effects, mse = swept, new
        if converged:
            break
    return effects


def joint_linear(p: ResidualProblem, effects: List[Effect]) -> List[Effect]:
    """The parameters the effects' forces are linear in (``Effect.linear``), solved jointly
    by least squares on the fit rows with the others held, for each combination of the
    effects' ``variants`` (the asymmetry's side): backfitting alone converges slowly between
    effects as alike as a force-constant error and a friction drift."""
    sig, rows = p.signals, p.fit_rows
    if not any(e.linear(sig)[1].size for e in effects):
        return effects
    best, best_mse = effects, mean_square(p, effects)
    for combo in itertools.product(*(e.variants() for e in effects)):
        parts = [e.linear(sig) for e in combo]
        regressors = np.column_stack([R for R, _ in parts])
        fixed = sum((e.force(sig) - R @ c for e, (R, c) in zip(combo, parts)), np.zeros(sig.t.size))
        target = p.target[rows] - p.at_rows(fixed, rows)
        coef, *_ = np.linalg.lstsq(p.at_rows(regressors, rows), target, rcond=None)
        ends = np.cumsum([c.size for _, c in parts])
        solved = [e.with_coefficients(c) for e, c in zip(combo, np.split(coef, ends[:-1]))]
        mse = mean_square(p, solved)
        if mse <= best_mse:
            best, best_mse = solved, mse
    return best


def mean_square(p: ResidualProblem, effects: Sequence[Effect]) -> float:
    """Mean square of the residual after ``effects`` on the fit rows."""
    r = p.target[p.fit_rows] - sum((p.predict(e, p.fit_rows) for e in effects),
                                   np.zeros(p.fit_rows.size))
    return float(np.mean(r ** 2))


def score(p: ResidualProblem, effects: Sequence[Effect], per_mass: bool = False) -> float:
    """Akaike's criterion of a joint fit on the fit rows, with the effective sample size;
    ``per_mass``: of the residual in acceleration, the force residual over the set's mass
    [C1], as the held-out gap sees it. A mass three times the nominal one and a force
    constant a third of the nominal one with the friction cut to a third move the axis
    alike, but the second's force residual is a third as large."""
    mse = max(mean_square(p, effects), 1e-300)
    if per_mass:
        mse /= (p.mass + sum(e.mass_delta for e in (*p.effects, *effects))) ** 2
    return p.n_effective * math.log(mse) + 2.0 * sum(e.n_params for e in effects)


def extensions(p: ResidualProblem, beam, names, used) -> List[Tuple[float, List[Effect]]]:
    """Every set of one more named effect grown from a set of the beam, fitted jointly, best
    first by ``score``; each distinct set once, its effects in the order they entered."""
    seen, out = set(), []
    for path in beam:
        have = {e.name for e in path}
        for name in names:
            key = frozenset(have | {name})
            if name in used or name in have or key in seen or (
                    name in MEMORIES and (have | used) & MEMORIES):     # one friction memory
                continue
            seen.add(key)
            joint = joint_fit(p, path, EFFECTS[name])
            out.append((score(p, joint), joint))
    return sorted(out, key=lambda t: t[0])
