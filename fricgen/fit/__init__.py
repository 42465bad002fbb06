"""Estimators from the normalized data of eq. (9) to a trained network (the AIM of eq. 3).

Every estimator follows one contract (``fricgen.fit.base.Estimator``, scikit-learn's):
``ELMRegressor`` (sections 4-5), ``AutoELMRegressor`` (the automatic ELM), ``AnfisRegressor``
(section 3), ``ConditionedELMRegressor`` (section 5), ``StribeckRegressor`` (the grey-box eq. 1),
``OracleRegressor`` (eq. 1 with the true shape and S) and ``DefaultRegressor`` (fricgen's
default: the grey-box model or the automatic ELM by cross-validation).
"""
from __future__ import annotations

from .anfis import AnfisRegressor
from .auto import AutoELMRegressor
from .base import Estimator, NotFittedError, as_rng
from .conditioning import ConditionedELMRegressor
from .elm import DEFAULT_ELM, ELMRegressor
from .default import DefaultRegressor
from .oracle import OracleRegressor
from .stribeck import StribeckRegressor


def default_elm(random_state=0, max_neurons=None) -> AutoELMRegressor:
    """The automatic ELM, which chooses its units, M and C by leave-one-out (at most
    ``max_neurons`` units if given): the default when the model must be an ELM (simulations,
    synthetic logs, the demo)."""
    return AutoELMRegressor(max_neurons=max_neurons, random_state=random_state)


def default_estimator(random_state=0, max_neurons=None, max_parameters=None) -> DefaultRegressor:
    """The estimator ``fricgen train`` uses unless told otherwise: the grey-box eq. (1) or the
    automatic ELM (at most ``max_neurons`` units), whichever has the smaller cross-validated
    error, gross outliers set aside; at most ``max_parameters`` parameters (a log's budget)."""
    return DefaultRegressor(random_state=random_state, max_neurons=max_neurons,
                            max_parameters=max_parameters)


__all__ = ["Estimator", "NotFittedError", "as_rng", "ELMRegressor", "AutoELMRegressor",
           "AnfisRegressor", "ConditionedELMRegressor", "OracleRegressor", "StribeckRegressor",
           "DefaultRegressor", "DEFAULT_ELM",
           "default_estimator", "default_elm"]
