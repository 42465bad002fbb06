"""Output-error refinement: the selected effects' parameters fitted to simulations of the fit part.

Selection fits each effect to the force residual phi i - m a - F(v) of [C1] (equation error).
The acceleration in it is a smoothed derivative of a noisy velocity, and the friction model is
close to the axis' but not equal, so the fitted values carry a small bias; the held-out gap,
which simulates the axis, is sensitive to it (a force constant 1 % off can leave a gap 40 %
above the true one's). Here the named effects' parameters are fitted again, by least squares
on the velocity errors of simulations restarted from the measured state on the fit part
(the held-out part is not touched, so the held-out gap stays an honest score). Zero values
are structural and stay, but a time constant whose 0 means none (``Effect.time_constants``:
a linear drift's) is fitted as its inverse, from 0 on: selection's choice between a linear and
a saturating drift, made on the force residual, is made again on the simulations. Position and
velocity tables keep their knots.
"""
from __future__ import annotations

from dataclasses import fields, replace
from typing import List, Sequence, Tuple

import numpy as np
from scipy.optimize import least_squares

from ..effects import EFFECTS, Effect
from .gap import moving_segments, resimulate
from .residual import ResidualProblem

#: Most restarted simulations of the fit part the refinement compares (spread over the part).
MAX_SEGMENTS = 4000
#: Most simulations per refinement, over the free parameters plus one.
NFEV_PER_PARAMETER = 12


def _free(effect: Effect, held: Sequence[str] = ()) -> List[Tuple[str, int]]:
    """(field, index) of the effect's free values (index -1 for a scalar): the non-zero ones
    and its ``time_constants``, but the fields ``held``; none for an effect without a physical
    name (a table)."""
    if effect.name not in EFFECTS:
        return []
    out = []
    for f in fields(effect):
        if f.name in effect.fixed or f.name in held or f.name == "shape":
            continue
        value = getattr(effect, f.name)
        if isinstance(value, float):
            out += [(f.name, -1)] if value != 0.0 or f.name in effect.time_constants else []
        elif isinstance(value, (tuple, list)):
            out += [(f.name, j) for j, x in enumerate(value) if isinstance(x, float) and x != 0.0]
    return out


def _inverse(x: float) -> float:
    """1 / x, and 0 for 0: a time constant and its rate, 0 meaning none both ways."""
    return 1.0 / x if x != 0.0 else 0.0


def _value(effect: Effect, name: str, j: int) -> float:
    """The value the refinement fits: the parameter, or the inverse of a time constant."""
    value = getattr(effect, name)
    return _inverse(value) if name in effect.time_constants else (value if j < 0 else value[j])


def _with_values(effects: Sequence[Effect], slots, values) -> List[Effect]:
    out = list(effects)
    for (k, name, j), x in zip(slots, values):
        if name in out[k].time_constants:
            x = _inverse(float(x))
        if j < 0:
            out[k] = replace(out[k], **{name: float(x)})
        else:
            seq = list(getattr(out[k], name))
            seq[j] = float(x)
            out[k] = replace(out[k], **{name: type(getattr(out[k], name))(seq)})
    return out


def fit_part_segments(problem: ResidualProblem, horizon: int) -> np.ndarray:
    """Restarts every ``horizon`` samples whose simulation ends a smoothing window before the
    held-out part (the smoothed signals it compares with read nothing of that part), at most
    ``MAX_SEGMENTS`` of them, evenly spread."""
    starts = np.arange(0, problem.split - horizon - problem.window, horizon)
    if starts.size > MAX_SEGMENTS:
        starts = starts[np.linspace(0, starts.size - 1, MAX_SEGMENTS).round().astype(int)]
    return starts


def output_error_fit(problem: ResidualProblem, base: Sequence[Effect], effects: Sequence[Effect],
                     horizon: int, substeps: int) -> Tuple[List[Effect], float, float]:
    """``effects`` (beside the model's own ``base``) with their free values fitted to the
    velocity of simulations restarted every ``horizon`` samples on the fit part
    (``fit_part_segments``), within each parameter's limits (the period of a position series
    stays when the problem has a known ``pitch``); the fit part's RMS velocity
    error before and after. The effects come back as they are when nothing is free or the
    fitted values cannot be named (``Effect.refused``: not what the names say, or a delay
    the log cannot resolve)."""
    effects = list(effects)
    slots = [(k, name, j) for k, e in enumerate(effects)
             for name, j in _free(e, e.given_by_pitch if problem.pitch is not None else ())]
    starts = fit_part_segments(problem, horizon)
    samples = moving_segments(problem, starts, horizon)

    def errors(values):
        v = resimulate(problem, list(base) + _with_values(effects, slots, values), starts,
                       horizon, substeps)
        e = v[samples] - problem.v_smooth[samples]
        return np.where(np.isfinite(e), e, 0.0)

    x0 = np.array([_value(effects[k], name, j) for k, name, j in slots])
    first = errors(x0)
    before = float(np.sqrt(np.mean(first ** 2))) if samples.size else float("nan")
    if not slots or samples.size < 2 * len(slots):
        return effects, before, before
    scale = np.abs(x0)
    lo, hi = np.full(x0.size, -np.inf), np.full(x0.size, np.inf)
    # the inverse of a time constant: from 0 (none) to 20 / the log's span, in units of
    # 1 / span
    span = max(float(np.ptp(problem.signals.t)), problem.sample_time)
    inverse = np.array([name in effects[k].time_constants for k, name, _ in slots])
    for m, (k, name, j) in enumerate(slots):
        if inverse[m]:
            scale[m], lo[m], hi[m] = 1.0 / span, 0.0, max(20.0 / span, x0[m])
            continue
        low, high = effects[k].limits().get(name, (-np.inf, np.inf))
        if name in effects[k].positive:
            low = max(low, 1e-3 * x0[m])
        lo[m], hi[m] = min(low, x0[m]), max(high, x0[m])
    z0 = x0 / scale

    def scaled(z):                  # the start's errors are known: least_squares asks first
        return first if np.array_equal(z, z0) else errors(z * scale)
    fit = least_squares(scaled, z0, bounds=(lo / scale, hi / scale), diff_step=1e-3,
                        max_nfev=NFEV_PER_PARAMETER * (x0.size + 1))
    z = np.where(inverse & (fit.x < 1e-6), 0.0, fit.x)             # T of 1e6 spans: none
    refined = _with_values(effects, slots, z * scale)
    after = float(np.sqrt(np.mean(fit.fun ** 2)))
    if not after < before or any(e.refused(problem.sample_time) for e in refined):
        return effects, before, before
    return refined, before, after
