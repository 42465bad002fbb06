"""Estimators from the normalized data of [F9] to a trained network (the AIM of [F3]).

Every estimator follows one contract (``fricgen.fit.base.Estimator``, scikit-learn's):
``ELMRegressor`` (sections 4-5), ``AutoELMRegressor`` (the automatic ELM), ``AnfisRegressor``
(section 3), ``ConditionedELMRegressor`` (section 5), ``StribeckRegressor`` (the grey-box [F1]),
``OracleRegressor`` ([F1] with the true shape and S) and ``DefaultRegressor`` (fricgen's
default: the grey-box model or the automatic ELM by cross-validation).
"""
from __future__ import annotations

from .anfis import AnfisRegressor
from .auto import AutoELMRegressor
from .base import Estimator, NotFittedError, as_rng
from .cogging import CoggingFit, identify_cogging
from .conditioning import ConditionedELMRegressor
from .elm import DEFAULT_ELM, ELMRegressor
from .default import DefaultRegressor
from .oracle import OracleRegressor
from .stribeck import StribeckRegressor


def default_elm(random_state=0, max_neurons=None) -> AutoELMRegressor:
    """The automatic ELM (``AutoELMRegressor``), which chooses its units, M and C by leave-one-out:
    the default when the model must be an ELM (simulations, synthetic logs, the demo).

    Parameters
    ----------
    random_state : int, numpy.random.Generator or None
        Passed on (the automatic ELM is deterministic).
    max_neurons : int, optional
        At most so many units.

    Returns
    -------
    AutoELMRegressor

    Examples
    --------
    >>> from fricgen.fit import default_elm
    >>> default_elm(max_neurons=12).max_neurons
    12
    """
    return AutoELMRegressor(max_neurons=max_neurons, random_state=random_state)


def default_estimator(random_state=0, max_neurons=None, max_parameters=None) -> DefaultRegressor:
    """The estimator ``fricgen train`` uses unless told otherwise (``DefaultRegressor``): the
    grey-box [F1], or the automatic ELM where it cross-validates better by more than one
    standard error, gross outliers set aside.

    Parameters
    ----------
    random_state : int, numpy.random.Generator or None
        Seeds the cross-validation partitions.
    max_neurons : int, optional
        At most so many ELM units.
    max_parameters : int, optional
        At most so many parameters in either model (a log's budget).

    Returns
    -------
    DefaultRegressor

    Examples
    --------
    >>> from fricgen.fit import default_estimator
    >>> default_estimator(random_state=3).get_params()["random_state"]
    3
    """
    return DefaultRegressor(random_state=random_state, max_neurons=max_neurons,
                            max_parameters=max_parameters)


__all__ = ["Estimator", "NotFittedError", "as_rng", "ELMRegressor", "AutoELMRegressor",
           "AnfisRegressor", "ConditionedELMRegressor", "OracleRegressor", "StribeckRegressor",
           "DefaultRegressor", "DEFAULT_ELM",
           "default_estimator", "default_elm", "CoggingFit", "identify_cogging"]
