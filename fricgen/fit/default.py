"""fricgen's default model: the grey-box [F1], or elm_auto where it cross-validates clearly better.

Gross outliers are set aside first (``fricgen.data.outliers``: the suspects of a running median
that [F1], fitted to every point, does not explain). Then both candidates are fitted to the
rest: ``StribeckRegressor`` (S and g chosen by cross-validation) and ``AutoELMRegressor``.
Their errors are compared on the same folds (``n_repeats`` partitions into ``n_folds``
interleaved folds), each candidate's whole procedure refitted without each fold (for the
grey-box model, S and g are chosen again on the fold's training points), scored on the
measured points (``inner_points``: not the two boundary points of section 2). The ELM wins
only when its gain exceeds ELM_GAIN_SIGMAS standard errors of the paired held-out difference
(the one-standard-error rule); on data that is a sum of Stribeck curves the grey-box [F1] is
kept, elsewhere (a viscous term in sqrt|v|, a measured curve) the ELM usually wins.
"""
from __future__ import annotations

import time

import numpy as np

from ..data.outliers import (MEDIAN_WINDOW, OUTLIER_SIGMAS, gross_outliers, inner_points,
                              unexplained)
from .._validate import integer
from .auto import AutoELMRegressor
from .base import Estimator, as_rng, interleaved_folds
from .stribeck import SOURCES, StribeckRegressor


def elm_units(budget: int) -> int:
    """The most ELM units within ``budget`` parameters: 2 per unit (its weight, and its place
    chosen from the dictionary) plus B."""
    return max(1, (int(budget) - 1) // 2)


def greybox_sources(budget: int, sources=SOURCES) -> tuple:
    """The numbers of [F1] sources within ``budget`` parameters: 2 S + 2 (c, a_k, v_sk and
    B); the fewest of ``sources`` when none fits."""
    return tuple(s for s in sources if 2 * s + 2 <= int(budget)) or (min(sources),)


#: elm_auto must beat the grey-box by more than this many standard errors of the paired
#: held-out difference (the one-standard-error rule): the grey-box is the smaller, physical
#: model, and a gain within the noise of the cross-validation is no reason to leave it.
ELM_GAIN_SIGMAS = 1.0


class DefaultRegressor(Estimator):
    """fricgen's default model: the grey-box [F1] (``StribeckRegressor``) or the automatic ELM
    (``AutoELMRegressor``): the grey-box unless the ELM's repeated cross-validated error is
    smaller by more than ELM_GAIN_SIGMAS standard errors.

    Points more than ``outlier_sigmas`` robust standard deviations off a running median are set
    aside first. x and t are the normalized data of [F9].

    Parameters
    ----------
    random_state : int, numpy.random.Generator or None
        Seeds the repeated fold partitions and the ELM.
    n_folds : int
        Folds of each cross-validation.
    n_repeats : int
        Repetitions of the cross-validation, on other interleaved partitions.
    outlier_sigmas : float
        Robust standard deviations beyond which a point is a gross outlier.
    max_neurons : int, optional
        A cap on the ELM's units.
    max_parameters : int, optional
        A cap on both models' parameters (what a log's effective samples support).

    Attributes
    ----------
    network_ : network
        The winner's trained AIM of [F3].
    choice_ : str
        "stribeck" or "elm_auto"; ``chosen_``: the fitted winner.
    greybox_, elm_ : estimator
        Both fitted candidates.
    cv_rmse_ : dict
        {choice: cross-validated RMSE} in units of t (normalized force).
    elm_gain_sigmas_ : float
        The ELM's mean gain in held-out squared error over the grey-box, in standard errors of
        the paired per-point differences (positive: the ELM is better).
    n_outliers_ : int
        Points set aside; ``inliers_`` (ndarray of bool): the mask over the points given.
    fit_seconds_ : float
        Wall time of ``fit`` (s).

    Notes
    -----
    Beyond the paper, which fits ELMs of a hand-picked size: the grey-box [F1] competes with the
    ELM on the same [F9] data, and the ELM must beat it by more than the noise of the
    cross-validation.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import DefaultRegressor
    >>> x = np.linspace(0, 1, 30)
    >>> t = 0.5 + 0.5 * np.exp(-(x / 0.2) ** 2)     # exactly [F1]: the grey-box wins
    >>> model = DefaultRegressor(n_repeats=1, max_parameters=6).fit(x, t)
    >>> model.choice_, model.n_outliers_
    ('stribeck', 0)
    """

    def __init__(self, random_state=0, n_folds: int = 5, n_repeats: int = 2,
                 outlier_sigmas: float = OUTLIER_SIGMAS, max_neurons=None, max_parameters=None):
        self.random_state = random_state
        self.max_neurons = max_neurons
        self.max_parameters = max_parameters
        self.n_folds = n_folds
        self.n_repeats = n_repeats
        self.outlier_sigmas = outlier_sigmas

    def _elm(self) -> AutoELMRegressor:
        cap = self.max_neurons
        if self.max_parameters is not None:
            budget = elm_units(self.max_parameters)
            cap = budget if cap is None else min(cap, budget)
        return AutoELMRegressor(max_neurons=cap, random_state=self.random_state)

    def _greybox(self) -> StribeckRegressor:
        sources = SOURCES if self.max_parameters is None else greybox_sources(self.max_parameters)
        return StribeckRegressor(n_folds=self.n_folds, sources=sources)

    def fit(self, x, t) -> "DefaultRegressor":
        x, t = self._inputs(x, t)
        integer("n_folds", self.n_folds, minimum=2)
        integer("n_repeats", self.n_repeats)
        start = time.perf_counter()
        suspects = gross_outliers(x, t, self.outlier_sigmas)
        outliers, everything = suspects, None
        if suspects.any():                    # confirmed against [F1] fitted to every point
            try:
                everything = self._greybox().fit(x, t)
                outliers = unexplained(t, suspects, [everything.predict(x)], self.outlier_sigmas)
            except ValueError:                # no admissible fit with them: they are gross
                everything = None
        self.greybox_ = everything if everything is not None and not outliers.any() else \
            self._greybox().fit(x[~outliers], t[~outliers])
        self.elm_ = self._elm().fit(x[~outliers], t[~outliers])
        self.inliers_ = ~outliers
        self.n_outliers_ = int(outliers.sum())
        x, t = x[self.inliers_], t[self.inliers_]
        rng = as_rng(self.random_state)
        inner = inner_points(x)                                    # scored: the measured points
        squared = {"stribeck": np.zeros(int(inner.sum())), "elm_auto": np.zeros(int(inner.sum()))}
        for repeat in range(int(self.n_repeats)):
            folds = interleaved_folds(x, self.n_folds, rng if repeat else None)
            held_out = np.empty_like(t)
            for k in np.unique(folds):
                out = folds == k
                held_out[out] = self._elm().fit(x[~out], t[~out]).predict(x[out]) - t[out]
            grey = self.greybox_.held_out_residuals(x, t, folds) if repeat else \
                self.greybox_.cv_residuals_                        # the same interleaved folds
            squared["elm_auto"] += held_out[inner] ** 2
            squared["stribeck"] += grey[inner] ** 2
        self.cv_rmse_ = {k: float(np.sqrt(np.mean(v) / self.n_repeats)) for k, v in squared.items()}
        gain = (squared["stribeck"] - squared["elm_auto"]) / self.n_repeats
        self.elm_gain_sigmas_ = float(np.mean(gain) / (np.std(gain, ddof=1) / np.sqrt(gain.size))) \
            if gain.size > 1 and np.std(gain) > 0 else 0.0
        self.choice_ = "elm_auto" if self.elm_gain_sigmas_ > ELM_GAIN_SIGMAS else "stribeck"
        self.chosen_ = self.greybox_ if self.choice_ == "stribeck" else self.elm_
        self.network_ = self.chosen_.network_
        self.fit_seconds_ = time.perf_counter() - start
        return self

    def warm_copy(self):
        """An unfitted estimator that refits the chosen model on data close to these (a fold
        of them): the grey-box's ``warm_copy``, or a fresh elm_auto."""
        return self.greybox_.warm_copy() if self.choice_ == "stribeck" else self._elm()

    @property
    def activation(self) -> str:
        return self.chosen_.activation

    @property
    def n_hidden(self) -> int:
        return self.chosen_.n_hidden

    def why(self) -> str:
        """One line: what was chosen and the cross-validated errors that chose it."""
        other = "elm_auto" if self.choice_ == "stribeck" else "stribeck"
        kept = (f" (elm_auto's gain {self.elm_gain_sigmas_:.2g} standard errors, within "
                f"{ELM_GAIN_SIGMAS:g}: the grey-box kept)"
                if self.choice_ == "stribeck" and self.elm_gain_sigmas_ > 0 else "")
        return (f"{self.choice_}: {self.n_repeats} x {self.n_folds}-fold cross-validated error "
                f"{self.cv_rmse_[self.choice_]:.4g} against {self.cv_rmse_[other]:.4g} for {other}"
                + kept)

    def outlier_note(self) -> str:
        return (f"{self.n_outliers_} training points rejected as gross outliers (> "
                f"{self.outlier_sigmas:g} robust sd off a running median of {MEDIAN_WINDOW})")
