"""A position that wraps, unwrapped: a single-turn encoder's angle (0 to 2 pi, -180 to 180
degrees, 0 to 4095 counts) read as a log's x jumps back by a turn each time the axis passes the
wrap, and every derivative of x (velocity, acceleration, the inertia's force) takes the jump for
motion. ``unwrapped`` finds the period from the jumps and adds the turns back.

A jump is a step of x larger than half its range, the other steps (the motion) at most
WRAP_SMOOTH of the range. The period is the jump less the motion over that
sample, the median over the jumps; every jump must give it within WRAP_AGREE (a reset of a
log's position, or a concatenation of runs, gives periods that disagree and is left alone), and
be against the motion where that motion is more than WRAP_AGREE of the period (at rest on the
wrap, x's noise carries it back and forth across it, and the motion's sign is the noise's).
A period within ROUND_WITHIN of a round one (2 pi, 360, 1, a power of two) is taken as that one;
a single jump of no round period is taken for a reset, not a wrap, and jumps of no round period
in an x of fewer than MIN_WRAP_VALUES values for the count steps of a creep.

A reset of the position while the time runs on (x set to 0 or homed mid-log) is a step of x
more than RESET_LOCAL times the largest of the RESET_SIDE steps on each side of it and than x's
finest step (an encoder's count: a count's step out of rest is motion) and more than RESET_SPAN
of x's range; each is stitched: x after it shifted by the step less the motion over
that sample, so the derivatives see no motion that did not happen. Where the time restarts or
pauses at one (runs joined end to end), x is left alone.
"""
from __future__ import annotations

import math
from typing import Callable, Dict, Optional, Tuple

import numpy as np

from ..unit_sizes import size

#: The steps that are no jumps are at most this share of x's range (else no wrap is told): a
#: log that samples a turn at least four times.
WRAP_SMOOTH = 0.4
#: A reset: a step more than RESET_LOCAL times the largest of the RESET_SIDE steps on each side,
#: and more than RESET_SPAN of x's range.
RESET_LOCAL, RESET_SIDE, RESET_SPAN = 20.0, 8, 0.02
#: A period that is no round one needs x to take at least this many values (a log that creeps
#: a few counts steps by one count between rests: motion, not wraps).
MIN_WRAP_VALUES = 64
#: Every jump's period within this share of their median.
WRAP_AGREE = 0.02
#: A period within this share of a round one is taken as the round one.
ROUND_WITHIN = 2e-3
#: Round periods: a turn in rad, in degrees, in turns, and 2^k encoder counts (k 8 to 24).
ROUND_PERIODS = ((2 * math.pi, "2 pi"), (360.0, "360"), (1.0, "1"),
                 *((float(2 ** k), f"2^{k}") for k in range(8, 25)))


def _jumps(step: np.ndarray, span: float) -> np.ndarray:
    """Which steps of x are jumps: larger than half its range ``span``."""
    return np.abs(step) > 0.5 * span


def _motion_over(step: np.ndarray, jump: np.ndarray) -> np.ndarray:
    """The motion over each jump's sample: the mean of the steps either side that are no jumps."""
    beside = np.pad(np.where(jump, np.nan, step), 1, constant_values=np.nan)
    pair = np.column_stack([beside[:-2], beside[2:]])[jump]
    known = np.isfinite(pair).sum(axis=1)
    return np.divide(np.nansum(pair, axis=1), known, out=np.zeros(known.size), where=known > 0)


def _smooth_jumps(x: np.ndarray) -> Optional[np.ndarray]:
    """Which steps of x are jumps, when it has any and its other steps are smooth (at most
    WRAP_SMOOTH of the range); None otherwise."""
    if x.size < 4 or not np.all(np.isfinite(x)):
        return None
    span, step = float(np.ptp(x)), np.diff(x)
    wrap = _jumps(step, span)
    if not wrap.any() or np.max(np.abs(step[~wrap]), initial=0.0) > WRAP_SMOOTH * span:
        return None
    return wrap


def wrap_period(x: np.ndarray) -> Optional[Tuple[float, str, int]]:
    """The period x wraps at, its name (a round period's, else its digits) and the number of
    wraps; None when x does not wrap (see the module docstring)."""
    x = np.asarray(x, dtype=float)
    wrap = _smooth_jumps(x)
    if wrap is None:
        return None
    span, step = float(np.ptp(x)), np.diff(x)
    motion, jumps = _motion_over(step, wrap), step[wrap]
    periods = np.abs(motion - jumps)
    period = float(np.median(periods))
    forward = (np.sign(jumps) == np.sign(motion)) & (np.abs(motion) > WRAP_AGREE * period)
    if np.any(forward) or \
            np.max(np.abs(periods - period)) > WRAP_AGREE * period or span > period * (1 + WRAP_AGREE):
        return None
    rounded = next(((p, name) for p, name in ROUND_PERIODS if abs(period / p - 1) <= ROUND_WITHIN), None)
    if rounded is None and (wrap.sum() < 2 or np.unique(x).size < MIN_WRAP_VALUES):
        return None                 # one jump of no round period: a reset; few values: steps
    period, name = rounded if rounded else (period, f"{period:.6g}")
    return period, name, int(wrap.sum())


def unwrapped(columns: Dict[str, np.ndarray], warn: Callable[[str], None]) -> Dict[str, np.ndarray]:
    """``columns`` with a wrapping position x unwrapped (the turns added back at each jump), and
    one line through ``warn`` saying so; unchanged when x is absent or does not wrap."""
    try:
        x = np.asarray(columns["x"], dtype=float)
    except (KeyError, TypeError, ValueError):        # no x, or none the fit can read: it says so
        return columns
    found = wrap_period(x) if x.ndim == 1 else None
    if found is None:
        return _stitched(columns, x, warn) if x.ndim == 1 else columns
    period, name, wraps = found
    step = np.diff(x)
    turns = np.where(_jumps(step, np.ptp(x)), -np.sign(step), 0.0)
    degrees = f" (x in degrees? fricgen reads rad: --scale x={size('deg'):.6g})" if name == "360" else ""
    warn(f"fricgen: x wraps at a period of {name} ({wraps} times): unwrapped, the turns added back "
         f"(a single-turn position){degrees}")
    return {**columns, "x": x + period * np.concatenate([[0.0], np.cumsum(turns)])}


def _beside(size: np.ndarray, side: int) -> np.ndarray:
    """The largest of ``size`` over the ``side`` entries before and after each (not itself)."""
    out = np.zeros_like(size)
    for s in range(1, min(side, size.size - 1) + 1):
        out[s:] = np.maximum(out[s:], size[:-s])
        out[:-s] = np.maximum(out[:-s], size[s:])
    return out


def _resets(step: np.ndarray, span: float) -> np.ndarray:
    """Which of x's steps are resets (see the module docstring); ``span``: x's range."""
    size = np.abs(step)
    if size.size < 2 * RESET_SIDE or not np.all(np.isfinite(size)):
        return np.zeros(size.size, dtype=bool)
    finest = float(size[size > 0].min(initial=np.inf))      # an encoder's count, for x in counts
    local = np.maximum(_beside(size, RESET_SIDE), finest)
    return (size > RESET_LOCAL * local) & (size > RESET_SPAN * span)


def _stitched(columns: Dict[str, np.ndarray], x: np.ndarray, warn: Callable[[str], None]) -> Dict[str, np.ndarray]:
    """``columns`` with the resets of x stitched (see the module docstring) and one line through
    ``warn`` saying so; unchanged where x has none, or where the time does not run on over one."""
    t = columns.get("t")
    if t is None or np.shape(t) != x.shape:
        return columns
    step = np.diff(x)
    jump = _resets(step, float(np.ptp(x)))
    if not jump.any():
        return columns
    dt = np.diff(np.asarray(t, dtype=float))
    usual = float(np.median(dt))
    if not (usual > 0 and np.all((dt[jump] > 0) & (dt[jump] <= 2 * usual))):
        return columns                                 # runs joined end to end: left alone
    shift = np.zeros(step.size)
    shift[jump] = _motion_over(step, jump) - step[jump]
    first = int(np.flatnonzero(jump)[0])
    warn(f"fricgen: warning: x jumps by {step[first]:.6g} at t = {float(t[first + 1]):.6g} s while the "
         f"time runs on{f' ({int(jump.sum())} times)' if jump.sum() > 1 else ''}: taken for a reset "
         "of the position and stitched (x after it shifted by the jump less the motion)")
    return {**columns, "x": x + np.concatenate([[0.0], np.cumsum(shift)])}
