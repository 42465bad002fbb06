"""Which effects are missing from a friction model, selected by size, and the gap after.

Effects are selected by size (``Diagnoser``) on the force residual of [C1]
(``residual``): sets of named effects are fitted jointly on the first part of the log and
ranked by an information criterion (``select``), and a set one effect larger than the chosen
one is taken only if the held-out test of ``decision`` rejects "it explains nothing" at level
``alpha``, it changes the force by at least ``min_size`` of the friction force and the held-out
gap (``gap``) shrinks by at least ``min_gain``.
"""
from __future__ import annotations

import copy
import math
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from .._validate import positive
from ..data import MotionLog
from ..effects import (EFFECTS, MEMORIES, TABLES, ConstantLoad, Effect, FrictionalLag, Presliding, model_effects,
                       with_effects)
from ..effects.presliding import bristles_of
from ..errors import DataError
from ..metrics import rmse
from ..model import FrictionModel
from .decision import held_out_p_value
from .gap import HeldOutGap
from .localize import localize, where
from .refine import output_error_fit
from .residual import ResidualProblem
from .select import BEAM, extensions, joint_fit, mean_square, rank, score
from .steps import Step

#: A table is tried before the named effects when its cross-validated reduction of the
#: residual's mean square is more than this many times the best named effect's.
TABLE_PREFERENCE = 2.0
#: Named sets tried per step (best first by the joint criterion).
MAX_TRIES = 4
#: Largest --max-effects.
MAX_EFFECTS = 8
#: Effects whose size over the whole log understates them, judged below ``min_size`` by the
#: held-out gap alone, which must then shrink by ``UNDERSTATED_GAIN`` rather than ``min_gain``:
#: those whose force lives in short stretches (the lag and pre-sliding: at the reversals), and a mass or force
#: constant at least ``MISMATCH_RELEVANT`` off the nominal one (a mass half the nominal one on
#: a slow log changes the force by 2 % of the friction, and detunes any controller built on it;
#: a saturation whose force constant falls by that much at the log's peak current, likewise).
SHORT_LIVED = ("frictional_lag", "presliding")
MISMATCH_RELEVANT = 0.1
UNDERSTATED_GAIN = 0.25
#: (A timing effect, ``Effect.via_timing``: a sensor delay, shifts the force in time rather than
#: adding one: below ``min_size`` it is judged by the held-out gap alone, which must shrink by
#: ``min_gain`` as for any effect.)
#:
#: Effects considered only when ``candidates`` names them (``candidates_with``), for the user
#: who suspects one: on short closed-loop logs a sensor delay of one or two samples also fits
#: what the model misses of an axis without one (on 3 of 60 null scenario logs of 14 s that
#: nothing else is named on); a saturation, close to a force-constant or mass error in the
#: current, takes their place among the ``MAX_TRIES`` sets a step tries, which cost two
#: triples of the scenario benchmark the true set (docs/guides/diagnosis.md); pre-sliding, for
#: an axis suspected of it, was added after the default's figures were measured, which a new
#: candidate among the sets each step tries would change.
ASKED_FOR = ("sensor_delay", "actuator_saturation", "presliding")


def candidates_with(*asked: str) -> List[str]:
    """The default candidates (every effect but ``ASKED_FOR``) and the ``asked`` ones, in the
    order of ``EFFECTS``."""
    return [n for n in EFFECTS if n not in ASKED_FOR or n in asked]


class Diagnoser:
    """Name the effects a friction model misses in a measured log, and add them.

    Selection by size, one effect more per step. At step k the sets of k named effects are grown
    from the ``BEAM`` best sets of k - 1 (the chosen one first): each set is fitted jointly
    (backfitting, with the parameters the forces are linear in solved together after each
    sweep, ``select.joint_linear``) on the fit part and ranked by Akaike's criterion with the
    effective sample size (``select.score``). So a step may also replace an earlier choice: a
    one-sided asymmetry chosen for what is a load plus a level change gives way to the two when
    the pair fits better. The best set (then the next, up to ``MAX_TRIES``) is taken only if,
    against the chosen set,

    1. the held-out test (``decision.held_out_p_value``) gives p < ``alpha``, and
    2. the fitted values are what the names say (``Effect.implausible``: no mass five times off)
       and the log can resolve them (``Effect.unresolved``: no delay within half a sample),
    3. it is practically relevant: the force it changes on the held-out part is at least
       ``min_size`` of the RMS friction force (a friction model fitted to a sweep is off by
       about a percent; such bias is real structure, significant on long logs, but not a
       missing effect; for a lag or a mass or force constant ``MISMATCH_RELEVANT`` off, see
       ``UNDERSTATED_GAIN``), and
    4. the held-out gap shrinks by at least ``min_gain`` (relative): never an effect that makes
       the simulation worse.

    Only a set refused for its size or gap lets the next be tried. Once one passes, the others
    up to ``MAX_TRIES`` are checked as well, and of those that pass and whose held-out gap is
    within one standard error of the smallest, the best by the score per unit of mass is taken
    (``_closest``): the fit part can rank a drift below what it extrapolates to. When no set
    one larger is taken, the sets two larger that contain the chosen one are tried the same way
    (effects that fit the held-out part only together: a drift and a force-constant error,
    either alone fitted on the first part, extrapolate worse than nothing); each newcomer of a
    set must change the force by ``min_size`` on its own. When no named set is taken, the tables of
    ``fricgen.effects.tables`` (no physical name) are ranked by blocked
    cross-validation and added to the chosen set in the same way; they go first when the best
    table's gain is more than ``TABLE_PREFERENCE`` times the best named one's (structure no
    named form follows). Selection stops at ``max_effects`` or when nothing is added.

    Parameters
    ----------
    window : float
        Smoothing window of the force residual (s).
    holdout : float
        Fraction of the log, at its end, kept for the test and the gap (0.05-0.6).
    horizon : float
        Restart interval of the held-out simulations (s).
    folds : int
        Folds of the blocked cross-validation that ranks the candidates.
    alpha : float
        Level of each held-out test.
    min_size, min_gain : float
        Least force change (share of the RMS friction force) and least relative shrinking of
        the held-out gap for an effect to be added (see above).
    max_effects : int
        Most effects added (1-8).
    candidates : sequence of str, optional
        Names of ``fricgen.effects.EFFECTS`` to consider (default: all but ``ASKED_FOR``).
    tables : bool
        Whether tables without a physical name may be offered.
    substeps : int
        Integration steps per sample of the simulations.
    pitch : float, optional
        The fundamental period (m) of the effects periodic in position (``position_ripple``,
        ``position_friction``) when it is known (a pole pitch, a screw lead); by default it is
        found from the log.
    refine : bool
        Whether the named effects selected are fitted again to simulations of the fit part
        (``refine.output_error_fit``) before the held-out gap after is measured.

    Attributes
    ----------
    effects_ : list of Step
        The steps that added an effect, in order; ``added_``: their fitted effects.
    effect_ : str
        The first effect added ("none" if none); ``p_value_``: the first step's p-value.
    steps_ : list of Step
        Every candidate considered, added or refused (with its reason).
    model_ : FrictionModel
        The model with the effects added appended to its ``effects``.
    gap_before_, gap_after_ : float
        Held-out gap (m/s, or rad/s: ``units_``, the model's) of the model as given and with the
        effects; ``gap_metric_`` says how
        it is measured, ``force_gap_before_``/``force_gap_after_`` the force residual's RMS (N).
        ``gap_selected_``: the gap after with the values selection fitted (``selected_``: those
        effects), before the refinement;
        ``fit_gap_before_``/``fit_gap_after_``: the fit part's gap before and after it (equal
        when it kept the values; NaN when it did not run: ``refine`` False or nothing added);
        ``gap_refined_``: the held-out gap with the refined values (NaN when they did not
        change); they are kept only if it grew by at most ``min_gain`` and they are what their
        names say (``refinement_refused_``: why not, else ''; ``refinement_kept``).
    where_, where_after_ : str
        Where the residual lives before and after (``localization_``, ``localization_after_``:
        the per-axis shares).
    problem_ : ResidualProblem
        The residual of [C1] on the log (``residual.ResidualProblem``).

    Notes
    -----
    The residual is phi i - m a - F(v) of the axis of [C1], with F the model's
    friction ([F1] or the AIM of [F3]); the effects' forms are those of
    ``fricgen.effects``. Beyond the paper, which identifies friction only.

    Examples
    --------
    >>> from fricgen.diagnose import Diagnoser
    >>> from fricgen.sim import LogSpec, synthesize_log
    >>> import fricgen
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> elm = fricgen.ELMRegressor(n_hidden=10, scheme="enlarged", solver="ridge", C=1e5, random_state=0)
    >>> model = fricgen.FrictionModel.fit(data, elm)       # the paper's ELM (sec. 4-5)
    >>> log = synthesize_log(LogSpec("constant_load", duration=1.5, substeps=2), model)
    >>> d = Diagnoser(candidates=["constant_load", "position_ripple"], tables=False)
    >>> d.fit(log, model, mass=4.0, force_constant=20.0).effect_
    'constant_load'
    >>> round(d.parameters()["load"]), d.gap_after_ < 0.1 * d.gap_before_
    (5, True)
    >>> Diagnoser(holdout=0.9).fit(log, model, 4.0, 20.0)
    Traceback (most recent call last):
    ValueError: holdout must be in [0.05, 0.6], got 0.9
    """

    def __init__(self, window: float = 0.021, holdout: float = 0.3, horizon: float = 0.02,
                 folds: int = 5, alpha: float = 0.01, min_size: float = 0.02, min_gain: float = 0.1,
                 max_effects: int = 3,
                 candidates: Optional[Sequence[str]] = None, tables: bool = True, substeps: int = 10,
                 pitch: Optional[float] = None, refine: bool = True):
        self.window, self.holdout, self.horizon = window, holdout, horizon
        self.folds, self.alpha, self.min_size, self.min_gain = folds, alpha, min_size, min_gain
        self.max_effects, self.candidates, self.tables, self.substeps = max_effects, candidates, tables, substeps
        self.pitch, self.refine = pitch, refine

    def _validate(self):
        if not 0.05 <= self.holdout <= 0.6:
            raise ValueError(f"holdout must be in [0.05, 0.6], got {self.holdout}")
        if self.folds < 2:
            raise ValueError(f"folds must be >= 2, got {self.folds}")
        if not self.window > 0:
            raise ValueError(f"window must be > 0, got {self.window}")
        if not self.horizon > 0:
            raise ValueError(f"horizon must be > 0, got {self.horizon}")
        if not 0 < self.alpha < 1:
            raise ValueError(f"alpha must be in (0, 1), got {self.alpha}")
        if not 0 <= self.min_size < 1:
            raise ValueError(f"min_size must be in [0, 1), got {self.min_size}")
        if not 0 <= self.min_gain < 1:
            raise ValueError(f"min_gain must be in [0, 1), got {self.min_gain}")
        if self.pitch is not None and not (np.isfinite(self.pitch) and self.pitch > 0):
            raise ValueError(f"pitch must be a finite number > 0, got {self.pitch}")
        if (isinstance(self.max_effects, bool) or not isinstance(self.max_effects, int)
                or not 1 <= self.max_effects <= MAX_EFFECTS):
            raise ValueError(f"max_effects must be an integer in [1, {MAX_EFFECTS}], got {self.max_effects!r}")
        names = (candidates_with() if self.candidates is None
                 else list(self.candidates))
        for name in names:
            if name not in EFFECTS:
                raise ValueError(f"candidates: unknown effect {name!r}; known: {', '.join(EFFECTS)}")
        return names

    # -- pieces of one step

    def _consider(self, p, base, chosen, gap_now, ranked, classes, joint=None) -> Step:
        """Fit the ranked candidate jointly with ``chosen`` (or take the set ``joint``), test the
        change on the held-out rows and check the gap."""
        name = ranked[0].effect
        if joint is None:
            joint = joint_fit(p, chosen, classes[name])
        test = p.test_rows
        before = p.target[test] - sum((p.predict(e, test) for e in chosen), np.zeros(test.size))
        after = p.target[test] - sum((p.predict(e, test) for e in joint), np.zeros(test.size))
        p_value, n_eff = held_out_p_value(before, after)
        ss_before = float(np.sum(before ** 2))
        share = 1.0 - float(np.sum(after ** 2)) / ss_before if ss_before > 0 else 0.0
        friction = rmse(p.signals.friction[p.rows[test]], 0.0)
        size = rmse(before - after, 0.0) / friction if friction > 0 else math.inf   # the force it changes
        step = Step(name, joint[-1], joint, p_value, n_eff, share, size, gap_now, math.nan, False, "", ranked)
        if p_value >= self.alpha:
            step.reason = f"not significant on the held-out part (p = {p_value:.2g} >= {self.alpha:g})"
            return step
        why = self._refused(p, joint)[1]
        if why:
            step.reason = why if len(joint) == 1 else f"in the set {', '.join(e.name for e in joint)}: {why}"
            return step
        had = {e.name for e in chosen}
        newcomers = [e for e in joint if e.name not in had]
        gain = self.min_gain
        if size < self.min_size:
            step.reason = (f"too small to matter ({size:.1%} of the friction force, below "
                           f"{self.min_size:.0%})")
            if not all(e.name in SHORT_LIVED or e.via_timing or e.mismatch() >= MISMATCH_RELEVANT
                       for e in newcomers):
                return step
            if not all(e.via_timing for e in newcomers):
                gain = UNDERSTATED_GAIN
        if len(newcomers) > 1:          # each effect a set names must matter on its own
            # (but the contact's pre-sliding: its force is at the reversals, where the moving
            # rows do not look; the gap judges it)
            own = {e.name: rmse(p.predict(e, test), 0.0) / friction for e in newcomers
                   if not e.via_contact}
            small = min(own, key=own.get, default=None)
            if small is not None and own[small] < self.min_size:
                step.reason = (f"{small} is too small to matter in the set ({own[small]:.1%} of "
                               f"the friction force, below {self.min_size:.0%})")
                return step
        step.gap_after, v_sim = self._held_out(base + joint)
        if not step.gap_after <= (1.0 - gain) * gap_now:
            step.reason = ((step.reason + ", and the held-out gap" if step.reason else
                            "the held-out gap") + f" does not shrink by {gain:.0%} "
                           f"({gap_now:.3g} -> {step.gap_after:.3g} {self.units_.speed})")
            return step
        step.reason = ""
        step.added = True
        self._v_sim = v_sim
        return step

    def _try(self, p, base, chosen, gap_now, ranked, grown, tables) -> Optional[Step]:
        """Consider the candidates of one kind in turn: ``grown`` named sets (from
        ``select.extensions``, best first) or, if None, the ``ranked`` tables added to ``chosen``.
        Only a significant candidate refused for its size or gap lets the next be tried; once
        a named set passes, the other sets up to ``MAX_TRIES`` are checked too and ``_closest``
        chooses among those that pass."""
        options = ([(k, None) for k in range(len(ranked))] if grown is None else
                   [(0, path) for _, path in grown[:MAX_TRIES]])
        had = {e.name for e in chosen}
        step, passed = None, []
        for k, joint in options:
            if joint is None:
                step = self._consider(p, base, chosen, gap_now, ranked[k:], tables)
            else:
                newcomer = [e for e in joint if e.name not in had][-1]
                step = self._consider(p, base, chosen, gap_now, ranked, None, joint=joint)
                step.effect, step.fitted = newcomer.name, newcomer
            self.steps_.append(step)
            if step.added:
                passed.append((step, self._v_sim))
                if joint is None:
                    break
            elif step.p_value >= self.alpha and not passed:
                return step
        if not passed:
            return step
        step, self._v_sim = self._closest(passed)
        self._replace(step, chosen)
        return step

    def _closest(self, passed: List[Tuple[Step, np.ndarray]]) -> Tuple[Step, np.ndarray]:
        """Of the sets that pass the checks (with their simulations), the best by ``score``
        per unit of mass among those whose held-out gap is within one standard error of the
        smallest: the first part of a log can rank a set below one that extrapolates worse (a
        drift is small there), and where the held-out part cannot tell sets apart the score
        decides, in the units the gap sees. The others are marked refused, saying why."""
        best, v_best = min(passed, key=lambda sv: sv[0].gap_after)
        limit = best.gap_after + self._held_out.standard_error(v_best)
        p = self.problem_
        pick = min((sv for sv in passed if sv[0].gap_after <= limit),
                   key=lambda sv: score(p, sv[0].joint, per_mass=True))
        names = ", ".join(e.name for e in pick[0].joint)
        for s, _ in passed:
            if s is not pick[0]:
                s.added = False
                s.reason = (f"passes, but the set {names} fits the first part better (per unit of "
                            f"mass) and is as close to the held-out part (within one standard error)"
                            if s.gap_after <= limit else
                            f"passes, but the set {names} leaves a smaller held-out gap "
                            f"({pick[0].gap_after:.3g} {self.units_.speed} against {s.gap_after:.3g})")
        return pick

    def _replace(self, step: Step, chosen: List[Effect]) -> None:
        """Book a set that is not ``chosen`` plus one effect: each of its other newcomers gets a
        step of its own (same test), each effect it drops is marked replaced."""
        new = {e.name for e in step.joint}
        old = {e.name for e in chosen}
        for e in step.joint:
            if e.name not in old and e is not step.fitted:
                twin = copy.copy(step)
                twin.effect, twin.fitted = e.name, e
                self.steps_.insert(len(self.steps_) - 1, twin)
        gone = old - new
        for s in self.steps_:
            if s.added and s.effect in gone:
                s.added = False
                s.reason = (f"replaced: the set {', '.join(e.name for e in step.joint)} fits "
                            "better and passes the held-out checks")

    def _prepare(self, log: MotionLog, model: FrictionModel, mass: float, force_constant: float):
        """The residual problem of the log under the model's own effects, and the held-out gap
        of the model as it is (``gap_before_``)."""
        mass = positive("mass", mass, DataError)
        force_constant = positive("force constant", force_constant, DataError)
        ts = log.sample_time
        w = max(5, int(round(self.window / ts)) | 1)
        # the model's own effects as they apply to this log: a carried mass or force constant
        # is the axis' own, a drift starts with the log
        base = [e.for_log(mass, force_constant, float(log.t[0])) for e in model_effects(model)]
        if bristles_of(model) is not None and any(e.name == FrictionalLag.name for e in base):
            raise ValueError("the model holds both bristles (pre-sliding) and a frictional lag: "
                             "two friction memories, which no simulation here combines")
        p = ResidualProblem(log, model, mass, force_constant, w, self.holdout, base, self.pitch)
        self.problem_ = p
        self.horizon_samples_ = max(1, int(round(self.horizon / ts)))
        self._held_out = HeldOutGap(p, self.horizon_samples_, self.substeps)
        self.held_ = self._held_out.held
        self.gap_before_, self.v_sim_before_ = self._held_out(base)
        return p, base

    def held_out_gap(self, log: MotionLog, model: FrictionModel, mass: float,
                     force_constant: float) -> float:
        """The held-out gap of the model as it is on ``log`` (``gap_before_`` of ``fit``,
        without the selection): e.g. of a log whose current is corrected by known effects."""
        self._validate()
        self._prepare(log, model, mass, force_constant)
        return self.gap_before_

    # -- the selection

    def fit(self, log: MotionLog, model: FrictionModel, mass: float, force_constant: float) -> "Diagnoser":
        """Select the effects ``model`` misses on ``log``, an axis of nominal ``mass`` (kg) and
        ``force_constant`` (N/A); returns self with the attributes above set."""
        names = self._validate()
        self.units_ = model.units
        p, base = self._prepare(log, model, mass, force_constant)
        ts = log.sample_time
        self._v_sim = self.v_sim_before_
        # the model's bristles are its friction's memory, as a named pre-sliding would be; a
        # load the model holds may have changed: a load named adds to it (``with_effects``)
        used = {e.name for e in base if e.name != ConstantLoad.name} | (
            {Presliding.name} if bristles_of(model) is not None else set())
        chosen: List[Effect] = []
        beam: List[List[Effect]] = [[]]
        self.steps_: List[Step] = []
        gap_now = self.gap_before_
        while len(chosen) < self.max_effects:
            q = p.after(chosen)
            taken = used | {e.name for e in chosen}
            tables = {n: c for n, c in TABLES.items() if n not in taken} if self.tables else {}
            named = {n: EFFECTS[n] for n in names if n not in taken
                     and not (n in MEMORIES and taken & MEMORIES)}
            ranked_named = rank(q, named, self.folds) if named else []
            ranked_tables = rank(q, tables, self.folds) if tables else []
            mse_none = float(np.mean(q.target[p.fit_rows] ** 2))
            sets = extensions(p, beam, names, used) if named else []
            # the named side's gain: the best single effect's, or a better set's (one that
            # replaces an earlier choice), whose fit-part mean square is not cross-validated
            best_set = min((mean_square(p, path) for _, path in sets[:1]), default=math.inf)
            best_named = min([c.mse for c in ranked_named[:1]] + [best_set])
            gain_named = mse_none - best_named if named else 0.0
            gain_table = mse_none - ranked_tables[0].mse if ranked_tables else 0.0
            trials = [(ranked_named, sets), (ranked_tables, None)]
            if ranked_tables and gain_table > TABLE_PREFERENCE * max(gain_named, 0.0):
                trials.reverse()       # a table explains far more than any named effect
            step = None
            for ranked, grown in trials:
                step = self._try(p, base, chosen, gap_now, ranked, grown, tables)
                if step is not None and step.added:
                    break
            if (step is None or not step.added) and named and len(chosen) + 2 <= self.max_effects:
                # two at once: effects that only together fit the held-out part (a drift and
                # a force-constant error: either alone, fitted on the first part, extrapolates
                # worse than nothing)
                have = {e.name for e in chosen}
                pairs = extensions(p, [path for _, path in sets[:BEAM]
                                             if have <= {e.name for e in path}], names, used)
                if pairs:
                    step = self._try(p, base, chosen, gap_now, ranked_named, pairs, tables)
                    sets = pairs if step.added else sets       # the next beam: sets of its size
            if step is None or not step.added:
                break
            chosen, gap_now = step.joint, step.gap_after
            beam = [chosen] + [path for _, path in sets[:BEAM]
                               if {e.name for e in path} != {e.name for e in chosen}][:BEAM - 1]
        self.effects_ = [s for s in self.steps_ if s.added]
        self._chain_gaps()
        # the joint refits change the parameters of earlier effects: report the final ones
        final = {e.name: e for e in chosen}
        chosen = [final[s.effect] for s in self.effects_]       # in the order they were added
        self.gap_selected_, self.selected_ = gap_now, list(chosen)
        self.fit_gap_before_ = self.fit_gap_after_ = math.nan
        self.gap_refined_, self.refinement_refused_ = math.nan, ""
        if chosen and self.refine:
            refined, self.fit_gap_before_, self.fit_gap_after_ = output_error_fit(
                p, base, chosen, self.horizon_samples_, self.substeps)
            if self.fit_gap_after_ < self.fit_gap_before_:       # values changed: gap again
                name, why = self._refused(p, refined)
                self.refinement_refused_ = f"{name}: {why}" if why else ""
                self.gap_refined_, v_refined = self._held_out(base + refined)
                # kept unless the held-out gap grows by more than an effect must shrink it
                # (the fit part's simulations fitted at the held-out part's expense)
                if self.refinement_kept:
                    chosen, gap_now, self._v_sim = refined, self.gap_refined_, v_refined
        for s, e in zip(self.effects_, chosen):
            s.fitted = e
        self.added_ = chosen
        self.effect_ = self.effects_[0].effect if self.effects_ else "none"
        self.p_value_ = self.steps_[0].p_value if self.steps_ else 1.0
        self.model_ = with_effects(model, chosen)
        self.localization_ = localize(p)
        self.where_ = where(self.localization_)
        final = p.after(chosen)
        self.localization_after_ = localize(final)
        self.where_after_ = where(self.localization_after_)
        self.v_sim_after_ = self._v_sim
        self.gap_after_ = gap_now
        self.gap_metric_ = (f"rms velocity error ({self.units_.speed}) of simulations restarted "
                            f"from the measured state every {self.horizon_samples_ * ts:.3g} s and "
                            f"driven by the measured current, against the measured velocity smoothed as the residual is, on "
                            f"the held-out last {self.holdout:.0%} of the log while moving")
        test = p.test_rows
        self.force_gap_before_ = rmse(p.target[test], 0.0)
        self.force_gap_after_ = rmse(final.target[test], 0.0)
        self.residual_after_ = p.raw_residual(base + chosen)
        return self

    @property
    def refinement_kept(self) -> bool:
        """Whether the refinement's values replaced the selection's: they changed, are what
        their names say (``refinement_refused_`` empty), and the held-out gap with them is at
        most (1 + ``min_gain``) times the selection's."""
        return not self.refinement_refused_ and bool(
            self.gap_refined_ <= (1.0 + self.min_gain) * self.gap_selected_)

    @staticmethod
    def _refused(p, effects) -> Tuple[str, str]:
        """The first of ``effects`` whose fitted values cannot be named on ``p``'s log
        (``Effect.refused``, ``Effect.implausible_beside`` at the log's speeds) and why; ("", "")
        if they all can."""
        speeds = p.log_speeds()
        reasons = ((e.name, e.refused(p.sample_time) or e.implausible_beside(p.signals.model, speeds))
                   for e in effects)
        return next((r for r in reasons if r[1]), ("", ""))

    def _chain_gaps(self) -> None:
        """Each added step's gap before is the gap after the effects added before it (effects
        that entered together share theirs): a step that replaced an earlier choice was decided
        against that choice, which the final list no longer holds."""
        before, last = self.gap_before_, None
        for s in self.effects_:
            if last is not None and s.joint is not last.joint:
                before = last.gap_after
            s.gap_before, last = before, s

    @property
    def fitted_(self) -> Optional[Effect]:
        """The first effect added (None if none)."""
        return self.added_[0] if self.added_ else None

    def parameters(self) -> Dict[str, object]:
        """The parameters of the first effect added ({} if none)."""
        return {} if self.fitted_ is None else self.fitted_.parameters()

    def refused(self) -> List[Step]:
        """The steps not added, each with its ``reason``."""
        return [s for s in self.steps_ if not s.added]

    def summary(self) -> dict:
        """The ``--json`` object."""
        return {"effect": self.effect_, "p_value": self.p_value_, "parameters": self.parameters(),
                "effects": [s.summary() for s in self.effects_],
                "refused": [{"effect": s.effect, "beside": s.beside, "p_value": s.p_value,
                             "reason": s.reason} for s in self.refused()],
                "where": self.where_, "where_after": self.where_after_,
                "gap_before": self.gap_before_, "gap_after": self.gap_after_,
                "gap_selected": self.gap_selected_,
                "fit_gap_before": None if math.isnan(self.fit_gap_before_) else self.fit_gap_before_,
                "fit_gap_after": None if math.isnan(self.fit_gap_after_) else self.fit_gap_after_,
                "gap_metric": self.gap_metric_, "alpha": self.alpha, "min_size": self.min_size,
                "min_gain": self.min_gain,
                "candidates": [{"effect": c.effect, "cv_rms": math.sqrt(c.mse)}
                               for c in (self.steps_[0].candidates if self.steps_ else [])]}


def diagnose(log: MotionLog, model: FrictionModel, mass: float, force_constant: float, **kwargs) -> Diagnoser:
    """Diagnose ``log``: ``Diagnoser(**kwargs).fit(log, model, mass, force_constant)``.

    Parameters
    ----------
    log : MotionLog
        The measured motion log (t, x, v, i).
    model : FrictionModel
        The friction model F(v) of [C1], that the log is compared with.
    mass, force_constant : float
        The nominal m (kg) and phi (N/A) of the axis.
    **kwargs
        Settings of ``Diagnoser``.

    Returns
    -------
    Diagnoser
        Fitted: ``effects_``, ``model_``, ``gap_before_``, ``gap_after_``, ``summary()``.

    Examples
    --------
    >>> from fricgen.diagnose import diagnose
    >>> from fricgen.sim import LogSpec, synthesize_log
    >>> import fricgen
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> elm = fricgen.ELMRegressor(n_hidden=10, scheme="enlarged", solver="ridge", C=1e5, random_state=0)
    >>> model = fricgen.FrictionModel.fit(data, elm)       # the paper's ELM (sec. 4-5)
    >>> log = synthesize_log(LogSpec("constant_load", duration=1.5, substeps=2), model)
    >>> d = diagnose(log, model, 4.0, 20.0, max_effects=1)     # every named effect and table
    >>> [s.effect for s in d.effects_], sorted(d.summary())[:3]
    (['constant_load'], ['alpha', 'candidates', 'effect'])
    """
    return Diagnoser(**kwargs).fit(log, model, mass, force_constant)
