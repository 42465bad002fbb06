"""What the columns of a motion log hold, told from how its force follows them: the textbook
law of the force (inertia, Coulomb + viscous per direction, a constant; [C1]) fitted with each
column read as named and read otherwise. A position column that holds the velocity, a velocity
that holds the position, a velocity swapped with the force, a joint's position in degrees are
refused in one line (``check_motion_column``, ``check_force_column``, ``check_degrees``); a
weight of the position that the force holds is told (``weight_residuals``, for ``train
--gravity``). ``check_log_columns`` runs them, each column smoothed once.
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

from ..errors import DataError
from .smoothing import smooth

#: A log of x alone (or v alone) is refused as holding the other quantity when reading its
#: column one derivative up (down) leaves the textbook law of the force (``_residual``) at most
#: this share of the residual it leaves read as named.
OTHER_QUANTITY_SHARE = 0.5
#: A log's v and force are refused as swapped where the share of v's variance that the textbook
#: law of the force read the other way round leaves unexplained is at most this fraction of the
#: share it leaves of the force's.
SWAPPED_SHARE = 0.25
#: A log with x and without ``--gravity`` is told of a weight G_s sin x + G_c cos x when that
#: term leaves at most this share of the textbook law's residual.
WEIGHT_SHARE = 0.7


def textbook_columns(a: np.ndarray, v: np.ndarray, *extra: np.ndarray) -> np.ndarray:
    """The columns of the textbook law of a log's force ([C1]): m a, Coulomb + viscous per
    direction of v, a constant, and ``extra`` columns."""
    up, down = v > 0, v < 0
    return np.column_stack([a, up, up * v, -1.0 * down, down * v, np.ones_like(v), *extra])


def _residual(force: np.ndarray, a: np.ndarray, v: np.ndarray, *extra: np.ndarray) -> float:
    """The RMS residual of the textbook law of a log's force (``textbook_columns``) by least
    squares."""
    columns = textbook_columns(a, v, *extra)
    theta, *_ = np.linalg.lstsq(columns, force, rcond=None)
    return float(np.sqrt(np.mean((force - columns @ theta) ** 2)))


def _window(n: int) -> int:
    """The checks' smoothing window for a log of ``n`` rows: about a 200th of it, 7 to 101."""
    return min(max(7, 2 * (n // 400) + 1), 101)


def _inner(n: int) -> slice:
    """The rows the checks use: all but a ``_window`` at each end."""
    return slice(_window(n), n - _window(n))


def _derivatives(values: np.ndarray, force: np.ndarray, ts: float, orders: int = 3):
    """The column and its derivatives up to the second (the first ``orders`` of the three:
    cubic Savitzky-Golay, ``_window``; None for those not asked for) and the force at the
    ``_inner`` rows; None for a short log."""
    window, inner = _window(values.size), _inner(values.size)
    if values.size < 4 * window:
        return None
    return ([smooth(values, window, k, ts)[inner] for k in range(orders)] + [None] * (3 - orders)
            + [force[inner]])


def check_motion_column(name: str, signals) -> None:
    """A log with a position ``x`` and no v, or a velocity ``v`` and no x: ``DataError`` when
    the column reads as the other quantity, that is when the force's textbook law (inertia,
    Coulomb + viscous per direction, a constant, and the column itself, its sine and cosine: a
    spring's or a link's weight, or a curve of v beyond the law) leaves at most
    OTHER_QUANTITY_SHARE of the residual with the column one derivative up (an x that holds the
    velocity) or down (a v that holds the position). Friction follows the sign of the velocity:
    read one derivative off, it follows none of the signals the law is given. ``signals``: the
    column's ``_derivatives``."""
    d0, d1, d2, f = signals
    own = (d0, np.sin(d0), np.cos(d0))        # read as x, a spring's or a link's weight; as
    if name == "x":                           # v, a curve beyond Coulomb + viscous
        named, other = _residual(f, d2, d1, *own), _residual(f, d1, d0, *own)
        held, other_name, other_column = "velocity", "position", "v"
    else:
        named, other = _residual(f, d1, d0, *own), _residual(f, d2, d1, *own)
        held, other_name, other_column = "position", "velocity", "x"
    if other <= OTHER_QUANTITY_SHARE * named:
        raise DataError(f"{name} holds a {held}, not a {other_name}: friction and inertia explain "
                        f"the force with {name} as {other_column} (RMS residual {other:.3g}, against "
                        f"{named:.3g} with {name} as the {other_name}): is it the {other_column} column?")


def check_force_column(named, other, weight: Tuple[np.ndarray, ...] = (), column: str = "v") -> None:
    """``DataError`` where a log's v and force are swapped: the force's textbook law
    (``_residual``) read the other way round, the force as the velocity and v as the force,
    leaves at most SWAPPED_SHARE of the share of the variance it leaves read as named. (A
    viscous law reads alike both ways and passes; the robot joints of benchmarks/real_data.py
    leave 0.68 or more.) ``named``, ``other``: the ``_derivatives`` of v beside the force and
    of the force beside v; ``weight``: columns of the position both readings take (sin x and
    cos x: a link's weight would otherwise leave the force unexplained, read as named);
    ``column``: the motion's column named in the message ("x" where v is dx/dt)."""
    share = [_residual(f, d1, d0, *weight) ** 2 / max(float(np.var(f)), 1e-300)
             for d0, d1, _, f in (named, other)]
    if share[1] <= SWAPPED_SHARE * share[0]:
        motion, force = ("v", "the force") if column == "v" else ("dx/dt", "the force's derivative")
        raise DataError(f"{column} and the force look swapped: friction and inertia explain "
                        f"{motion} from {force} "
                        f"({100 * share[1]:.2g} % of its variance left) far better than the force "
                        f"from {motion} ({100 * share[0]:.2g} % left): are the {column} and force (or "
                        "current) columns swapped?")


def check_force_swap(force: np.ndarray, ts: float, v: Optional[np.ndarray],
                     x: Optional[np.ndarray] = None) -> None:
    """``check_force_column`` on a log's columns (v's and the force's ``_derivatives``, the
    weight of ``x`` where it is given); without v, on dx/dt and the force's derivative beside
    x (x swapped with the force). A short log is not checked."""
    if v is None:
        if x is not None and x.size > 2:
            named = _derivatives(np.gradient(x, ts), force, ts)
            if named is not None:
                check_force_column(named, _derivatives(np.gradient(force, ts), x, ts, orders=2),
                                   column="x")
        return
    of_v = _derivatives(v, force, ts)
    if of_v is not None:
        inner = _inner(v.size)
        weight_columns = () if x is None else (np.sin(x[inner]), np.cos(x[inner]))
        check_force_column(of_v, _derivatives(force, v, ts, orders=2), weight_columns)


def weight_residuals(signals) -> Optional[Tuple[float, float]]:
    """The RMS residual of the force's textbook law (``_residual``) without and with a weight
    G_s sin x + G_c cos x of the position (``train --gravity``'s), where the weight leaves at
    most WEIGHT_SHARE of it: the log holds a link's weight that the friction samples would
    take in; None where it does not. ``signals``: the position's ``_derivatives``."""
    d0, d1, d2, f = signals
    without, with_weight = _residual(f, d2, d1), _residual(f, d2, d1, np.sin(d0), np.cos(d0))
    return (without, with_weight) if with_weight <= WEIGHT_SHARE * without else None


#: With ``--gravity``, a joint's position is read as degrees where it spans more than a turn
#: read in rad, and a weight of x pi / 180 leaves at most this share of the residual that a
#: weight of x (rad) leaves.
DEGREES_SHARE = 0.7


def check_degrees(signals) -> None:
    """``DataError`` where a joint's position, whose log holds a link's weight (``train
    --gravity``), reads as degrees: read in rad it spans more than a turn, and a weight
    G_s sin x + G_c cos x of x pi / 180 leaves at most DEGREES_SHARE of the residual of the
    force's textbook law with a weight of x itself (sin x of an x in degrees turns over every
    6.3 degrees: a 6 Nm link's weight was found as 0.04 Nm, and the joint's speeds 57 times
    too fast). Without ``--gravity`` a weight of a small arc in degrees is a spring's force in
    rad, and nothing is said. ``signals``: the position's ``_derivatives``."""
    d0, d1, d2, f = signals
    span = float(np.ptp(d0))
    if span <= 2.0 * np.pi:
        return
    angle = np.radians(d0)
    as_rad = _residual(f, d2, d1, np.sin(d0), np.cos(d0))
    as_deg = _residual(f, d2, d1, np.sin(angle), np.cos(angle))
    if as_deg <= DEGREES_SHARE * as_rad:
        raise DataError(f"x looks in degrees: it spans {span:.4g} rad ({span / (2 * np.pi):.3g} "
                        f"turns), and the link's weight G_s sin x + G_c cos x leaves an RMS "
                        f"residual of {as_deg:.3g} of x in degrees against {as_rad:.3g} in rad: "
                        "--scale x=0.0174533 (and v=0.0174533 where the log has v) converts it")


#: A log's acceleration column is dv/dt where it follows dv/dt with a slope within this factor
#: of 1 and dv/dt explains at least ACCELERATION_SHARE of its variance
#: (``check_acceleration_column``).
ACCELERATION_SLOPE = 1.2
ACCELERATION_SHARE = 0.5
#: A degree in rad: an acceleration in deg/s^2 beside a v in rad/s follows dv/dt with slope 1 / DEGREE.
DEGREE = np.pi / 180.0


def check_acceleration_column(v: np.ndarray, a: np.ndarray, ts: float) -> None:
    """``DataError`` where a log's acceleration column ``a`` is not its dv/dt: smoothed alike
    (``_derivatives``' window), regressed on dv/dt (with a constant; the noise of a
    double-differenced position biases no slope so) it has a slope beyond ACCELERATION_SLOPE
    of 1, or dv/dt explains less than ACCELERATION_SHARE of its variance: an acceleration in
    other units, another axis's, a velocity, a lagging estimate. A short log is not checked."""
    window, inner = _window(v.size), _inner(v.size)
    if v.size < 4 * window:
        return
    dv_dt, given = smooth(v, window, 1, ts)[inner], smooth(a, window)[inner]
    if np.ptp(given) == 0:
        raise DataError("the log's acceleration column is constant: it holds no dv/dt")
    columns = np.column_stack([dv_dt, np.ones_like(dv_dt)])
    coef, *_ = np.linalg.lstsq(columns, given, rcond=None)
    slope = float(coef[0])
    share = 1.0 - float(np.var(given - columns @ coef)) / max(float(np.var(given)), 1e-300)
    if not (1 / ACCELERATION_SLOPE <= slope <= ACCELERATION_SLOPE and share >= ACCELERATION_SHARE):
        units = ("in deg/s^2? --scale a=0.0174533 converts it" if abs(slope * DEGREE - 1) < 0.3
                 else "in other units (--scale a=FACTOR), another axis's, an estimate that lags, "
                 "or another quantity?")
        raise DataError(f"the log's acceleration column (a) is not its dv/dt: it follows dv/dt with "
                        f"slope {slope:.3g} (1 for an acceleration) and dv/dt explains "
                        f"{100 * max(share, 0):.0f} % of its variance: {units}")


def check_log_columns(force: np.ndarray, ts: float, v: Optional[np.ndarray] = None,
                      x: Optional[np.ndarray] = None,
                      gravity: bool = False) -> Optional[Tuple[float, float]]:
    """Every check of what a log's columns hold, each column smoothed once: a position or a
    velocity alone read as the other (``check_motion_column``), v swapped with the force
    (``check_force_column``); with ``gravity`` (``train --gravity``), a joint's position in
    degrees (``check_degrees``), and without it the position's ``weight_residuals`` (None
    without x, or where the weight explains little). A short log is not checked."""
    of_v = None if v is None else _derivatives(v, force, ts)
    of_x = None if x is None else _derivatives(x, force, ts)
    if of_v is None and of_x is None:
        return None                                     # too short to tell
    if v is None or x is None:
        check_motion_column("v" if x is None else "x", of_v if x is None else of_x)
    if v is not None:
        check_force_swap(force, ts, v, x)
    if gravity:
        if of_x is not None:
            check_degrees(of_x)
        return None
    return weight_residuals(of_x) if of_x is not None else None
