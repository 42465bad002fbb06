"""The load and temperature dependence of a fitted curve (``effects.load_temperature``),
identified from a log's friction samples and the load and temperature at the same rows.

With the curve's velocity-weakening part l(v) = F0(v) - B v and viscous part b(v) = B v, the
samples are fitted by nonlinear least squares as

    f = c_l l(v) (1 + s_q |L|) exp(-k_c dT) + c_v b(v) exp(-k_v dT),

c_l and c_v rescaling the curve (they are folded into it). What the data cannot determine is
left out and said: a load dependence needs |L| to vary (its spread at least LOAD_SPREAD of its
largest value), its two quadrant slopes need rows in both quadrants (QUADRANT_SHARE of the
loaded rows each; else one slope for both; where the load keeps one sign the quadrants are the
directions of motion, and the report says the other sign is untested), a temperature
dependence needs a span of TEMPERATURE_SPAN degC. The slopes are bounded so that the factors
stay within LEAST_FACTOR and LARGEST_FACTOR over the trained box. The forms
(none, load, temperature, both, as determined) are scored by cross-validation in contiguous
blocks of the log's rows (``fit.directions.row_folds``), each with a correction of the curve by
any function of v (``data.idim.friction_basis``: a dependence is kept for what no curve of v
explains, not for the curve's own misfit, which the load would stand in for where the motion
ties |L| to v), and the simplest within one standard error of the paired fold differences of
the best is kept, as ``fit.law_choice`` chooses a law: a log at one load and one temperature
keeps the one-input model.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, Optional, Tuple

import numpy as np
from scipy.optimize import least_squares

from ..effects.load_temperature import (LARGEST_EXPONENT, LARGEST_FACTOR, LEAST_FACTOR,
                                        LoadDependence, LoadTemperature, TemperatureDependence)
from ..data.idim import friction_basis
from .directions import CV_FOLDS, row_folds
from .law_choice import SE_RULE

#: |L| must spread (standard deviation) by this share of its largest value to determine a slope.
LOAD_SPREAD = 0.05
#: Each quadrant (driving, back-driving) needs this share of the loaded rows for its own slope.
QUADRANT_SHARE = 0.1
#: A temperature dependence needs the log to span this many degC (a sensor's 0.1 degC steps and a
#: few degrees of drift determine no slope).
TEMPERATURE_SPAN = 3.0
#: The parameters, in the order of the fit's vector.
PARAMETERS = ("levels_scale", "viscous_scale", "load_driving", "load_back_driving",
              "temperature_levels", "temperature_viscous")


@dataclass(frozen=True)
class Form:
    """Which dependences a fit holds: ``load`` (one slope, or two with ``quadrants``),
    ``temperature``."""

    load: bool = False
    quadrants: bool = False
    temperature: bool = False

    scaled: bool = True

    @property
    def free(self) -> np.ndarray:
        """The mask of PARAMETERS this form fits (the curve's scales unless ``scaled`` is off:
        a curve fitted at the reference point already)."""
        return np.array([self.scaled, self.scaled, self.load, self.load and self.quadrants,
                         self.temperature, self.temperature])

    @property
    def name(self) -> str:
        parts = (["load"] if self.load else []) + (["temperature"] if self.temperature else [])
        return " + ".join(parts) or "velocity only"


@dataclass
class Samples:
    """Friction samples with their operating point: v, f, the curve's parts at v, |L|, the
    quadrant (v L > 0), dT = T - T_ref (zeros where the log has no such column)."""

    f: np.ndarray
    level: np.ndarray
    viscous: np.ndarray
    load: np.ndarray
    driving: np.ndarray
    dt: np.ndarray
    #: columns spanning any friction curve of v (``data.idim.friction_basis``): the choice's
    #: correction of the curve, so that no form wins by what a curve of v would explain
    curve: np.ndarray

    def take(self, rows) -> "Samples":
        return Samples(*(getattr(self, k)[rows] for k in
                         ("f", "level", "viscous", "load", "driving", "dt", "curve")))


def predict(p: np.ndarray, s: Samples) -> np.ndarray:
    """The friction of the module's form at the parameters ``p`` (all of PARAMETERS)."""
    c_l, c_v, s_d, s_b, k_c, k_v = p
    slope = np.where(s.driving, s_d, s_b)
    return (c_l * s.level * (1.0 + slope * s.load) * np.exp(-k_c * s.dt)
            + c_v * s.viscous * np.exp(-k_v * s.dt))


def _bounds(s: Samples) -> Tuple[np.ndarray, np.ndarray]:
    """The parameters' bounds: the slopes those that keep the factors within their limits over
    the samples' |L| and dT."""
    top = max(float(np.max(s.load)), 1e-300)
    reach = max(float(np.max(np.abs(s.dt))), 1e-300)
    low = np.array([0.0, 0.0, (LEAST_FACTOR - 1.0) / top, (LEAST_FACTOR - 1.0) / top,
                    -LARGEST_EXPONENT / reach, -LARGEST_EXPONENT / reach])
    high = np.array([np.inf, np.inf, (LARGEST_FACTOR - 1.0) / top, (LARGEST_FACTOR - 1.0) / top,
                     LARGEST_EXPONENT / reach, LARGEST_EXPONENT / reach])
    return low, high


def _fit(form: Form, s: Samples, corrected: bool = False):
    """The parameters of ``form`` (the others 0, the scales 1 where not fitted, the back-driving
    slope the driving one's without quadrants), slopes bounded (``_bounds``); with
    ``corrected``, beside them the linear coefficients of the curve's correction
    (``Samples.curve``). Returns the parameters, the correction's coefficients (empty without)
    and the Jacobian of the free parameters and coefficients at the optimum."""
    free = form.free
    m = int(free.sum())
    k = s.curve.shape[1] if corrected else 0
    start = np.array([1.0, 1.0, 0.0, 0.0, 0.0, 0.0])
    low, high = _bounds(s)

    def full(q):
        p = start.copy()
        p[free] = q[:m]
        if form.load and not form.quadrants:
            p[3] = p[2]
        return p

    def residual(q):
        r = predict(full(q), s) - s.f
        return r + s.curve @ q[m:] if k else r

    result = least_squares(residual, np.concatenate([start[free], np.zeros(k)]), x_scale="jac",
                           bounds=(np.concatenate([low[free], np.full(k, -np.inf)]),
                                   np.concatenate([high[free], np.full(k, np.inf)])))
    return full(result.x), result.x[m:], result.jac


@dataclass
class DependenceFit:
    """The dependence kept (``inputs``; None: velocity only) with the curve's rescaling, each
    parameter's estimate and standard error, what the data do not determine, and the held-out
    mean squared error of each form tried."""

    inputs: Optional[LoadTemperature]
    scale: Tuple[float, float]
    estimates: Dict[str, Tuple[float, float]]
    undetermined: Dict[str, str] = field(default_factory=dict)
    cv_mse: Dict[str, float] = field(default_factory=dict)
    form: Form = Form()
    #: RMS of the samples about the fitted friction
    rms: float = 0.0

    @property
    def chosen(self) -> str:
        return self.form.name


def _forms(load, temperature, v) -> Tuple[list, Dict[str, str]]:
    """The forms the data determine, simplest first, and why the others are left out."""
    undetermined: Dict[str, str] = {}
    has_load = quadrants = False
    if load is not None:
        magnitude = np.abs(load)
        top = float(magnitude.max())
        if not top > 0 or float(magnitude.std()) < LOAD_SPREAD * top:
            undetermined["load"] = (f"|load| hardly varies (standard deviation {float(magnitude.std()):.2g} "
                                    f"about {float(magnitude.mean()):.4g}): the log determines no load slope")
        else:
            has_load = True
            loaded = magnitude > LOAD_SPREAD * top
            driving = float(np.mean((v * load)[loaded] > 0))
            quadrants = min(driving, 1.0 - driving) >= QUADRANT_SHARE
            if not quadrants:
                undetermined["quadrants"] = (f"the drive drives the load on {100 * driving:.0f} % of "
                                             "the loaded rows: one slope for both quadrants")
            positive = float(np.mean(load[loaded] > 0))
            if max(positive, 1.0 - positive) > 1.0 - QUADRANT_SHARE:
                undetermined["sign"] = (f"the load keeps one sign on {100 * max(positive, 1 - positive):.0f} "
                                        "% of the loaded rows: driving and back-driving are the two "
                                        "directions of motion there, and the model is not tested at "
                                        "the other sign")
    has_temperature = False
    if temperature is not None:
        span = float(np.ptp(temperature))
        if span < TEMPERATURE_SPAN:
            undetermined["temperature"] = (f"the temperature spans {span:.2g} degC (at least "
                                           f"{TEMPERATURE_SPAN:g}): the log determines no "
                                           "temperature dependence")
        else:
            has_temperature = True
    forms = [Form()]
    if has_load:
        forms.append(Form(load=True, quadrants=quadrants))
    if has_temperature:
        forms.append(Form(temperature=True))
    if has_load and has_temperature:
        forms.append(Form(load=True, quadrants=quadrants, temperature=True))
    return forms, undetermined


def _cross_validated(forms, s: Samples, blocks: int) -> Tuple[np.ndarray, np.ndarray]:
    """Each form's held-out squared error per fold (forms x folds) and the fold of each row."""
    folds = row_folds(s.f.size, CV_FOLDS, blocks=blocks)
    errors = np.zeros((len(forms), CV_FOLDS))
    for k in range(CV_FOLDS):
        train, test = folds != k, folds == k
        for j, form in enumerate(forms):
            p, c, _ = _fit(form, s.take(train), corrected=True)
            held = s.take(test)
            errors[j, k] = float(np.mean((predict(p, held) + held.curve @ c - held.f) ** 2))
    return errors, folds


def _simplest_within_noise(errors: np.ndarray) -> int:
    """The first (simplest) form whose mean held-out error is within SE_RULE standard errors
    of the paired fold differences of the best one's."""
    mean = errors.mean(axis=1)
    best = int(np.argmin(mean))
    for j in range(len(errors)):
        diff = errors[j] - errors[best]
        if diff.mean() <= SE_RULE * diff.std(ddof=1) / np.sqrt(diff.size) + 1e-300:
            return j
    return best


def samples_of(model, v, f, load=None, temperature=None, reference: float = 0.0) -> Samples:
    """The samples of a log for the model's curve (its ``force`` and ``viscous_force`` at v)."""
    v = np.asarray(v, dtype=float)
    viscous = model.viscous_force(v)
    zeros = np.zeros(v.size)
    return Samples(f=np.asarray(f, dtype=float), level=model.force(v) - viscous, viscous=viscous,
                   load=zeros if load is None else np.abs(load),
                   driving=zeros.astype(bool) if load is None else v * load > 0,
                   dt=zeros if temperature is None else np.asarray(temperature) - reference,
                   curve=friction_basis(v, odd=False))


def fit_dependence(model, v, f, load=None, temperature=None, independence: float = 1.0,
                   blocks: int = 0, form: Optional[Form] = None) -> DependenceFit:
    """The dependence of the friction samples (v, f) on ``load`` and ``temperature`` (arrays at
    the same rows, or None) beside the one-input ``model``'s curve (see the module).
    ``independence``: independent samples per row (smoothing); ``blocks``: rows per block of
    the cross-validation; ``form`` skips the choice (a refit after the curve's)."""
    v = np.asarray(v, dtype=float)
    reference = None if temperature is None else float(np.round(np.median(temperature)))
    s = samples_of(model, v, f, load, temperature, reference or 0.0)
    forms, undetermined = _forms(load, temperature, v)
    cv: Dict[str, float] = {}
    if form is None:
        if len(forms) > 1:
            errors, _ = _cross_validated(forms, s, blocks)
            cv = {fm.name: float(e) for fm, e in zip(forms, errors.mean(axis=1))}
            form = forms[_simplest_within_noise(errors)]
        else:
            form = forms[0]
    p, _, jac = _fit(form, s)
    residual = predict(p, s) - s.f
    dof = max(s.f.size - int(form.free.sum()), 1)
    cov = np.linalg.pinv(jac.T @ jac) * float(residual @ residual) / dof / max(independence, 1e-9)
    se = np.zeros(len(PARAMETERS))
    se[form.free] = np.sqrt(np.maximum(np.diag(cov), 0.0))
    if form.load and not form.quadrants:
        se[3] = se[2]
    estimates = {name: (float(p[k]), float(se[k])) for k, name in enumerate(PARAMETERS)
                 if form.free[k] or (k == 3 and form.load)}
    inputs = _dependence(form, p, load, temperature, reference)
    return DependenceFit(inputs=inputs, scale=(float(p[0]), float(p[1])), estimates=estimates,
                         undetermined=undetermined, cv_mse=cv, form=form,
                         rms=float(np.sqrt(np.mean(residual ** 2))))


def _dependence(form: Form, p, load, temperature, reference) -> Optional[LoadTemperature]:
    """The ``LoadTemperature`` of a fitted form (None for velocity only), its slopes limited to
    what keeps a friction (LEAST_FACTOR, LARGEST_EXPONENT) over the trained box."""
    if not (form.load or form.temperature):
        return None
    load_dep = temp_dep = None
    if form.load:
        largest = float(np.max(np.abs(load)))
        floor = (LEAST_FACTOR - 1.0) / largest
        load_dep = LoadDependence(max(float(p[2]), floor), max(float(p[3]), floor), largest)
    if form.temperature:
        span = (float(np.min(temperature)), float(np.max(temperature)))
        reach = max(abs(span[0] - reference), abs(span[1] - reference), 1e-9)
        limit = LARGEST_EXPONENT / reach
        temp_dep = TemperatureDependence(reference, float(np.clip(p[4], -limit, limit)),
                                         float(np.clip(p[5], -limit, limit)), span)
    return LoadTemperature(load=load_dep, temperature=temp_dep)
