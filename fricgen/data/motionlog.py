"""Measured motion logs: CSV with columns t (s), x (m), v (m/s), i (A), sampled uniformly (or a
MATLAB file with these variables).

A log comes from any controller. Extra columns (e.g. ``x_d``) are kept but not interpreted.
``read_log_csv`` validates everything before anything uses it and raises ``DataError`` with one
line that names the problem.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, Optional, Tuple, Union

import numpy as np

from .._io import named_data
from ..errors import DataError
from ..units import axis_units
from .matfile import is_matfile, read_matfile
from .smoothing import smooth
from .table import DROPPED_SAMPLE, SLOW_SIGNALS, header_hint, read_table_csv, table_csv_text

#: The columns every log must have.
COLUMNS = ("t", "x", "v", "i")
#: Fewest samples a usable log may have.
MIN_SAMPLES = 1000
#: Largest relative deviation of one sampling interval from the median interval.
UNIFORM_TOLERANCE = 0.01
#: The range the ratio of dx/dt to v must lie in for x, v and t to be in consistent units.
UNITS_TOLERANCE = (0.5, 2.0)
#: Below this correlation of dx/dt with v, x and v are not one motion in other units (the axis
#: stands still in the sensor noise, or the columns are of different axes).
UNRELATED_BELOW = 0.3


def uniform_time(t: np.ndarray) -> Tuple[np.ndarray, float]:
    """``t`` and its sampling interval, or the uniform grid it was rounded from when it was
    written with a fixed number of decimals (``_rounded_grid``) and that grid's interval;
    ``DataError`` as ``uniform_sample_time``."""
    try:
        return t, uniform_sample_time(t)
    except DataError:
        grid = _rounded_grid(t)
        if grid is None:
            raise
        return grid, float(np.median(np.diff(grid)))


#: A log's time stamps may jitter by up to this factor of the median step and still be
#: resampled onto a uniform grid (a robot controller's 10-12 ms); beyond it, a gap is refused.
JITTER_RESAMPLED = 10.0


def resampled_uniformly(columns: Dict[str, np.ndarray]) -> Tuple[Dict[str, np.ndarray], bool]:
    """The columns on a uniform time grid: as they are when ``t`` is uniform (``uniform_time``),
    else every column linearly interpolated onto the grid of the median step over t's span
    (time stamps that jitter, as a robot controller's or an irregular logger's do). The flag
    says whether they were resampled. ``DataError`` when t does not increase, or when one step
    exceeds JITTER_RESAMPLED median steps (a gap, not jitter)."""
    t = columns["t"]
    try:
        grid = uniform_time(t)[0]
        return {**columns, "t": grid}, False
    except DataError:
        dt = np.diff(t)
        ts = float(np.median(dt))
        if not (ts > 0 and np.all(dt > 0)):
            raise
        if float(dt.max()) > JITTER_RESAMPLED * ts:
            k = int(np.argmax(dt))
            raise DataError(f"log has a gap: t steps by {dt[k]:.6g} s between data rows {k + 1} "
                            f"and {k + 2}, {dt[k] / ts:.3g} times its median step {ts:.6g} s") from None
    grid = t[0] + ts * np.arange(int(np.floor((t[-1] - t[0]) / ts + 1e-9)) + 1)
    return {k: (grid if k == "t" else np.interp(grid, t, c)) for k, c in columns.items()}, True


def run_starts(t: np.ndarray, min_rows: int) -> np.ndarray:
    """The rows where a new run begins in a log concatenated from runs: t restarts (steps back
    into the first half of the run before, or earlier: a run timed from 0 again) or pauses (a
    step beyond JITTER_RESAMPLED median steps, a logger stopped between runs). Empty when there
    is one run, or when t steps back by less (swapped rows), which ``resampled_uniformly``
    names; ``DataError`` for a run of fewer than ``min_rows`` rows."""
    dt = np.diff(t)
    ahead = dt[dt > 0]
    none = np.zeros(0, dtype=int)
    if not ahead.size:
        return none
    starts = np.flatnonzero((dt < 0) | (dt > JITTER_RESAMPLED * float(np.median(ahead)))) + 1
    bounds = np.concatenate([[0], starts, [t.size]])
    for before, start in zip(bounds[:-2], starts):
        if t[before] + 0.5 * (t[start - 1] - t[before]) < t[start] < t[start - 1]:
            return none                                 # back, but not to a run's start
    rows = np.diff(bounds)
    if starts.size and rows.min() < min_rows:
        k = int(np.argmin(rows))
        raise DataError(f"run {k + 1} of {rows.size} (data rows {bounds[k] + 1} to {bounds[k + 1]}, "
                        f"where t restarts or pauses) has {rows[k]} rows, need at least {min_rows}: "
                        "leave it out of the file")
    return starts


def resampled_runs(columns: Dict[str, np.ndarray], min_rows: int):
    """``resampled_uniformly`` run by run (``run_starts``), the runs joined end to end on one
    time grid: (columns, whether resampled, the run of each row, or None for a single run).
    ``DataError`` when the runs were sampled at different rates."""
    starts = run_starts(columns["t"], min_rows)
    if not starts.size:
        return (*resampled_uniformly(columns), None)
    bounds = np.concatenate([[0], starts, [columns["t"].size]])
    runs, resampled = [], False
    for k, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
        try:
            run, again = resampled_uniformly({name: c[a:b] for name, c in columns.items()})
        except DataError as exc:
            raise DataError(f"run {k + 1} of {len(bounds) - 1} (data rows {a + 1} to {b}): "
                            f"{exc}") from None
        runs.append(run)
        resampled |= again
    steps = [float(np.median(np.diff(run["t"]))) for run in runs]
    if max(steps) - min(steps) > UNIFORM_TOLERANCE * min(steps):
        slow, fast = int(np.argmax(steps)), int(np.argmin(steps))
        raise DataError(f"the log's runs are sampled at different rates: run {slow + 1} every "
                        f"{steps[slow]:.6g} s, run {fast + 1} every {steps[fast]:.6g} s; train "
                        "runs of one rate together")
    joined = {name: np.concatenate([run[name] for run in runs]) for name in columns}
    joined["t"] = columns["t"][0] + steps[0] * np.arange(joined["t"].size)
    run_of_row = np.repeat(np.arange(len(runs)), [run["t"].size for run in runs])
    return joined, resampled, run_of_row


def uniform_sample_time(t: np.ndarray) -> float:
    """The median sampling interval of the time column ``t``; ``DataError`` unless t increases
    and every step lies within UNIFORM_TOLERANCE of it. Messages count data rows from 1."""
    dt = np.diff(t)
    ts = float(np.median(dt)) if dt.size else 0.0
    if not ts > 0:
        raise DataError(f"time column must increase, median step is {ts:g} s")
    worst = float(np.max(np.abs(dt - ts)))
    if not worst <= UNIFORM_TOLERANCE * ts:
        k = int(np.argmax(np.abs(dt - ts)))
        rows = f"data rows {k + 1} and {k + 2}"
        if dt[k] == 0:
            raise DataError(f"t repeats at {rows} ({t[k]:.6g} s)")
        if dt[k] < 0:
            back = int(np.count_nonzero(dt < 0))
            more = f" (and at {back - 1} other rows: sort the log by t?)" if back > 1 else ""
            raise DataError(f"t goes back by {-dt[k]:.6g} s between {rows}{more}: time must "
                            "increase")
        off = np.flatnonzero(np.abs(dt - ts) > UNIFORM_TOLERANCE * ts)
        k = int(off[0])                             # the first, where the user looks first
        more = f" (the first of {off.size} such steps)" if off.size > 1 else ""
        raise DataError(f"log is not uniformly sampled: t steps by {dt[k]:.6g} s between data rows "
                        f"{k + 1} and {k + 2}{more}, median step is {ts:.6g} s")
    return ts


def _rounded_grid(t: np.ndarray) -> Optional[np.ndarray]:
    """The uniform grid ``t`` was rounded from (written with a fixed number of
    decimals, e.g. milliseconds at 300 Hz), or None: every sample written to that unit and
    within 0.75 of a unit of the least-squares line through the samples (rounding leaves half
    a unit). The unit may be coarser than the step (a 67 Hz log written to 10 ms, a 4 kHz one
    in whole ms, several rows to a stamp: both had been refused), the line's step then the
    log's; the line holds a dropped sample within the rounding there, as the stamps do."""
    k = np.arange(t.size)
    step, start = np.polyfit(k, t - t[0], 1)
    if not step > 0:
        return None
    grid = t[0] + start + step * k
    rounding = 8.0 * np.finfo(float).eps * max(abs(float(t[0])), abs(float(t[-1])), 1.0)
    for decimals in range(10):
        unit = 10.0 ** -decimals
        off = np.abs(t / unit - np.round(t / unit))
        if float(np.max(off)) <= rounding / unit + 1e-9:        # t is written to this unit
            return grid if float(np.max(np.abs(t - grid))) <= 0.75 * unit + rounding else None
    return None


def check_moves(v: np.ndarray, x: Optional[np.ndarray] = None, v_given: bool = True) -> None:
    """``DataError`` when the velocity column is 0 throughout (naming x's travel if x moves), or,
    where v is x's derivative (``v_given`` False), when x never changes."""
    if np.any(v):
        return
    if not v_given:
        raise DataError("the position x never changes: the axis never moves")
    if x is not None and np.ptp(x) > 0:
        raise DataError(f"column 'v' is 0 throughout while x travels {np.ptp(x):.3g} "
                        f"{axis_units().position}: is v logged?")
    raise DataError("column 'v' is 0 throughout: the axis never moves")


def check_finite(name: str, values: np.ndarray, where: str = "") -> None:
    """``DataError`` naming the first data row (from 1) where the column ``name`` is NaN or
    infinite, after ``where`` (the file) when given."""
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise DataError(f"{where + ': ' if where else ''}column {name!r} holds NaN or infinite "
                        f"value at data row {int(bad[0]) + 1}{'' if name in SLOW_SIGNALS else DROPPED_SAMPLE}")


def varies(values: np.ndarray) -> bool:
    """Whether the finite ``values`` of a logged signal hold more than one value over 98 % of
    the log (their 1 % and 99 % quantiles differ); True where none is finite."""
    values = values[np.isfinite(values)]
    return values.size == 0 or bool(np.ptp(np.quantile(values, [0.01, 0.99])) > 0)


def check_varies(values: np.ndarray, what: str, unit: str) -> None:
    """``DataError`` when the finite ``values`` of a logged signal hold one value over 98 % of
    the log (``varies``): the signal was not really logged."""
    if not varies(values):
        values = values[np.isfinite(values)]
        raise DataError(f"the {what} is constant ({np.median(values):g} {unit}) over 98 % of the "
                        f"log; a log needs the measured {what}")


def _follows(derivative: np.ndarray, column: np.ndarray) -> Tuple[float, float]:
    """The least-squares ratio of ``derivative`` to ``column`` and their correlation."""
    if not (np.ptp(derivative) > 0 and np.ptp(column) > 0):
        return 0.0, 0.0
    return (float(np.dot(derivative, column) / np.dot(column, column)),
            float(np.corrcoef(derivative, column)[0, 1]))


def check_swapped_force(x: np.ndarray, v: np.ndarray, force: np.ndarray, ts: float) -> None:
    """``DataError`` naming a swap where x and v disagree (dx/dt off v by more than
    UNITS_TOLERANCE) and dx/dt follows the force column, or the force's derivative follows v,
    within UNITS_TOLERANCE and more closely than dx/dt follows v (a joint's torque that is
    mostly viscous correlates with its speed at 0.9 or more, and a swapped log had been told
    its units were off)."""
    dxdt = np.gradient(x, ts)
    ratio, own = _follows(dxdt, v)
    own = abs(own)
    low, high = UNITS_TOLERANCE
    if low <= ratio <= high:
        return
    for pair, (scale, follow), what in (
            ("v and force", _follows(dxdt, force), "dx/dt follows the force column"),
            ("x and force", _follows(np.gradient(force, ts), v), "the force column's derivative follows v")):
        if low <= scale <= high and follow > own:
            raise DataError(f"{pair.replace(' and ', ' and the ')} look swapped: {what} ({scale:.3g} "
                            f"times it, correlation {follow:.3f}) closer than dx/dt follows v "
                            f"({ratio:.3g} times it, correlation {own:.3f}): are the {pair} (or "
                            "current) columns swapped?")


def check_units(x: np.ndarray, v: np.ndarray, ts: float, force: Optional[np.ndarray] = None) -> None:
    """x, v and the sampling interval ``ts`` must agree: the least-squares ratio of dx/dt to v
    lies within UNITS_TOLERANCE of 1 (a time column in ms, or x in mm, is off by 1000). Where
    they do not and a ``force`` is given, a force column that x or v would agree with names a
    swap (``check_swapped_force``)."""
    dxdt = np.gradient(x, ts)
    ratio = float(np.dot(dxdt, v) / np.dot(v, v))
    low, high = UNITS_TOLERANCE
    if not low <= ratio <= high:
        check_varies(x, "position x", "m")          # x not logged: not a matter of units
        if force is not None:
            check_swapped_force(x, v, force, ts)
        follow = float(np.corrcoef(dxdt, v)[0, 1]) if np.ptp(dxdt) > 0 else 1.0
        if not abs(follow) >= UNRELATED_BELOW:
            raise DataError(f"x does not follow v: dx/dt and v correlate by {follow:.2f} (does the "
                            "axis move beyond the sensor noise? are x and v of one axis?)")
        dvdt = np.gradient(v, ts)
        swapped = float(np.dot(dvdt, x) / np.dot(x, x)) if np.dot(x, x) > 0 else 0.0
        if low <= swapped <= high:
            raise DataError(f"t, x and v disagree: dx/dt is {ratio:.3g} times v, but dv/dt is "
                            f"{swapped:.3g} times x: are the x and v columns swapped?")
        if -high <= ratio <= -low:
            raise DataError(f"x and v have opposite signs: dx/dt is {ratio:.3g} times v (is x or "
                            "v inverted?)")
        degrees = {np.degrees(1.0): f"x in degrees and v in rad/s? --scale x={np.radians(1.0):.6g}",
                   np.radians(1.0): f"v in deg/s and x in rad? --scale v={np.radians(1.0):.6g}"}
        guess = next((hint for factor, hint in degrees.items() if abs(ratio / factor - 1) < 0.05),
                     "t in ms, x in mm, or v in other units?")
        raise DataError(f"t, x and v disagree: dx/dt is {ratio:.3g} times v (is {guess})")


#: A logged velocity that lags (or leads) dx/dt by more than this many samples ...
LAG_SAMPLES = 0.25
#: ... and this many standard errors (``velocity_lag``) is set aside for dx/dt.
LAG_SIGMAS = 4.0
#: Samples of the Savitzky-Golay filter that smooths x's derivatives and v alike there.
LAG_WINDOW = 31
#: The share of v's square that a lagging dx/dt must explain for v to be one (a joint's torque
#: logged as dq, the velocity as tau, read as a velocity leading dx/dt by 50 ms with 9.5 % left,
#: was set aside for dx/dt, and the force, the velocity itself, trained to a viscous slope of
#: 1 +- 1e-5; a velocity filtered at 2 Hz, 65 ms behind, leaves 1 %).
LAG_EXPLAINED = 0.98


def velocity_lag(t: np.ndarray, x: np.ndarray, v: np.ndarray) -> Optional[Tuple[float, float, float]]:
    """How far the logged velocity v lags dx/dt (s; < 0: leads), its standard error and the
    sampling interval: v(t) = dx/dt(t - tau) ~ dx/dt - tau d2x/dt2, fitted by least squares
    over each run (``run_starts``), v and x's derivatives smoothed by one Savitzky-Golay filter
    (``smoothing.smooth``) of LAG_WINDOW samples (a filter common to both leaves the lag as it
    is). The standard error counts one independent sample per window. None where x and v are
    not one motion in one unit (``check_units`` and the other checks name that), where a lagging
    dx/dt leaves more than 1 - LAG_EXPLAINED of v's square unexplained (v is another quantity:
    a swapped column, which those checks name), or where no run holds three windows."""
    try:
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
            return None
        bounds = np.concatenate([[0], run_starts(t, 1), [t.size]])
    except DataError:
        return None
    cut, parts, ts = LAG_WINDOW // 2, [], None
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b - a < 3 * LAG_WINDOW:
            continue
        step = float(np.median(np.diff(t[a:b])))
        if not step > 0:
            return None
        ts = ts or step
        parts.append([smooth(x[a:b], LAG_WINDOW, 1, step)[cut:-cut],
                      smooth(x[a:b], LAG_WINDOW, 2, step)[cut:-cut],
                      smooth(v[a:b], LAG_WINDOW)[cut:-cut]])
    if ts is None:
        return None
    dxdt, curvature, smoothed = (np.concatenate(p) for p in zip(*parts))
    speed, moving = float(np.dot(smoothed, smoothed)), float(np.dot(curvature, curvature))
    low, high = UNITS_TOLERANCE
    if not (speed > 0 and moving > 0 and low <= np.dot(dxdt, smoothed) / speed <= high):
        return None
    residual = smoothed - dxdt
    tau = -float(np.dot(residual, curvature)) / moving
    left = float(np.sum((residual + tau * curvature) ** 2))
    if left > (1.0 - LAG_EXPLAINED) * speed:    # no lagging copy of dx/dt: another quantity
        return None
    spread = left / max(residual.size - 1, 1)
    return tau, float(np.sqrt(spread / moving * LAG_WINDOW)), ts


def without_lagging_velocity(columns: Dict[str, np.ndarray], warn) -> Dict[str, np.ndarray]:
    """``columns`` without the velocity v where it lags (or leads) dx/dt beyond LAG_SAMPLES and
    LAG_SIGMAS standard errors (``velocity_lag``), with one line through ``warn`` saying so: the
    velocity is then dx/dt. A lag tau biases the inertia by the viscous slope times tau and
    makes the force lead the motion as pre-sliding would."""
    if "x" not in columns or "v" not in columns or "t" not in columns:
        return columns
    found = velocity_lag(*(np.asarray(columns[k], dtype=float) for k in ("t", "x", "v")))
    if found is None:
        return columns
    tau, se, ts = found
    if not (abs(tau) > LAG_SAMPLES * ts and abs(tau) > LAG_SIGMAS * se):
        return columns
    warn(f"fricgen: v {'lags' if tau > 0 else 'leads'} dx/dt by {abs(tau) * 1e3:.3g} ms "
         f"({abs(tau) / ts:.2g} samples, +- {se / ts:.2g}; a drive's filtered velocity?): the "
         "velocity is taken from x (a lagging v biases the inertia by the viscous slope times the lag)")
    return {k: c for k, c in columns.items() if k != "v"}


@dataclass(frozen=True)
class MotionLog:
    """A uniformly sampled log of time t, position x, velocity v and motor current i.

    Parameters
    ----------
    t : array_like
        Time (s), uniformly sampled, at least 1000 samples.
    x : array_like
        Position (m).
    v : array_like
        Velocity (m/s); the axis must move.
    i : array_like
        Motor current (A); the force is phi i (sec. 6).
    extra : dict of str to array_like
        Other columns of the same length (kept, e.g. a measured force).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import MotionLog
    >>> t = np.arange(2000) * 1e-3
    >>> log = MotionLog(t, x=0.05 * np.sin(2 * np.pi * t), v=0.1 * np.pi * np.cos(2 * np.pi * t),
    ...                 i=np.sign(np.cos(2 * np.pi * t)))
    >>> len(log), round(log.sample_time, 4)
    (2000, 0.001)
    """

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    i: np.ndarray
    extra: Dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self):
        arrays = {k: np.asarray(getattr(self, k), dtype=float).ravel() for k in COLUMNS}
        n = arrays["t"].size
        for k, a in arrays.items():
            if a.size != n:
                raise DataError(f"column {k!r} has {a.size} samples, column 't' has {n}")
            check_finite(k, a)
            object.__setattr__(self, k, a)
        if n < MIN_SAMPLES:
            raise DataError(f"log has {n} samples, need at least {MIN_SAMPLES}")
        t, ts = uniform_time(self.t)
        object.__setattr__(self, "t", t)
        check_moves(self.v, self.x)
        check_units(self.x, self.v, ts)

    def __len__(self) -> int:
        return self.t.size

    @property
    def sample_time(self) -> float:
        """The (uniform) sampling interval Ts in seconds."""
        return float((self.t[-1] - self.t[0]) / (self.t.size - 1))


def read_log(path: Union[str, Path]) -> MotionLog:
    """Read a log CSV (``read_log_csv``) or a MATLAB file whose vector variables include t, x, v, i
    (other vectors of their length are kept as extra).

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV or .mat file.

    Returns
    -------
    MotionLog

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import MotionLog
    >>> t = np.arange(2000) * 1e-3
    >>> log = MotionLog(t, x=0.05 * np.sin(2 * np.pi * t), v=0.1 * np.pi * np.cos(2 * np.pi * t),
    ...                 i=np.sign(np.cos(2 * np.pi * t)))
    >>> from fricgen.data import log_csv_text, read_log
    >>> _ = (tmp / "log.csv").write_text(log_csv_text(log))
    >>> len(read_log(tmp / "log.csv"))
    2000
    """
    if not is_matfile(path):
        return read_log_csv(path)
    return _log_of(read_matfile(path).columns(COLUMNS), path)


def read_log_csv(path: Union[str, Path]) -> MotionLog:
    """Read a log CSV whose header names at least t, x, v, i (other numeric columns are kept as
    extra; a column with text in it is left out).

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV file.

    Returns
    -------
    MotionLog
        ``DataError`` for missing columns, non-uniform time, or too few samples.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import MotionLog
    >>> t = np.arange(2000) * 1e-3
    >>> log = MotionLog(t, x=0.05 * np.sin(2 * np.pi * t), v=0.1 * np.pi * np.cos(2 * np.pi * t),
    ...                 i=np.sign(np.cos(2 * np.pi * t)))
    >>> import fricgen
    >>> from fricgen.data import log_csv_text
    >>> _ = (tmp / "log.csv").write_text(log_csv_text(log))
    >>> bool(np.allclose(fricgen.read_log_csv(tmp / "log.csv").v, log.v))
    True
    """
    return _log_of(read_table_csv(path, COLUMNS, keep_extra=True, drop_text=True), path)


def log_from_columns(columns: Dict[str, np.ndarray], path, written=None) -> MotionLog:
    """The log of ``columns`` read from ``path`` (by fricgen's names, e.g. by
    ``export.read_export``); ``DataError`` naming the columns of COLUMNS it lacks (``written``:
    the header's names as the file writes them, for the hint on units in names)."""
    missing = [c for c in COLUMNS if c not in columns]
    if missing:
        cells = written or list(columns)
        raise DataError(f"{path}: a log needs the columns {', '.join(COLUMNS)}: missing "
                        f"{', '.join(missing)} (header is {','.join(cells)[:80]}){header_hint(cells)}")
    return _log_of(columns, path)


def _log_of(columns: Dict[str, np.ndarray], path) -> MotionLog:
    with named_data(path):
        return MotionLog(**{c: columns[c] for c in COLUMNS},
                         extra={h: a for h, a in columns.items() if h not in COLUMNS})


def log_csv_text(log: MotionLog) -> str:
    """The CSV text of a log: t, x, v, i and then the extra columns, floats written to round-trip.

    Parameters
    ----------
    log : MotionLog
        The log to write.

    Returns
    -------
    str

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import MotionLog
    >>> t = np.arange(2000) * 1e-3
    >>> log = MotionLog(t, x=0.05 * np.sin(2 * np.pi * t), v=0.1 * np.pi * np.cos(2 * np.pi * t),
    ...                 i=np.sign(np.cos(2 * np.pi * t)))
    >>> from fricgen.data import log_csv_text
    >>> log_csv_text(log).splitlines()[0]
    't,x,v,i'
    """
    columns = {c: getattr(log, c) for c in COLUMNS}
    columns.update({k: log.extra[k] for k in sorted(log.extra)})
    return table_csv_text(columns)
