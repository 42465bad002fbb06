"""The held-out gap: the RMS velocity error of simulations of the axis of [C1].

The simulations are restarted from the measured state every ``horizon`` samples and driven by
the measured current, on the held-out part, and compared with the measured velocity smoothed
as the residual is: the velocity sensor's noise is not something a model can close; left in,
it would set a floor under the gap that hides what an effect removes.
"""
from __future__ import annotations

import math
from typing import Sequence, Tuple

import numpy as np

from ..effects import Effect, Signals
from ..effects.timing import shifted
from ..metrics import rmse
from ..effects.presliding import bristles_of
from ..sim.axis import AxisState, MotorAxis
from ..sim.bristle_axis import BristleAxis
from ..sim.effect_law import EffectLaw
from .residual import ResidualProblem

#: Batches of the held-out samples for the standard error of a gap (``HeldOutGap``).
GAP_BATCHES = 10


def resimulate(problem: ResidualProblem, effects: Sequence[Effect], starts: np.ndarray,
               horizon: int, substeps: int = 10) -> np.ndarray:
    """Velocity of simulations restarted from the (smoothed) measured state at each of
    ``starts`` (samples at least ``horizon`` apart) for ``horizon`` samples, driven by the
    measured current (smoothed; NaN elsewhere): the axis of [C1] under the model's friction
    and ``effects``, in Karnopp steps, or, for a model with bristles or a named pre-sliding,
    on that LuGre contact (``sim.bristle_axis``) from the deflection the measured motion left
    there. A sensor delay tau (``EffectLaw.input_delay``) drives it
    with the current read tau earlier, interpolated."""
    sig = problem.signals
    n = sig.t.size
    law = EffectLaw(sig.model, effects, mass=problem.mass, force_constant=problem.force_constant)
    s0 = None
    bristles = next((e.bristles for e in effects if e.via_contact), bristles_of(sig.model))
    if bristles is not None:                # the deflection the log left at each restart
        axis = BristleAxis(law, bristles, sig.model.stribeck, sig.model.viscous_force)
        s0 = problem.deflection(bristles.stiffness)[starts]
        advance = axis.advance
    else:
        if law.lag_tau > 0:
            s0 = Signals(sig.model, v=problem.v_smooth, sample_time=problem.sample_time).lagged_speed(law.lag_tau)[starts]
        advance = MotorAxis(law).karnopp
    state = AxisState.of(problem.x_smooth[starts], problem.v_smooth[starts], sig.t[starts], s0)
    current = problem.i_smooth
    if law.input_delay:
        current = shifted(current, -law.input_delay / problem.sample_time)
    out = np.full(n, np.nan)
    for j in range(horizon):
        k = np.minimum(starts + j, n - 1)
        state = advance(state, current[k], problem.sample_time, substeps)
        k1 = starts + j + 1
        ok = k1 < n
        out[k1[ok]] = state.v[ok]
    return out


def moving_segments(problem: ResidualProblem, starts: np.ndarray, horizon: int) -> np.ndarray:
    """The samples of the simulations restarted at ``starts`` (``resimulate``) whose segment,
    from its restart on, stays in the moving part of the log (stick and break-away are not what
    a friction curve identifies), as sorted indices."""
    n = problem.moving.size
    broken = np.concatenate([[0], np.cumsum(~problem.moving)])    # broken[k] = count before k
    starts = np.asarray(starts, dtype=int)
    k = starts[:, None] + np.arange(1, horizon + 1)
    ok = (k < n) & (broken[np.minimum(k, n - 1) + 1] - broken[starts][:, None] == 0)
    return k[ok]


class HeldOutGap:
    """The held-out gap of sets of effects on ``problem``: simulations restarted every
    ``horizon`` samples from its split on, in ``substeps`` Karnopp steps per sample, compared
    on the samples whose segment stays moving (``held``)."""

    def __init__(self, problem: ResidualProblem, horizon: int, substeps: int):
        self.problem, self.horizon, self.substeps = problem, horizon, substeps
        self.starts = np.arange(problem.split, problem.moving.size - 1, horizon)
        self.held = moving_segments(problem, self.starts, horizon)

    def __call__(self, effects: Sequence[Effect]) -> Tuple[float, np.ndarray]:
        """The gap under ``effects`` and the simulated velocity."""
        v_sim = resimulate(self.problem, list(effects), self.starts, self.horizon, self.substeps)
        return rmse(self.errors(v_sim), 0.0), v_sim

    def errors(self, v_sim: np.ndarray) -> np.ndarray:
        """The simulated minus the smoothed measured velocity on the held-out samples (finite ones)."""
        held = self.held
        e = v_sim[held] - self.problem.v_smooth[held]
        return e[np.isfinite(e)]

    def standard_error(self, v_sim: np.ndarray) -> float:
        """Standard error of a held-out gap, from the mean squared error of ``GAP_BATCHES``
        consecutive batches of the held-out samples (their errors are correlated in time)."""
        e2 = self.errors(v_sim) ** 2
        if e2.size < 2 * GAP_BATCHES or not e2.mean() > 0:
            return 0.0
        means = np.array([b.mean() for b in np.array_split(e2, GAP_BATCHES)])
        return float(means.std(ddof=1) / math.sqrt(GAP_BATCHES) / (2.0 * math.sqrt(e2.mean())))
