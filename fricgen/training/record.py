"""model.json's ``training`` record: how each curve was fitted (the method, the model chosen, a
grey-box curve's standard errors), its training and validation errors, and the axis of the data.

What the record says of an estimator is registered per estimator type (``functools.singledispatch``):
a new estimator adds its functions here rather than a branch to a chain.
"""
from __future__ import annotations

from functools import singledispatch
from typing import Optional

import numpy as np

from ..data.identification import Identification
from ..data.sweep import Sweep
from ..fit import DEFAULT_ELM, AutoELMRegressor, DefaultRegressor, ELMRegressor, StribeckRegressor
from ..fit.elm import EnlargedScheme
from ..fit.stribeck import measured
from ..fit.textbook import LawFit, TextbookRegressor
from ..metrics import rmse


@singledispatch
def method_record(estimator) -> dict:
    """model.json's ``training.method`` (and the ELM's options) for ``estimator``."""
    return {"method": type(estimator).__name__, "scheme": type(estimator).__name__}


@method_record.register
def _(estimator: DefaultRegressor) -> dict:
    return {"method": "auto", "scheme": "auto"}


@method_record.register
def _(estimator: AutoELMRegressor) -> dict:
    return {"method": "elm_auto", "scheme": "elm_auto"}


@method_record.register
def _(estimator: StribeckRegressor) -> dict:
    return {"method": "stribeck", "scheme": "stribeck"}


@method_record.register
def _(estimator: ELMRegressor) -> dict:
    scheme = estimator.scheme
    if scheme == "enlarged":
        scheme = EnlargedScheme()
    enlarged = isinstance(scheme, EnlargedScheme)
    return {"method": "elm", "scheme": "enlarged" if enlarged else scheme,
            "w_max": scheme.w_max if enlarged else DEFAULT_ELM["scheme"].w_max,
            "solver": estimator.solver}


@singledispatch
def validation_error(estimator) -> tuple:
    """The kind and value of the error on held-out points that the fit report prints."""
    return "leave-one-out", estimator.loo_rmse_


@validation_error.register
def _(estimator: DefaultRegressor) -> tuple:
    return "cross-validated", estimator.cv_rmse_[estimator.choice_]


@validation_error.register
def _(estimator: StribeckRegressor) -> tuple:
    return "cross-validated", estimator.cv_rmse_


@singledispatch
def chosen_record(estimator) -> dict:
    """model.json's training record of the model an estimator fitted (an ELM's by default)."""
    return {"activation": estimator.activation, "n_hidden": estimator.n_hidden, "C": estimator.C_}


@chosen_record.register
def _(estimator: DefaultRegressor) -> dict:
    entry = chosen_record(estimator.chosen_)
    extra = {"choice": estimator.choice_, "choice_reason": estimator.why(),
             "n_outliers_rejected": estimator.n_outliers_}
    keys = list(entry)
    return {**{k: entry[k] for k in keys[:2]}, **extra, **{k: entry[k] for k in keys[2:]}}


@chosen_record.register
def _(estimator: StribeckRegressor) -> dict:
    return {"activation": estimator.activation, "n_hidden": estimator.n_hidden,
            "shape": estimator.shape_, "n_sources": estimator.n_sources_}


@validation_error.register
def _(estimator: TextbookRegressor) -> tuple:
    """The law's held-out error, over both directions' points (its ``law`` line's); a curve
    its points do not determine (a direction of 2 points on its own line) had none held out."""
    determined = all(np.isfinite(se) for se in estimator.law_.standard_errors.values())
    return ("the law's held-out" if determined else
            "the law's held-out (the other direction's points: none of these was held out)",
            estimator.cv_rmse_)


@chosen_record.register
def _(estimator: TextbookRegressor) -> dict:
    law = estimator.law_
    entry = {"activation": "stribeck", "n_hidden": estimator.n_hidden,
             "law": "coulomb_viscous_stribeck" if law.stribeck else "coulomb_viscous",
             "coulomb": law.coulomb, "viscous": law.viscous}
    if law.stribeck:
        entry.update(static=law.static, v_s=law.v_s, shape=law.shape)
    entry["standard_errors"] = {k: (v if np.isfinite(v) else None)
                                for k, v in law.standard_errors.items()}
    return entry


@singledispatch
def fitted_rows(estimator, x: np.ndarray) -> np.ndarray:
    """A mask of the training points ``x`` the estimator fitted (the default sets gross
    outliers aside; the grey-box fits the measured points, ``fricgen.fit.stribeck.measured``)."""
    return np.ones(x.shape, dtype=bool)


@fitted_rows.register
def _(estimator: StribeckRegressor, x: np.ndarray) -> np.ndarray:
    return measured(x)


@fitted_rows.register
def _(estimator: DefaultRegressor, x: np.ndarray) -> np.ndarray:
    return estimator.inliers_ & (measured(x) if estimator.choice_ == "stribeck" else True)


def curve_errors(dataset, estimator) -> dict:
    """The errors of the report; E_train over the points fitted (not the gross outliers the
    default sets aside, nor the point at v = 0 the grey-box leaves out)."""
    rows = fitted_rows(estimator, dataset.x)
    e_train = rmse(estimator.predict(dataset.x[rows]), dataset.t[rows])
    kind, e_validation = validation_error(estimator)
    return {"e_train": e_train, "e_train_newton": e_train / dataset.scaling.k_out,
            "e_loo": e_validation, "e_loo_newton": e_validation / dataset.scaling.k_out,
            "e_validation_kind": kind}


def curve_record(fit) -> dict:
    """model.json's training record of one fitted curve: what was chosen, a grey-box curve's
    standard errors in SI units (infinite, written null, where the data do not determine a
    source: emit refuses it) and the errors."""
    entry = chosen_record(fit.estimator)
    chosen = getattr(fit.estimator, "chosen_", fit.estimator)
    if isinstance(chosen, StribeckRegressor):
        se, s = chosen.standard_errors_, fit.dataset.scaling
        entry["standard_errors"] = {"amplitudes_newton": (se["amplitudes"] / s.k_out).tolist(),
                                    "stribeck_m_per_s": (se["stribeck"] / s.k_in).tolist()}
    return {**entry, "metrics": curve_errors(fit.dataset, fit.estimator)}


def speed_record(slowest: float, fastest: float) -> dict:
    """model.json's ``training.axis`` of data that identify no axis: the speed range alone."""
    return {"mass": None, "mass_se": None, "mass_from": None, "force_constant": None,
            "offset": None, "offset_se": None, "speed_min": slowest, "speed_max": fastest}


def axis_record(sweep: Sweep, ident: Optional[Identification], asymmetric: bool) -> dict:
    """model.json's ``training.axis``: the mass, force constant and constant force that training
    identified or was given (null for a sweep; the offset null where the asymmetric model's
    curves hold it, not a load taken out of them), and the speed range of the data."""
    speed = np.abs(sweep.v[sweep.v != 0])
    record = speed_record(float(speed.min()), float(speed.max()))
    if ident is not None:
        body = ident.body
        if body.mass > 0:               # an inertia identified as 0 (pass --mass) records none
            record.update(mass=body.mass, mass_se=body.mass_se,
                          mass_from="data" if body.mass_identified else "option")
        if not asymmetric or ident.load:
            record.update(offset=body.offset, offset_se=body.offset_se)
        if ident.force_constant is not None:
            record["force_constant"] = ident.force_constant[0]
    return record


def law_record_edits(model) -> list:
    """Where a textbook law's record (``training``'s coulomb, viscous, static, v_s, shape, and
    ``training.negative``'s of a per-direction law) no longer gives the model's force over the
    trained speeds (``training.axis``): the records' names ("training", "training.negative").
    The record is read, never used: eval and emit run the model's own fields, which the
    model_hash covers, so a record edited by hand changes nothing and is said to."""
    training = model.training
    axis = training.get("axis") or {}
    slowest, fastest = axis.get("speed_min"), axis.get("speed_max")
    if "coulomb" not in training or model.inputs is not None or not (
            isinstance(slowest, (int, float)) and isinstance(fastest, (int, float))
            and 0 < slowest <= fastest < np.inf):
        return []
    edited = []
    for name, record, sign in (("training", training, 1.0),
                               ("training.negative", training.get("negative") or training, -1.0)):
        if "coulomb" not in record:
            continue
        # up to the direction's own v_sat (the other's may be faster), beyond which the model
        # runs on with its slope and the law with its curve
        curve = (model.negative if sign < 0 else model.positive) or model
        speed = np.geomspace(slowest, max(slowest, min(fastest, curve.v_sat)), 9)
        force = sign * model.force(sign * speed)
        try:
            law = LawFit(record["coulomb"], record["viscous"], record.get("static"),
                         record.get("v_s"), record.get("shape"), {}, fastest, 0.0).magnitude(speed)
            kept = np.allclose(law, force, rtol=1e-6, atol=1e-9 * float(np.max(np.abs(force))))
        except (KeyError, TypeError, ValueError):
            kept = False
        if not kept:
            edited.append(name)
    return edited
