"""Plausibility of well-formed data: columns that are numbers, yet cannot be the axis they claim.

Each check returns nothing when the data are plausible; otherwise it refuses with one
``DataError`` line naming the column and the likely cause, or, where the user said the data
really are unusual (``--accept-unusual``), gives that line back as a warning:

- ``check_bounds``: the fastest speed, the largest force and current within
  ``_validate.PHYSICAL`` (a speed in mm/s read as m/s, a force in mN, a current in mA), with
  the ``--scale`` that would bring it there;
- ``check_sweep_shape``: a sweep whose force follows the speed as friction does (section 2:
  the force of [F1] is a function of v, from a Coulomb level at low speed): swapped columns
  (the speed then never comes near 0, and v follows f more closely than f follows v), or a force
  that scatters about any curve of v by more than its own level (a fit would explain nothing);
- ``check_merge_shift``: the ``--merge-shift`` of two instruments' files near the one at which
  the force best fits the motion (f = m dv/dt + friction, [C1], searched over shifts).
"""
from __future__ import annotations

import math
from typing import Callable, Dict, Mapping, Optional, Tuple

import numpy as np

from .._validate import (ACCEPT_UNUSUAL, PHYSICAL_ROTARY, USUAL_MIN, in_rotary_axis, physical_problem,
                         physical_range, physical_unit, rotary_units, unusual, unusually_small, usual_max)
from ..errors import DataError
from ..units import axis_units
from .idim import friction_basis
from .log_columns import check_force_swap
from .motionlog import check_swapped_force, varies
from .outliers import running_median
from .smoothing import smooth

#: A sweep whose slowest speed exceeds this share of its fastest never nears v = 0, where
#: friction has its Coulomb level and Stribeck drop (a speed column that holds forces).
SLOWEST_SHARE = 0.2
#: v follows f this much more closely than f follows v (robust scatter about a running median,
#: relative to the level): the columns are the other way round.
SWAP_RATIO = 0.5
#: The force scatters about any curve of v by more than this share of its median level: no
#: friction curve is in the data (a fit would explain nothing).
NOTHING_EXPLAINED = 0.5
#: The share of rows whose magnitudes the bounds leave out (glitches; ``_top``).
TOP_SHARE = 0.01
#: A motion log sampled slower than this (Hz) is beyond any drive's or DAQ's log: time in ms
#: read as s lands there (and gives an inertia a thousand times the axis's, at 1 kHz).
USUAL_MIN_RATE = 10.0
#: The share of a sweep's rows that may repeat an earlier row exactly before one warning line:
#: points written with few digits repeat now and then, a file joined twice repeats them all.
REPEATED_SHARE = 0.1
#: Rows the shape and shift checks look at (evenly thinned beyond).
CHECK_ROWS = 100_000
#: A merge shift is off when the force fits the motion at another shift this much better
#: (residual variance) and that shift is this many of the slower clock's steps away.
SHIFT_GAIN, SHIFT_STEPS = 2.0, 5
#: Shifts tried over the span, before the best is refined tenfold.
COARSE_SHIFTS = 401


def _thin(n: int) -> slice:
    return slice(None, None, max(1, math.ceil(n / CHECK_ROWS)))


def refuse_or_warn(message: str, accept_unusual: bool, warn: Callable[[str], None]) -> None:
    if not accept_unusual:
        raise DataError(f"{message} ({ACCEPT_UNUSUAL} to use the data as they are)")
    warn(f"fricgen: warning: {message}; used as it is ({ACCEPT_UNUSUAL})")


def _unit_factor(quantity: str, value: float) -> Optional[float]:
    """The smallest power of 1000 that brings ``value`` into ``physical_range(quantity)`` (the
    axis's own: linear or rotary), or None."""
    low, high, _ = physical_range(quantity)
    step = 1e-3 if value > high else 1e3
    return next((step ** k for k in range(1, 5) if low <= value * step ** k <= high), None)


def _unit_hint(column: str, quantity: str, value: float) -> str:
    """'; is v in mm/s? --scale v=0.001 converts it': the smallest power of 1000 that brings
    ``value`` into ``physical_range(quantity)``, or ''. A rotary axis's speed too fast asks for
    degrees or rpm first (``_validate.rotary_units``); a linear axis's, whether it is a rotary one
    in rad/s, rpm or deg/s (a joint's sweep in deg/s taken as rad/s on the first hint alone gave
    a viscous friction 57 times too small)."""
    low, high, _ = physical_range(quantity)
    if quantity == "speed" and value > high and in_rotary_axis():
        named = rotary_units(column, column, lambda size: low <= value * size <= high)
        if named:           # degrees or rpm before any power of 1000
            return f"; is {column} in {named}?"
    factor = _unit_factor(quantity, value)
    if factor is None:
        return ""
    unit = axis_units().position if column == "x" else physical_unit(quantity)   # x: its own unit
    prefix = {1e-3: "m", 1e-6: "u", 1e3: "k"}.get(factor)
    named = f"is {column} in {prefix}{unit}? " if prefix else ""
    rotary = ""
    if quantity == "speed" and value > high and not in_rotary_axis():
        low_r, high_r = PHYSICAL_ROTARY["speed"][:2]
        units = rotary_units(column, column if column == "x" else "v",
                             lambda size: low_r <= value * size <= high_r)
        readings = []
        if value <= high_r:                 # rad/s itself, where the speed is a shaft's
            readings.append(f"{column} in rad{'' if column == 'x' else '/s'}")
        if units:
            readings.append(f"in {units}")
        if readings:
            rotary = f"; or is the axis a joint or shaft (--rotary), {', or '.join(readings)}?"
    return f"; {named}--scale {column}={factor:g} converts it{rotary}"


#: The hint for a position of whole numbers too fast for the axis: the encoder's counts, whose
#: size no power of 1000 gives (a power that brings the speed within bounds is a plausible
#: wrong one: 2^16 counts a turn are 9.59e-5 rad each, not 0.001).
COUNTS_HINT = ("; x holds whole numbers: encoder counts? --scale x=M converts them, M the radians "
               "(2 pi over the counts per turn) or the metres of one count")


def whole_numbers(values: np.ndarray) -> bool:
    """Whether every value is a whole number (and not all 0): a position in encoder counts."""
    return bool(np.any(values) and np.all(values == np.round(values)))


def _top(values: np.ndarray) -> float:
    """The largest magnitude of ``values`` but for the top TOP_SHARE of rows: a glitch row (a
    gross outlier, which training sets aside) is no unit."""
    return float(np.quantile(np.abs(values), 1.0 - TOP_SHARE))


def top_speed(columns: Dict[str, np.ndarray]) -> Optional[Tuple[str, float]]:
    """The fastest speed but for the top TOP_SHARE of rows (``_top``) and the column it is of:
    of |v|, or of |dx/dt| of a log without v ("x"); None where neither is there."""
    if "v" in columns:
        return "v", _top(columns["v"])
    if {"x", "t"} <= set(columns) and columns["t"].size > 1 and np.all(np.diff(columns["t"]) > 0):
        return "x", _top(np.diff(columns["x"]) / np.diff(columns["t"]))
    return None


def check_bounds(columns: Dict[str, np.ndarray], source: str, accept_unusual: bool = False,
                 warn: Callable[[str], None] = print, scaled: Mapping[str, str] = None) -> None:
    """The fastest speed (|v|, or |dx/dt| of a log without v), the largest force (|f|, |force|)
    and the largest current (|i|), each but for the top 1 % of rows (``_top``), within
    the axis's physical range (``_validate.physical_range``: a linear axis's or a rotary one's);
    else one line naming the column and the --scale that brings it there. Within it, beyond
    ``usual_max`` (a joint's torque above 2 kNm: mNm?) or below ``USUAL_MIN``: one warning
    line; a sweep's speed beyond ``usual_max`` is refused, or with ``accept_unusual`` warned (its fastest speed
    is the textbook law's v_sat: speeds in m/min or rpm would make every number of the model
    wrong). ``scaled``: how a column was scaled already, by column (the user's --scale, the
    header's unit): it is named, and no unit is asked about (``_given_scale``, ``unusual``'s
    ``given``)."""
    checks = []
    speed = top_speed(columns)
    if speed is not None:
        column, value = speed
        what = "|v|" if column == "v" else "|dx/dt|"
        checks.append((column, "speed", f"{what} (99th percentile)", value))
    for name in ("f", "force", "load"):
        if name in columns:
            checks.append((name, "force", f"|{name}| (99th percentile)", _top(columns[name])))
    if "i" in columns:
        checks.append(("i", "current", "|i| (99th percentile)", _top(columns["i"])))
    for column, quantity, what, value in checks:
        if value == 0:
            continue                # no motion or no force: the readers name that
        given = _given_scale(column, scaled)
        counts = column == "x" and whole_numbers(columns["x"])
        problem = physical_problem(quantity, what, value)
        if problem:
            hint = given or (COUNTS_HINT if counts else
                             _unit_hint(column, quantity, value))
            refuse_or_warn(f"{source}: {problem}{hint}", accept_unusual, warn)
        elif usual_max(quantity) is not None and unusual(quantity, what, value, column):
            said = given or (COUNTS_HINT if counts else "")
            note = f"{source}: {unusual(quantity, what, value, column, said)}"
            if quantity == "speed" and "t" not in columns:    # a sweep: its speeds are the law's
                refuse_or_warn(note, accept_unusual, warn)
            else:
                warn(f"fricgen: warning: {note}")
        elif quantity in USUAL_MIN and unusually_small(quantity, what, value, column):
            warn(f"fricgen: warning: {source}: {unusually_small(quantity, what, value, column, given)}")


def _given_scale(column: str, scaled: Optional[Mapping[str, str]]) -> str:
    """' (after --scale v=0.10472: check the factor)' where ``column`` was scaled (``scaled``:
    how, by column: the user's --scale, the header's unit), else ''."""
    how = (scaled or {}).get(column)
    return "" if how is None else f" (after {how}: check the factor)"


def _scatter(a: np.ndarray, b: np.ndarray) -> float:
    """How closely b follows a: the robust standard deviation of b about its running median in
    order of a, relative to the median |b|."""
    level = float(np.median(np.abs(b)))
    spread = 1.4826 * float(np.median(np.abs(b - running_median(a, b))))
    return spread / level if level > 0 else math.inf


def _pushes_at_rest(speed: np.ndarray, force: np.ndarray) -> bool:
    """Whether the least-squares line of the force (in the direction of motion) on the speed
    crosses 0 at a positive speed, two standard errors clear (both directions folded): friction has
    a Coulomb level at v = 0; a speed column read as the force (swapped) has none."""
    basis = np.column_stack([np.ones_like(speed), speed])
    if speed.size < 3 or np.ptp(speed) == 0:
        return False
    coef, *_ = np.linalg.lstsq(basis, force, rcond=None)
    resid = force - basis @ coef
    cov = np.linalg.pinv(basis.T @ basis) * float(resid @ resid) / max(speed.size - 2, 1)
    return bool(coef[0] + 2.0 * math.sqrt(max(cov[0, 0], 0.0)) < 0.0)


def check_sweep_shape(v: np.ndarray, f: np.ndarray, source: str, accept_unusual: bool = False,
                      warn: Callable[[str], None] = print) -> None:
    """A sweep (v, f) whose force follows the speed as friction does: refused (or, with
    ``accept_unusual``, warned) when its columns look swapped or its force follows no curve of v.
    Runs before any fit, so every method sees the same answer."""
    keep = _thin(v.size)
    moving = v[keep] != 0
    signed, force_all = v[keep][moving], (np.sign(v[keep]) * f[keep])[moving]
    speed = np.abs(signed)
    if speed.size < 2:
        return                      # the sweep reader names too few rows
    slowest = float(speed.min()) / float(speed.max())
    # per direction: two directions' curves (a Coulomb level and a B each) interleave in one
    curves = [(speed[m], force_all[m]) for m in (signed > 0, signed < 0) if m.sum() >= 3] or \
        [(speed, force_all)]
    why = [_looks_swapped(*curve) for curve in curves] if SLOWEST_SHARE < slowest < 1 else [""]
    if all(why):
        refuse_or_warn(f"{source}: v never comes near 0 (its slowest speed is {slowest:.0%} of its "
                        f"fastest) and {why[0]}: are the columns v and f swapped?", accept_unusual, warn)
        return
    scatter = min(_scatter(*curve) for curve in curves) if speed.size >= 20 else 0.0
    if scatter > NOTHING_EXPLAINED:
        refuse_or_warn(f"{source}: f scatters about any curve of v by {scatter:.0%} of its median "
                        "level: no friction curve is in it (is f the force of this axis, the sensor "
                        "connected?)", accept_unusual, warn)


def _looks_swapped(speed: np.ndarray, force: np.ndarray) -> str:
    """Why one curve (|v|, the force in the direction of motion) looks like a speed read as
    the force ("" where it does not): under 20 points its line reaches 0 at a positive speed
    (``_pushes_at_rest``), from 20 v follows f more closely than f follows v (SWAP_RATIO,
    ``_scatter``), or, where neither scatters about its running median at all (a speed set
    exactly, evenly spaced), that line again."""
    line = "the force's line through the points reaches 0 before v does (no Coulomb level)"
    if speed.size >= 20:
        f_on_v, v_on_f = _scatter(speed, force), _scatter(force, speed)
        if f_on_v > 0 or v_on_f > 0:
            return "v follows f more closely than f follows v" if v_on_f < SWAP_RATIO * f_on_v else ""
    return line if _pushes_at_rest(speed, force) else ""


def _regressors(columns: Dict[str, np.ndarray], t: np.ndarray) -> Optional[np.ndarray]:
    """The columns of f = m dv/dt + F_c sgn(v) + B v + o at the times ``t`` ([C1] with
    Coulomb and viscous friction), or None without v or x."""
    if "v" in columns:
        v = np.interp(t, columns["t"], columns["v"])
    elif "x" in columns:
        v = np.gradient(np.interp(t, columns["t"], columns["x"]), t)
    else:
        return None
    return np.column_stack([np.gradient(v, t), np.sign(v), v, np.ones_like(v)])


def _force_of(columns: Dict[str, np.ndarray]) -> Optional[str]:
    return next((k for k in ("force", "f", "i") if k in columns), None)


def check_merge_shift(first: Dict[str, np.ndarray], second: Dict[str, np.ndarray], shift: float,
                      names, accept_unusual: bool = False, warn: Callable[[str], None] = print) -> None:
    """The given ``shift`` of the second file's clock near the one at which the force (of either
    file) best fits the motion of the other (least squares of [C1] with Coulomb and viscous
    friction, on the middle half of the force file's span, over every shift that keeps it
    within the motion file's); refused (or warned)
    when another shift fits SHIFT_GAIN times better SHIFT_STEPS samples or more away."""
    if _force_of(second) and not _force_of(first):
        motion, force, sign = first, second, 1.0
    elif _force_of(first) and not _force_of(second):
        motion, force, sign = second, first, -1.0
    else:
        return
    tm, tf = motion.get("t"), force.get("t")
    if tm is None or tf is None or tm.size < 20 or tf.size < 20:
        return
    name = _force_of(force)
    step = max(float(np.median(np.diff(tm))), float(np.median(np.diff(tf))))
    span = min(tm[-1] - tm[0], tf[-1] - tf[0])
    if not (step > 0 and span > 40 * step):
        return

    # the middle half of the force file, the same samples at every shift tried, so that the
    # residuals compare (a shorter overlap of simpler motion would fit better at a wrong shift)
    middle = (tf >= tf[0] + 0.25 * (tf[-1] - tf[0])) & (tf <= tf[0] + 0.75 * (tf[-1] - tf[0]))
    rows = np.flatnonzero(middle)[_thin(int(middle.sum()))]
    if rows.size < 20:
        return
    y = force[name][rows]
    low, high = tm[0] - tf[rows[0]], tm[-1] - tf[rows[-1]]     # shifts that keep them in the motion

    def residual(s: float) -> float:
        # the force file's sample at tf happened at tf + s on the motion file's clock
        design = _regressors(motion, tf[rows] + s)
        if design is None:
            return math.inf
        coef, *_ = np.linalg.lstsq(design, y, rcond=None)
        return float(np.mean((y - design @ coef) ** 2))

    given = sign * shift
    if not low <= given <= high:
        return                      # the merge's own check names a short common span
    coarse = np.append(np.linspace(low, high, COARSE_SHIFTS), given)
    scores = np.array([residual(s) for s in coarse])
    best = float(coarse[int(np.argmin(scores))])
    width = (high - low) / (COARSE_SHIFTS - 1)
    fine = np.clip(best + np.linspace(-width, width, 21), low, high)
    fine_scores = np.array([residual(s) for s in fine])
    best = float(fine[int(np.argmin(fine_scores))])
    at_given, at_best = residual(given), float(min(fine_scores.min(), scores.min()))
    if not (math.isfinite(at_given) and at_best > 0):
        return
    if abs(best - given) >= SHIFT_STEPS * step and at_given > SHIFT_GAIN * at_best:
        suggested = sign * best
        refuse_or_warn(f"--merge-shift {shift:g} s looks off: the force of {names[1 if sign > 0 else 0]} "
                        f"fits the motion of {names[0 if sign > 0 else 1]} best at a shift of about "
                        f"{suggested:.4g} s (RMS residual {math.sqrt(at_best):.3g} against "
                        f"{math.sqrt(at_given):.3g} {'A' if name == 'i' else 'N'} at {shift:g} s); "
                        "check the clocks",
                        accept_unusual, warn)


#: Temperatures (degC) of a lubricated axis in service: beyond, the column is in K or degF
#: (refused); a log whose coolest reading exceeds WARM_START is warned about (in degF?).
TEMPERATURE_PHYSICAL = (-60.0, 250.0)
TEMPERATURE_USUAL = (-30.0, 120.0)
WARM_START = 45.0


def check_temperature(values: np.ndarray, source: str, accept_unusual: bool = False,
                      warn: Callable[[str], None] = print) -> None:
    """A temperature column in degC: readings beyond TEMPERATURE_PHYSICAL refused (K?), beyond
    TEMPERATURE_USUAL refused unless ``accept_unusual`` (degF?), a coolest reading above
    WARM_START warned about (degF?)."""
    read = values[np.isfinite(values)]
    if read.size == 0:
        return
    low, high = float(read.min()), float(read.max())
    what = f"{source}: column 'temperature' reads {low:.4g} to {high:.4g}, in degC"
    if low < TEMPERATURE_PHYSICAL[0] or high > TEMPERATURE_PHYSICAL[1]:
        hint = "; in K? subtract 273.15" if 200 < low and high < 600 else "; in degF or K?"
        raise DataError(f"{what} beyond any axis in service{hint}")
    if low < TEMPERATURE_USUAL[0] or high > TEMPERATURE_USUAL[1]:
        refuse_or_warn(f"{what}: beyond {TEMPERATURE_USUAL[0]:g} to {TEMPERATURE_USUAL[1]:g} degC "
                        "(in degF? (T - 32) / 1.8 converts it)", accept_unusual, warn)
    elif low > WARM_START:
        warn(f"fricgen: warning: {what}: its coolest reading is warmer than most machines' "
             "surroundings (in degF? (T - 32) / 1.8 converts it)")


def check_columns(columns: Dict[str, np.ndarray], source: str, is_log: bool,
                  accept_unusual: bool = False, warn: Callable[[str], None] = print,
                  scaled: Mapping[str, str] = None) -> None:
    """Every data check that applies to the columns read from ``source``: for a sweep its shape
    (``check_sweep_shape``, first: swapped columns also break the bounds), for a log its
    columns swapped with the force (``check_log_swaps``, first likewise), then the physical
    bounds (``scaled`` as ``check_bounds``); a log's temperature column (``check_temperature``)
    and the timing of its force against its motion (``check_timing``)."""
    if "temperature" in columns:
        check_temperature(columns["temperature"], source, accept_unusual, warn)
    if not all(np.all(np.isfinite(values)) for k, values in columns.items() if k != "temperature"):
        return                      # the readers name the row
    if not is_log and {"v", "f"} <= set(columns):
        check_sweep_shape(columns["v"], columns["f"], source, accept_unusual, warn)
        check_repeats(columns["v"], columns["f"], source, warn)
    if is_log:
        check_log_swaps(columns, source)
    check_bounds(columns, source, accept_unusual, warn, scaled)
    if is_log and "t" in columns:
        check_rate(columns["t"], source, warn, scaled)
        check_timing(columns, source, warn)


#: A log's force is said to lag or lead its motion where [C1] fits it SHIFT_GAIN times better
#: (residual variance) shifted by at least this many samples, of at most TIMING_SHIFTS.
TIMING_STEPS, TIMING_SHIFTS = 2, 50
#: The farthest ``check_timing`` searches where the best shift lies at its first search's edge.
TIMING_REACH = 200
#: Stribeck drops per direction in ``check_timing``'s law (``idim.friction_basis``): with
#: Coulomb + viscous alone a Stribeck curve's misfit hid a drive's velocity filtered 10 ms late
#: (its mass 22 % high; 0.80 of the residual at the best shift, 0.35 with them).
TIMING_STRIBECK = 5


def check_timing(columns: Mapping[str, np.ndarray], source: str,
                 warn: Callable[[str], None] = print) -> None:
    """One warning line where a log's force fits its motion (least squares of [C1] with
    Coulomb, viscous and TIMING_STRIBECK Stribeck drops per direction and a constant, v and
    dv/dt of a 7-sample Savitzky-Golay) far
    better a few samples off than in time: SHIFT_GAIN times less residual variance at a shift
    of TIMING_STEPS to TIMING_SHIFTS samples, or up to TIMING_REACH where the best lies at the
    edge (a delay of 120 samples had been told as 50; a best shift still at the edge, where
    the residual falls on past any delay, locates none). The motion is x's where the log has x (a filtered velocity
    column's lag had been taken for the force's). A force column a few samples off its motion
    trains silently wrong numbers (20 ms at 1 kHz: a 3 kg axis's mass 3.28 kg, its viscous
    friction 0.86 of 4 N s/m; 2 samples at 100 Hz: 1.28 of 4); the robot joints of
    ``../shared/data`` fit best in time or at most 0.72 of it."""
    t, v, x = (columns.get(k) for k in ("t", "v", "x"))
    force = columns.get("force", columns.get("i"))
    if t is None or force is None or (v is None and x is None) or t.size < 8 * TIMING_SHIFTS:
        return
    ts = float(np.median(np.diff(t)))
    if not ts > 0:
        return
    # the motion from x where the log has it: a drive's velocity column may be filtered, and
    # its lag (``motionlog.without_lagging_velocity`` takes v from x then) is not the force's
    v = smooth(np.gradient(x, t if np.all(np.diff(t) > 0) else ts) if x is not None else v, 7)
    if not np.all(np.isfinite(v)):
        return                      # the readers name a column that is not finite
    a = np.gradient(v, ts)
    reach = TIMING_SHIFTS
    while True:             # a best shift at the search's edge: searched twice as far
        inner = np.arange(reach, t.size - reach)[_thin(t.size - 2 * reach)]
        design = np.column_stack([a[inner], friction_basis(v[inner], odd=False, terms=TIMING_STRIBECK),
                                  np.ones(inner.size)])
        pinv = np.linalg.pinv(design)       # one design for every shift: only the force moves
        scores = {d: float(np.mean((force[inner + d] - design @ (pinv @ force[inner + d])) ** 2))
                  for d in range(-reach, reach + 1)}
        best = min(scores, key=scores.get)
        if abs(best) < reach or 2 * reach > TIMING_REACH or t.size < 16 * reach:
            break
        reach *= 2
    # a best shift still at the edge locates no delay (uniform stamps on jittering samples)
    if TIMING_STEPS <= abs(best) < reach and scores[best] * SHIFT_GAIN < scores[0]:
        which = "lags" if best > 0 else "leads"
        warn(f"fricgen: warning: {source}: the force column {which} the motion by {abs(best)} "
             f"samples ({abs(best) * ts * 1e3:.3g} ms): friction and inertia fit it so with "
             f"{scores[best] / scores[0]:.2g} of the residual variance they leave in time; a "
             "delay between the columns biases the mass and the friction (shift one column)")


def check_log_swaps(columns: Mapping[str, np.ndarray], source: str) -> None:
    """``DataError`` where a log's v, or its x, holds the force and the force column the motion
    (``log_columns.check_force_swap``, ``motionlog.check_swapped_force``): named before the
    bounds, which would read the force in a velocity column as a velocity in mm/s. Not judged
    where the force or the motion holds one value over 98 % of the log (not logged, or no
    motion: the readers' checks name that)."""
    t, v, x = (columns.get(k) for k in ("t", "v", "x"))
    force = columns.get("force", columns.get("i"))
    if t is None or (v is None and x is None) or force is None or t.size < 3:
        return
    if not (varies(force) and varies(x if v is None else v)):
        return                      # no motion, or a force not logged: the readers name it
    ts = float(np.median(np.diff(t)))
    if not ts > 0:
        return                      # the readers name the time column
    try:
        if x is not None and v is not None:
            check_swapped_force(x, v, force, ts)
        check_force_swap(force, ts, v, x)
    except DataError as exc:
        raise DataError(f"{source}: {exc}") from None


def check_repeats(v: np.ndarray, f: np.ndarray, source: str, warn: Callable[[str], None] = print) -> None:
    """One warning line when REPEATED_SHARE or more of a sweep's rows repeat an earlier row
    exactly (v and f): a file joined twice counts each point twice, in the fit, its standard
    errors and its held-out error (a copy in the training folds predicts its twin)."""
    pairs = np.column_stack([v, f])
    repeats = pairs.shape[0] - np.unique(pairs, axis=0).shape[0]
    if repeats and repeats >= REPEATED_SHARE * pairs.shape[0]:
        warn(f"fricgen: warning: {source}: {repeats} of {pairs.shape[0]} rows repeat an earlier row "
             "exactly (v and f): a file joined twice? Each copy counts again in the fit, its "
             "standard errors and its held-out error")


def check_rate(t: np.ndarray, source: str, warn: Callable[[str], None] = print,
               scaled: Mapping[str, str] = None) -> None:
    """One warning line when the log's median sampling rate is below USUAL_MIN_RATE, asking
    whether t is in ms or us (the first that brings the rate above it; none where the user
    scaled t, ``_given_scale``)."""
    steps = np.diff(t)
    step = float(np.median(steps)) if steps.size else 0.0
    if step > 1.0 / USUAL_MIN_RATE:
        ask = _given_scale("t", scaled)
        if not ask:                         # ms, or us where ms leaves it below
            unit, factor = next(((u, f) for u, f in (("ms", 1e-3), ("us", 1e-6))
                                 if step * f <= 1.0 / USUAL_MIN_RATE), ("us", 1e-6))
            ask = (f": is t in {unit} (--scale t={factor:g})? The inertia would come out "
                   f"{1 / factor:.0f} times the axis's")
        warn(f"fricgen: warning: {source}: the log is sampled at {1.0 / step:.3g} Hz, below the "
             f"{USUAL_MIN_RATE:g} Hz of any drive's or DAQ's log{ask}")
