"""Friction samples from a motion log by inverse dynamics of [C1]: F(v) = f - m dv/dt.

The log holds time ``t`` (s, uniformly sampled), velocity ``v`` (m/s) or position ``x`` (m), and
the drive force ``force`` (N) or the motor current ``i`` (A) times the force constant. Velocity
and force are smoothed by one zero-phase Savitzky-Golay filter (cubic, centred window,
``data.smoothing``), which also gives dv/dt, so F = f - m a holds between the smoothed signals.
The window is chosen from the data (``smoothing.choose_window``: generalized cross-validation of
the force plus the derivative's noise); the mass at a window of its own (``explaining_window``), where dv/dt is not so noisy
that the mass is pulled towards 0. Rows where the axis really moves are kept: |v| above the velocity noise and one
direction of motion over the whole window (no reversal or sticking smeared in).
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable, Dict, List, Optional, Tuple

import numpy as np
from scipy.ndimage import minimum_filter1d
from scipy.signal import savgol_filter

from ..errors import DataError
from ..metrics import least_squares_errors
from ..units import axis_units
from .identification import Identification
from .export import suggested_columns
from .idim import (BASIS_COLUMNS, PHASE_SHARE, SAMPLES_PER_PARAMETER, RigidBody,
                   friction_basis, identify_rigid_body, known_columns, operating_basis)
from .log_columns import check_acceleration_column, check_log_columns
from .motionlog import (check_finite, check_moves, check_units, check_varies, resampled_runs,
                        uniform_time)
from .smoothing import (MIN_WINDOW, POLYORDER, VelocityNoise, between_edges, candidate_windows,
                        centre_weight, choose_window, smooth, steady_rows)
from .sweep import MIN_ROWS, Sweep
from .table import header_hint

#: The axis moves where |v| exceeds this many standard deviations of the velocity noise.
MOVING_SIGMAS = 5.0
#: ... and this fraction of the largest speed (noise-free logs).
MOVING_FRACTION = 1e-3
#: Fewest rows of a log: the smoothing and the noise estimate need a few windows.
MIN_LOG_ROWS = 4 * MIN_WINDOW
#: Fewest independent samples a log must give: those of the four parameters of the smallest
#: friction law (Coulomb, viscous, a Stribeck drop and its velocity).
MIN_INDEPENDENT = 4 * SAMPLES_PER_PARAMETER
#: m dv/dt this many times the force (RMS where the axis moves), or a force that follows m dv/dt
#: this many times over, is a wrong mass or unit (``_check_inertia``).
INERTIA_OFF = 10.0


#: A log's own acceleration is used unless the force's RMS residual with it is more than this
#: factor above that with dv/dt of v (``explaining_window``): it then leaves unexplained a part
#: of the force about a third (sqrt(1.05^2 - 1)) of the whole residual's size; a causal filter of
#: 5 ms on a 0.2-2.9 Hz move left 1.40 times the residual, one of 20 ms 3.98 times.
ACCELERATION_EXCESS = 1.05

#: Rows (evenly spaced among the moving ones) at which ``explaining_window`` scores a window:
#: a bound on its cost for long logs, well above the independent samples a mass needs.
EXPLAINING_ROWS = 50_000

#: The columns of a log's operating point beside the motion and the force.
CONDITIONS = ("load", "temperature")

#: How close to a whole number of encoder steps each change of a logged position must be (a
#: continuous position meets it on 0.02 % of its changes; the rule asks 99 %).
COUNT_TOLERANCE = 1e-4


def robust_sd(values: np.ndarray) -> float:
    """1.4826 times the median absolute deviation: the standard deviation of Gaussian noise."""
    return float(1.4826 * np.median(np.abs(values - np.median(values))))


def position_quantum(x: np.ndarray) -> float:
    """The step of a position logged in encoder counts (every change between samples a whole
    number of one step, to COUNT_TOLERANCE of it: counts times their size written with 9
    significant digits are still counts), else 0."""
    steps = np.abs(np.diff(np.asarray(x, dtype=float)))
    steps = steps[steps > 0]
    if steps.size < MIN_LOG_ROWS:
        return 0.0
    quantum = float(steps.min())
    counts = steps / quantum
    whole = np.abs(counts - np.round(counts)) <= COUNT_TOLERANCE * np.maximum(counts, 1.0)
    return quantum if np.median(counts) < 1e3 and whole.mean() >= 0.99 else 0.0


#: The key under which ``identify_log`` carries its row mask through the resampling.
USE_COLUMN = "_use"
#: The velocity a log resolves: RESOLUTION_SIGMAS standard deviations of its velocity noise,
#: and RESOLUTION_COUNTS steps (a velocity from counts jitters by a step per sample; a banded
#: compensation switched on at one step per sample hunted at rest on 3 of 8 simulated precision
#: stages, at three on 1 of 8: benchmarks/slow_speeds.py --measured, seeds 0-7, set the value).
RESOLUTION_SIGMAS = 4.0
RESOLUTION_COUNTS = 3.0


def velocity_resolution(x: Optional[np.ndarray], noise: float, sample_time: float, v=None) -> float:
    """The smallest speed a log tells from rest: RESOLUTION_SIGMAS standard deviations of the
    velocity noise, and RESOLUTION_COUNTS steps of the velocity ``v`` where the log gives one
    (the drive's own estimate, which its firmware reads), else of the position's counts per
    sample."""
    step = position_quantum(v) if v is not None else position_quantum(x) / sample_time if x is not None else 0.0
    return max(RESOLUTION_COUNTS * step, RESOLUTION_SIGMAS * noise)


def velocity_noise(v: np.ndarray) -> float:
    """The standard deviation of white noise on v, from its second differences (variance
    6 sigma^2; a smooth signal barely contributes at the sampling rate)."""
    return robust_sd(np.diff(v, 2)) / np.sqrt(6.0)


def at_sample_times(held: np.ndarray, junction: np.ndarray) -> np.ndarray:
    """A force held over the sample after the one it is logged at, at the motion's sample times:
    each row the mean of it and the row before (the first of a run, ``junction``, as logged). As
    logged it leads the motion by half a sample: m x jerk x half a sample at a speed's corner."""
    mean = np.concatenate([held[:1], 0.5 * (held[1:] + held[:-1])])
    return np.where(junction, held, mean)


def identify_friction(t: np.ndarray, force: np.ndarray, mass: Optional[float] = None,
                      v: Optional[np.ndarray] = None, x: Optional[np.ndarray] = None,
                      window: Optional[int] = None, body_window: Optional[int] = None,
                      use: Optional[np.ndarray] = None,
                      progress: Optional[Callable[[str], None]] = None,
                      conditions: Optional[Dict[str, np.ndarray]] = None,
                      gravity: bool = False, runs: Optional[np.ndarray] = None,
                      held: bool = False, a: Optional[np.ndarray] = None) -> Identification:
    """Friction samples F = f - m dv/dt of a log [C1] at the rows where the axis moves, m
    identified by inverse dynamics (``data.idim``; ``mass`` pins m) with a constant force o, the
    even part of the force: a symmetric model leaves it out by folding, an asymmetric one holds
    it in its curves (``offset_line``).

    ``v`` or, without it, ``x`` (v = dx/dt by central differences) gives the motion. ``window``
    (odd samples) overrides ``choose_window``, which reports to ``progress``, and ``body_window``
    ``explaining_window`` (the mass's; at ``window`` where only that is given). ``use`` (a mask of rows) confines everything
    identified to those rows, so that a held-out block of time leaks no force into it: the
    friction samples less half a window at each edge (their force is smoothed), the mass's
    rows not (their force is not; the velocity is smoothed across the edge).

    ``conditions``: the log's ``load`` (the external force the drive supplies beside the
    friction, f = m a + L + F + o; ``check_load``) and ``temperature`` columns, smoothed as v and
    kept at the rows of the samples (``Identification.conditions``). ``gravity``: a force
    G_s sin x + G_c cos x of the position (a robot joint's link weight, x in rad) identified
    beside the mass and taken out of the friction samples; it needs ``x``. ``runs``: the run of
    each row of a log concatenated from runs (``motionlog.resampled_runs``): no window spans two
    runs (the windows bounded by a typical run's length: a run shorter than a window is left
    out), and of the runs that move both ways each one's constant force less the first such
    run's is identified beside the mass (``RigidBody.run_offsets``) and taken out of the
    friction samples. ``a``: the log's own acceleration (a column a, ddq): dv/dt wherever the
    mass is identified or taken out (``check_acceleration_column``), so that a force from which
    a rigid-body model was removed with it leaves its residual inertia against the same signal;
    not used where dv/dt of v explains the force clearly better (ACCELERATION_EXCESS: a drive's
    estimate that lags), which ``Identification.acceleration_unused`` records."""
    conditions = dict(conditions or {})
    columns = {"t": t, "force": force, "v": v, "x": x, "a": a, **conditions}
    unused = None
    for name, values in columns.items():
        if values is not None:
            check_finite(name, values)
    if t.size < MIN_LOG_ROWS:
        raise DataError(f"log has {t.size} samples, need at least {MIN_LOG_ROWS}")
    if mass is not None and not (np.isfinite(mass) and mass > 0):
        raise DataError(f"mass must be > 0, got {mass}")
    ts = uniform_time(t)[1]
    given = v is not None
    junction = np.zeros(t.size, dtype=bool)
    if runs is not None:
        junction[1:] = np.diff(runs) != 0               # the first row of each later run
    quantum = 0.0 if given else position_quantum(x)
    if not given:                                       # run by run: x jumps between runs
        cuts = np.flatnonzero(junction)
        parts = zip(np.split(t, cuts), np.split(x, cuts))
        v = np.concatenate([np.gradient(between_edges(tp, xp) if quantum > 0 else xp, ts)
                            for tp, xp in parts])
    check_moves(v, x, given)
    if a is not None:
        check_acceleration_column(v, a, ts)
    if given and x is not None:     # x, v and t, or a column swapped with the force
        check_units(x, v, ts, force)
    weight = None
    if runs is None:                # what the columns hold (x jumps between runs: one run only)
        weight = check_log_columns(force, ts, v if given else None, x, gravity=gravity)
    measured = velocity_noise(v)
    # encoder counts: the position between the count edges is off by up to a count's rounding,
    # q / sqrt(12), a noise on x that the central difference and the smoothing then filter
    noise = VelocityNoise(measured, quantum / np.sqrt(12.0), ts)
    if gravity and x is None:
        raise DataError("--gravity needs the position (a column x or q): the gravity force is a "
                        "function of the joint's angle")
    angle = x if gravity else None
    use = np.ones(t.size, dtype=bool) if use is None else np.asarray(use, dtype=bool)
    use = use & ~junction                  # whole windows of use never span two runs
    span = t.size if runs is None else int(np.median(np.bincount(runs)))  # a typical run's rows
    body = None
    # the rows that choose the window move beyond v's white noise and what a count's rounding
    # leaves in the shortest window (taken per sample, 5 x 0.63 rad/s of a 12-bit encoder at
    # 2 kHz left a 1.5 rad/s move no rows); the body's rows beyond the noise of each sample:
    # the slower ones, near reversals, hold the bristles' build-up after each start, which
    # hid the disagreement of speeding up and braking (``RigidBody.phases_disagree``)
    instant = savgol_filter(v, MIN_WINDOW, POLYORDER)
    speed = np.abs(instant)
    rows = use & (speed > MOVING_SIGMAS * max(noise.white, noise.smoothed(MIN_WINDOW)))
    sliding = use & (speed > MOVING_SIGMAS * noise.per_sample())
    logged, force = force, at_sample_times(force, junction) if held else force
    log_mass = None
    if window is None or (mass is None and body_window is not None):
        raw = force - conditions["load"] if "load" in conditions else force
        # the mass's rows: dv/dt smoothed within one run, away from the log's ends, at rows of
        # use (the raw force is not smoothed there: a mask of rows such as train --dynamic's
        # settled ones need not hold whole windows, or only long cruises without ramps are left)
        whole = minimum_filter1d((~junction).astype(np.int8), candidate_windows(span)[-1],
                                 mode="constant").astype(bool) & use
        alike, at = None, body_window
        if at is None:                      # the body where dv/dt explains the force best
            explained = explaining_window(v, raw, sliding & whole, ts, span, angle, runs, a)
            if explained is not None:
                at, alike, versus = explained
                if versus is not None and versus[0] <= ACCELERATION_EXCESS * versus[1]:
                    at, alike = versus[2], None         # the log's own a, at its best window
                elif versus is not None:
                    a, unused = None, versus[:2]
        try:
            found = None if at is None else _body_at(at, ts, v, raw, sliding & whole, conditions,
                                                     angle, runs, noise, a)
        except DataError:
            if mass is None:
                raise
            found = None                    # a mass given: the checks below name the log's fault
        determined = found is not None and found.mass_identified and found.mass_determined
        if mass is None:
            body, body_window = found, at
            if determined:
                body = replace(body, window_masses=alike)
        elif determined:                    # a mass given: what the log's accelerations say
            log_mass = (found.mass, found.mass_se)
    if window is None:
        guess = (mass or 0.0) if body is None else body.inertia
        window = choose_window(logged, rows, guess, noise, progress, span)
    v_s, a_s, f_s, moving, at_rows, independent, at_window = _at_window(
        window, ts, v, force, noise, use, conditions, mass, body is None, angle, runs, a)
    body = at_window if body is None else body
    if log_mass is not None:
        body = replace(body, log_mass=log_mass)
    friction = f_s - body.inertia * a_s - body.run_force(runs)
    if angle is not None:
        friction = friction - body.gravity_force(smooth(angle, window))
    steady = steady_rows(v_s, moving, window)
    # near a reversal: the raw force (``reversals``), where the axis slides at that instant in
    # the direction of the window's v (a long window smears a stop: a joint's rebound of 0.01
    # rad/s after each run, its friction still the other way, was read as sliding backwards)
    reversing = moving & ~steady & sliding & (np.sign(instant) == np.sign(v_s))
    reversing[:window // 2] = reversing[-(window // 2):] = False
    raw = friction + (force - f_s)
    kept = float(steady.sum()) * centre_weight(window)
    if steady.sum() < MIN_ROWS or kept < MIN_INDEPENDENT:
        raise DataError(f"the axis moves steadily in only {int(steady.sum())} rows (about "
                        f"{kept:.0f} independent samples; no reversal within {window} samples), "
                        f"need {MIN_ROWS} rows and {MIN_INDEPENDENT} independent samples: log "
                        "longer or more varied motion")
    check_friction_found(v_s[steady], friction[steady], kept, axis_units())
    return Identification(sweep=Sweep(v_s[steady], friction[steady]), n_rows=int(t.size),
                          window=int(window), sample_time=ts, velocity_noise=noise.per_sample(),
                          independent=kept, body=body, body_window=body_window,
                          conditions={k: c[steady] for k, c in at_rows.items()},
                          n_runs=1 if runs is None else int(runs[-1]) + 1, weight=weight,
                          reversals=Sweep(v_s[reversing], raw[reversing]),
                          acceleration_given=a is not None, acceleration_unused=unused)


#: A log's friction samples hold friction where its Coulomb level or its viscous slope stands
#: this many standard errors from 0.
FRICTION_Z = 3.0


def check_friction_found(v: np.ndarray, friction: np.ndarray, independent: float, units) -> None:
    """``DataError`` where the friction samples of a log hold no friction: neither the Coulomb
    level F_c sgn(v) nor the viscous slope B v, each fitted alone with a constant, stands
    FRICTION_Z standard errors from 0 (fitted together, a move at one speed each way makes
    them one column, and neither stood clear). An axis without friction, or a velocity of
    another axis beside a force that follows it by no chance (a new user's log: given the mass
    it trained a model of F_c 0 and B 0.39 +- 0.35 that explained nothing, and without it was
    told of units). The samples count as independent but for the smoothing alone: counted by
    the residual's correlation from row to row as well, the friction of a joint whose link's
    weight is left in the samples (``train`` without ``--gravity``) no longer stood clear; so a
    smooth force of another axis that follows this one's motion by chance passes."""
    def alone(column: np.ndarray) -> Tuple[float, float]:
        coef, se = least_squares_errors(np.column_stack([column, np.ones(v.size)]), friction,
                                        independent)
        return float(coef[0]), float(se[0])

    (coulomb, coulomb_se), (viscous, viscous_se) = alone(np.sign(v)), alone(v)
    if abs(coulomb) <= FRICTION_Z * coulomb_se and abs(viscous) <= FRICTION_Z * viscous_se:
        raise DataError(f"the log holds no friction: the force less the inertia's follows neither "
                        f"sgn(v) nor v (F_c = {coulomb:.3g} +- {coulomb_se:.2g} {units.force}, B = "
                        f"{viscous:.3g} +- {viscous_se:.2g} {units.force} s/{units.position}, neither "
                        f"{FRICTION_Z:g} standard errors from 0): are v (or x) and the force "
                        "columns of the same axis, and in time with each other?")


#: The force must follow the load column with a slope within this factor of 1 (f = m a + L + F):
#: a load of the other sign convention gives -1, one in other units 1000 or 0.001.
LOAD_SLOPE_OFF = 2.0


def check_load(force: np.ndarray, load: np.ndarray, a: np.ndarray, v: np.ndarray,
               independent: float) -> None:
    """``DataError`` when the force does not follow the load column as f = m a + L + F does:
    its slope on L (regressed with a, sgn(v), v, sgn(v) |L| for a load-dependent friction and a
    constant) below 1 / LOAD_SLOPE_OFF or above LOAD_SLOPE_OFF, three standard errors clear: a
    load of the opposite sign convention, or in other units. A load that does not vary is not
    checked (it is one with the offset)."""
    if not np.ptp(load) > 0:
        return
    basis = np.column_stack([load, a, np.sign(v), v, np.sign(v) * np.abs(load), np.ones(v.size)])
    coef, se = least_squares_errors(basis, force, independent)
    k, k_se = float(coef[0]), float(se[0])
    if k + 3.0 * k_se < 1.0 / LOAD_SLOPE_OFF or k - 3.0 * k_se > LOAD_SLOPE_OFF:
        cause = ("the load column has the opposite sign convention (negate it)" if k < 0 else
                 "check the load's units (the force's: N, or Nm on a rotary axis)")
        raise DataError(f"the force follows the load column with slope {k:.3g} +- {k_se:.2g}, "
                        f"where f = m dv/dt + load + friction gives 1: {cause}")


def _at_window(window: int, ts: float, v: np.ndarray, force: np.ndarray, noise: VelocityNoise,
               use: np.ndarray, conditions: Dict[str, np.ndarray], mass: Optional[float],
               identify: bool = True, angle: Optional[np.ndarray] = None,
               runs: Optional[np.ndarray] = None, a: Optional[np.ndarray] = None):
    """The log smoothed by ``window`` (``_smoothed``) with its operating point, the load taken
    out of the force (``check_load``), and the rigid body identified there (``mass`` given:
    checked, ``_check_inertia``; None where not ``identify``): (v, dv/dt, force, the moving
    rows, the conditions, the independent samples, the body)."""
    v_s, a_s, f_s, moving = _smoothed(window, ts, v, force, noise, use, a)
    independent = moving.sum() * centre_weight(window)
    at_rows = {name: smooth(values, window) for name, values in conditions.items()}
    if "load" in at_rows:
        check_load(f_s[moving], at_rows["load"][moving], a_s[moving], v_s[moving], independent)
        f_s = f_s - at_rows["load"]
    if mass is not None:
        _check_inertia(f_s[moving], mass * a_s[moving], v_s[moving], independent)
    body = None
    if identify:
        extra = operating_basis(v_s[moving], *(None if k not in at_rows else at_rows[k][moving]
                                               for k in CONDITIONS))
        body = identify_rigid_body(a_s[moving], v_s[moving], f_s[moving], independent, mass, extra,
                                   None if angle is None else smooth(angle, window)[moving],
                                   None if runs is None else runs[moving])
    return v_s, a_s, f_s, moving, at_rows, independent, body


def _body_at(window: int, ts: float, v: np.ndarray, force: np.ndarray, rows: np.ndarray,
             conditions: Dict[str, np.ndarray], angle: Optional[np.ndarray] = None,
             runs: Optional[np.ndarray] = None, noise: Optional[VelocityNoise] = None,
             a: Optional[np.ndarray] = None) -> RigidBody:
    """The rigid body (``data.idim``) from the raw ``force`` (the load taken out) at ``rows``,
    with v, dv/dt and the operating point smoothed by ``window`` (``explaining_window``). The
    residual is the raw force's, so the rows count as independent but for its correlation from
    one row to the next (n (1 - r) / (1 + r), r its lag-one autocorrelation). ``noise``: the
    velocity's, which sets that of dv/dt for the phases' masses (``RigidBody.phase_masses``).
    ``a``: the log's acceleration (``acceleration``)."""
    at = np.flatnonzero(rows)
    v_s, a_s = smooth(v, window)[at], acceleration(v, a, window, ts)[at]
    at_rows = {k: smooth(c, window)[at] for k, c in conditions.items()}
    extra = operating_basis(v_s, *(at_rows.get(k) for k in CONDITIONS))
    x_s = None if angle is None else smooth(angle, window)[at]
    runs = None if runs is None else runs[at]
    basis = np.column_stack([a_s, friction_basis(v_s, odd=False)]
                            + ([] if extra is None else [extra])
                            + known_columns(v_s, x_s, runs)[0])
    coef, *_ = np.linalg.lstsq(basis, force[at], rcond=None)
    accel_noise = None if noise is None else noise.derivative(window)
    return identify_rigid_body(a_s, v_s, force[at], independent_rows(force[at] - basis @ coef),
                               None, extra, x_s, runs, accel_noise)


def independent_rows(residual: np.ndarray) -> float:
    """The independent samples a residual holds: its n rows but for their correlation from
    one row to the next, n (1 - r) / (1 + r) with r the lag-one autocorrelation."""
    lag = float(np.corrcoef(residual[:-1], residual[1:])[0, 1]) if np.ptp(residual) > 0 else 0.0
    lag = min(max(lag if np.isfinite(lag) else 0.0, 0.0), 1.0 - 1.0 / residual.size)
    return residual.size * (1 - lag) / (1 + lag)


def acceleration(v: np.ndarray, a: Optional[np.ndarray], window: int, ts: float) -> np.ndarray:
    """dv/dt at one Savitzky-Golay ``window``: the log's own acceleration column ``a`` smoothed
    as v is, where it has one; else the filter's derivative of v."""
    return smooth(v, window, deriv=1, delta=ts) if a is None else smooth(a, window)


def _smoothed(window: int, ts: float, v: np.ndarray, force: np.ndarray, noise: VelocityNoise,
              use: np.ndarray, a: Optional[np.ndarray] = None):
    """v, dv/dt and the force smoothed by one Savitzky-Golay ``window``, and the rows of ``use``
    (whole windows) where the axis moves: |v| above MOVING_SIGMAS of the noise the smoothing
    leaves (``VelocityNoise.smoothed``) and MOVING_FRACTION of
    the top speed; ``DataError`` when there are none. ``a``: the log's acceleration."""
    v_s = smooth(v, window)
    a_s = acceleration(v, a, window, ts)
    f_s = smooth(force, window)
    threshold = max(MOVING_SIGMAS * noise.smoothed(window),
                    MOVING_FRACTION * float(np.max(np.abs(v_s))))
    whole = minimum_filter1d(use.astype(np.int8), window).astype(bool)    # whole windows of use
    moving = (np.abs(v_s) > threshold) & whole
    if not moving.any():
        raise DataError("the axis never moves beyond the velocity noise")
    return v_s, a_s, f_s, moving


def explaining_window(v: np.ndarray, force: np.ndarray, rows: np.ndarray,
                      sample_time: float, span: Optional[int] = None,
                      angle: Optional[np.ndarray] = None,
                      runs: Optional[np.ndarray] = None, a: Optional[np.ndarray] = None
                      ) -> Optional[Tuple[int, Tuple[Tuple[float, float], ...],
                                          Optional[Tuple[float, float, int]]]]:
    """The window at which the mass is identified: the candidate whose smoothed v and dv/dt
    explain the raw force best over ``rows`` (least residual of f = m dv/dt + F(v) + o by least
    squares, F by ``friction_basis`` per direction, with the forces of known shape that the body
    holds: the weight of ``angle`` and the runs' offsets, ``known_columns``; a link's weight left
    out would be explained by whatever window correlates with it). The raw force's noise is the same at every
    window, so the least residual marks the smoothing that leaves dv/dt least noisy without
    smearing the motion: a short window's noisy derivative pulls m towards 0 (errors in the
    variables), and the short window ``choose_window`` gives a small mass would keep it there.
    Returned with the least and the largest mass (with its standard error) of the windows whose
    sum of squares is within PHASE_SHARE of the least (``RigidBody.windows_disagree``), and,
    for a log's own acceleration ``a``, the RMS residual with it (smoothed alike, at its best
    window), that with the best window's dv/dt of v, and that window of ``a`` (None without
    ``a``). None where ``rows`` are too few for the basis (SAMPLES_PER_PARAMETER rows per
    column). ``span`` as ``choose_window``."""
    at = np.flatnonzero(rows)
    if at.size < SAMPLES_PER_PARAMETER * (2 + BASIS_COLUMNS):     # dv/dt, the basis, one more
        return None
    at = at[::max(1, at.size // EXPLAINING_ROWS)]
    windows = candidate_windows(rows.size if span is None else span)
    scores = [_explained(v, None, force, at, window, sample_time, angle, runs) for window in windows]
    best, window, _ = min(scores)
    masses = sorted(mass for score, _, mass in scores if score <= (1.0 + PHASE_SHARE) * best)
    versus = None
    if a is not None:
        given, at_window, _ = min(_explained(v, a, force, at, w, sample_time, angle, runs) for w in windows)
        versus = (float(np.sqrt(given / at.size)), float(np.sqrt(best / at.size)), at_window)
    return window, (masses[0], masses[-1]), versus


def _explained(v: np.ndarray, a: Optional[np.ndarray], force: np.ndarray, at: np.ndarray,
               window: int, ts: float, angle: Optional[np.ndarray], runs: Optional[np.ndarray]):
    """(sum of squares, ``window``, (m, its standard error)) of f = m dv/dt + F(v) + o and the
    body's known forces at the rows ``at``, smoothed by ``window`` (dv/dt: ``acceleration``;
    ``explaining_window``)."""
    a_s, v_s = acceleration(v, a, window, ts)[at], smooth(v, window)[at]
    known = known_columns(v_s, None if angle is None else smooth(angle, window)[at],
                          None if runs is None else runs[at])[0]
    basis = np.column_stack([a_s, friction_basis(v_s, odd=False)] + known)
    coef, se = least_squares_errors(basis, force[at], at.size)
    residual = force[at] - basis @ coef
    mass = (float(coef[0]), float(se[0] * np.sqrt(at.size / independent_rows(residual))))
    return float(residual @ residual), window, mass


def _check_inertia(force: np.ndarray, inertia: np.ndarray, v: np.ndarray, independent: float) -> None:
    """``DataError`` when the force where the axis moves cannot be m dv/dt plus friction: m dv/dt
    ``INERTIA_OFF`` times the force (RMS), or the force following m dv/dt with a slope more than
    ``INERTIA_OFF`` (3 standard errors clear; regressed with sgn(v), v and a constant for the
    friction) -- a mass, force or current in the wrong unit. A small slope is no proof: the noise
    of dv/dt pulls it towards 0."""
    ratio = float(np.sqrt(np.mean(inertia ** 2) / max(np.mean(force ** 2), 1e-300)))
    if ratio > INERTIA_OFF:
        raise DataError(f"m dv/dt is {ratio:.3g} x the force where the axis moves (RMS), yet the "
                        "force is m dv/dt plus friction [C1]: check the mass and the units of "
                        "t, x, v and of the force or i")
    coef, se = least_squares_errors(np.column_stack([inertia, np.sign(v), v, np.ones(v.size)]),
                                    force, independent)
    k, se = float(coef[0]), float(se[0])
    if k - 3.0 * se > INERTIA_OFF:
        raise DataError(f"the log accelerates as if the mass were {k:.3g} x the mass given: check "
                        "the mass and the units of the force or i (mA for A?) and of the force constant")


def interpolated(values: np.ndarray, t: Optional[np.ndarray]) -> np.ndarray:
    """A column logged at a slower rate (NaN between its readings) linearly interpolated in
    time, held beyond its first and last reading; ``DataError`` with fewer than one reading."""
    values = np.asarray(values, dtype=float)
    read = np.isfinite(values)
    if read.all() or t is None or t.size != values.size:
        return values
    if not read.any():
        raise DataError("column 'temperature' holds no reading")
    return np.interp(t, t[read], values[read])


#: The columns that make a CSV a motion log rather than a sweep (v, f).
LOG_TIME, LOG_MOTION, LOG_DRIVE = "t", ("v", "x"), ("force", "i")


def is_log(columns: Dict[str, np.ndarray]) -> bool:
    """A motion log has t, v or x, and force or i; a sweep has v and f."""
    return (LOG_TIME in columns and any(c in columns for c in LOG_MOTION)
            and any(c in columns for c in LOG_DRIVE))


def describe_missing(columns: Dict[str, np.ndarray], written: Optional[List[str]] = None) -> str:
    """Why the columns are neither a sweep (v, f) nor a log (t, v or x, force or i): a log's
    missing columns where there is t, or x, force or i but no f; else a sweep's. ``written``:
    the header's names as the file writes them, for the message."""
    cells = written or list(columns)
    header = ",".join(cells)[:80]
    if LOG_TIME in columns or ("f" not in columns and any(c in columns for c in ("x", *LOG_DRIVE))):
        missing = [" or ".join(group) for group in ((LOG_TIME,), LOG_MOTION, LOG_DRIVE)
                   if not any(c in columns for c in group)]
        sweep = ("" if any(c in columns for c in (LOG_TIME, "x", "i")) else
                 "; a sweep? --columns v=COLUMN,f=COLUMN names its columns")
        if "v" in columns and "i" in columns and not any(c in columns for c in (LOG_TIME, "x")):
            sweep = ("; a sweep of the current? --columns f=i --scale f=K reads it, K the force "
                     "constant (N/A, Nm/A on a rotary axis; divided by 1000 for a current in mA)")
        return (f"a motion log needs t, v or x, and force or i: missing {' and '.join(missing)} "
                f"(header is {header}){header_hint(cells)}{suggested_columns(cells) or sweep}")
    missing = ", ".join(repr(c) for c in ("v", "f") if c not in columns)
    return (f"missing column {missing} of a sweep, or t, v or x, and force or i of a motion log "
            f"(header is {header}){header_hint(cells)}{suggested_columns(cells)}")


def identify_log(columns: Dict[str, np.ndarray], mass: Optional[float] = None,
                 force_constant: Optional[float] = None,
                 progress: Optional[Callable[[str], None]] = None,
                 use: Optional[np.ndarray] = None, gravity: bool = False,
                 held: bool = False) -> Identification:
    """``identify_friction`` on the columns of a log: force in N, or current i in A times
    ``force_constant`` (N/A). A current without a force constant determines M/K and the friction
    over K only: with ``mass`` that gives K = M / (M/K); without, ``DataError`` saying so.
    ``progress``, ``use`` (a mask of the log's rows), ``gravity`` and ``held`` as there."""
    if "temperature" in columns:                # a sensor's slower rate: blank cells between
        columns = {**columns, "temperature": interpolated(columns["temperature"], columns.get("t"))}
    for name, values in columns.items():        # named as the file has them (i, not force)
        check_finite(name, values)
    if use is not None:                         # resampled with the columns
        columns = {**columns, USE_COLUMN: np.asarray(use, dtype=float)}
    columns, resampled, runs = resampled_runs(columns, MIN_LOG_ROWS)
    use = columns.pop(USE_COLUMN, None)
    ident = _identify_log(columns, mass, force_constant, progress,
                          None if use is None else use > 0.5, gravity, runs, held)
    return replace(ident, resampled=resampled) if resampled else ident


def _identify_log(columns, mass, force_constant, progress, use=None,
                  gravity=False, runs=None, held=False) -> Identification:
    conditions = {k: columns[k] for k in CONDITIONS if k in columns}
    t, motion = columns["t"], {"v": columns.get("v"), "x": columns.get("x"), "progress": progress,
                               "use": use, "conditions": conditions, "gravity": gravity,
                               "runs": runs, "held": held, "a": columns.get("a")}
    if "load" in conditions and "force" not in columns and force_constant is None:
        raise DataError("the log has a load column and a current i but no force: the load is a "
                        f"force, the current not: pass --force-constant ({axis_units().force_constant})")
    if "force" in columns:
        if force_constant is not None:
            raise DataError("the log has a force column; --force-constant applies to a current column i")
        check_varies(columns["force"], axis_units().effort, axis_units().force)
        return identify_friction(t, columns["force"], mass, **motion)
    current = columns["i"]
    check_varies(current, "current i", "A")
    if force_constant is not None:
        return replace(identify_friction(t, force_constant * current, mass, **motion),
                       force_constant=(float(force_constant), None))
    in_amperes = identify_friction(t, current, None, **{**motion, "conditions": {}}).body  # m/K, o/K
    units = axis_units()
    m_k = f"{in_amperes.mass:.4g} +- {in_amperes.mass_se:.2g} {units.per_force_constant}"
    if mass is not None and not in_amperes.mass_determined:
        raise DataError(f"the log's accelerations do not determine M/K ({m_k}), so --mass cannot "
                        "give K: pass --force-constant, or log motion that accelerates and brakes")
    if mass is None:
        raise DataError(f"the log has a current i but no {units.effort}: it determines M/K = {m_k} "
                        f"and the friction in A, not M nor the {units.effort} in {units.force}: pass "
                        f"--force-constant ({units.force_constant}), or --mass ({units.mass}) to "
                        "identify K")
    k = mass / in_amperes.mass
    k_se = k * in_amperes.mass_se / in_amperes.mass
    return replace(identify_friction(t, k * current, mass, **motion), force_constant=(k, k_se))
