"""Estimators from the normalized data of eq. (9) to a trained network (the AIM of eq. 3).

Every estimator follows one contract (``fricgen.fit.base.Estimator``, scikit-learn's):
``ELMRegressor`` (sections 4-5), ``AutoELMRegressor`` (fricgen's default), ``AnfisRegressor``
(section 3), ``ConditionedELMRegressor`` (section 5) and ``OracleRegressor`` (eq. 1 itself).
"""
from __future__ import annotations

from .anfis import AnfisRegressor
from .auto import AutoELMRegressor
from .base import Estimator, NotFittedError, as_rng
from .conditioning import ConditionedELMRegressor
from .elm import DEFAULT_ELM, ELMRegressor
from .oracle import OracleRegressor


def default_estimator(random_state=0, max_neurons=None) -> AutoELMRegressor:
    """The estimator ``fricgen train`` uses unless told otherwise: the automatic ELM, which
    chooses its units, M and C by leave-one-out (at most ``max_neurons`` units if given)."""
    return AutoELMRegressor(max_neurons=max_neurons, random_state=random_state)


__all__ = ["Estimator", "NotFittedError", "as_rng", "ELMRegressor", "AutoELMRegressor",
           "AnfisRegressor", "ConditionedELMRegressor", "OracleRegressor", "DEFAULT_ELM",
           "default_estimator"]
