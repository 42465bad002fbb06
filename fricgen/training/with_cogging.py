"""``fricgen train LOG --cogging``: the cogging map of a slow move (``fit.cogging``) and a
friction model of the same log with the map's force taken out: the default fit where the log
holds the speeds it needs, else Coulomb + viscous per direction from the map's own fit; a move
at one speed (a calibration) gets that fit's level at its speed. ``less_position_force``: the
same for a log of normal operation already trained (a fleet's), its map found in what the
friction model leaves."""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable, Mapping, Optional, Tuple

import numpy as np
from scipy.integrate import cumulative_trapezoid

from ..data.motionlog import check_finite
from ..effects.cogging_map import CoggingMap, check_rotary_period
from ..fit.cogging import (FUNDAMENTAL_PERIODS, SAMPLE_RATE_LIMIT, UNEXPLAINED_SHARE, UNVISITED,
                           CoggingFit, identify_cogging)
from ..errors import DataError, ModelError, UsageError
from ..fit.textbook import LawFit
from ..model import FrictionModel
from ..unit_sizes import size as unit_size
from ..units import units_of
from .record import speed_record
from .report import FitReport


@dataclass(frozen=True)
class CoggingReport:
    """The model (friction and cogging map), the report's text and the notes on the data."""

    model: FrictionModel
    text: str
    warnings: Tuple[str, ...]


def log_force(columns: Mapping[str, np.ndarray], force_constant: Optional[float]) -> np.ndarray:
    """The drive force of a log: ``force``, or the current ``i`` times the force constant
    (``DataError`` naming the column and its first row that is not finite)."""
    name = "force" if "force" in columns else "i"
    if name == "i" and force_constant is None:
        raise UsageError("--cogging on a log of current i needs --force-constant (N/A, Nm/A): the map "
                         "is a force")
    values = np.asarray(columns[name], dtype=float)
    check_finite(name, values)
    return values if name == "force" else force_constant * values


def _law(coulomb: float, viscous: float, fastest: float) -> LawFit:
    return LawFit(max(coulomb, 0.0), max(viscous, 0.0), None, None, None,
                  {"coulomb": 0.0, "viscous": 0.0}, fastest, 0.0)


def _law_of_the_move(fit: CoggingFit, speed: np.ndarray, name: str, units,
                   symmetric: bool = False) -> FrictionModel:
    """Coulomb + viscous per direction from the move (its speeds ``speed``), or one curve of
    their means where ``symmetric`` (the constant force between the directions left out, as a
    symmetric fit folds it), with the axis record of its speed range and the map's inertia
    where it has one (``recording_force_constant`` adds the force constant)."""
    cp, bp, cn, bn = fit.coulomb_viscous
    fastest = float(np.percentile(speed, 99))
    axis = speed_record(float(np.percentile(speed, 1)), fastest)
    if fit.inertia_source != "undetermined":
        axis.update(mass=fit.inertia, mass_from="cogging" if fit.inertia_source == "identified" else "option")
    training = {"units": units.kind, "axis": axis, "method": "coulomb_viscous_per_direction"}
    if symmetric:
        curve = _law((cp - cn) / 2, (bp + bn) / 2, fastest).direction()
        return FrictionModel.from_directions(curve, name=name, training={
            **training, "method": "coulomb_viscous_symmetric"})
    return FrictionModel.from_directions(_law(cp, bp, fastest).direction(),
                                         _law(-cn, bn, fastest).direction(), name=name,
                                         training=training)


#: Speeds within this factor of each other (the 95th and 5th percentiles of a move's) are one
#: speed: a slope or a Stribeck drop fitted over them is the ripple's, no measurement.
ONE_SPEED = 2.0


def _level_at_one_speed(model: FrictionModel, speeds: Tuple[float, float, float], units,
                        text: str) -> Tuple[FrictionModel, str]:
    """``model`` made the level it has at the move's median speed, per direction (one curve for a
    symmetric model), at every speed, and the report's line saying so. A calibration at one speed
    each way tells the friction there alone; the default fit of the speeds its ripple spreads
    (a new user's 0.75 to 1.27 rad/s) had drawn a viscous line through 0: a quarter of the
    friction at 0.3 rad/s and six times it at 6 rad/s."""
    slow, speed, fast = speeds
    forward, back = float(model.force(speed)), float(-model.force(-speed))
    per_direction = model.negative is not None
    if not per_direction:
        forward = back = (forward + back) / 2
    positive = _law(forward, 0.0, fast).direction()
    negative = _law(back, 0.0, fast).direction() if per_direction else None
    training = {**model.training, "method": "level_at_one_speed"}
    if "coulomb" in training:                 # the law's record says the level (``law_record_edits``)
        training = _level_record(training, forward)
        if per_direction:
            training["negative"] = _level_record(training.get("negative", {}), back)
    model = replace(model, aim=positive.aim, scaling=positive.scaling, viscous=positive.viscous,
                    v_sat=positive.v_sat, negative=negative, training=training)
    level = (f"{forward:.4g} {units.force} forward and {back:.4g} back" if per_direction
             else f"{forward:.4g} {units.force} each way")
    line = (f"friction  the move holds one speed ({slow:.3g} to {fast:.3g} {units.speed}, 5th to "
            f"95th percentile): the model is the fit's level there, {level}, at every speed "
            "(the fit's slope or drop over so narrow a range is no measurement: a move at other "
            "speeds identifies them)")
    return model, text + "\n" + line


def _level_record(record: dict, level: float) -> dict:
    """A law's training record made the level ``level``: Coulomb alone."""
    kept = {k: v for k, v in record.items() if k not in ("static", "v_s", "shape", "standard_errors")}
    return {**kept, "coulomb": level, "viscous": 0.0}


def describe(m: CoggingMap, what: str, units) -> list:
    """Lines of a map: each harmonic's amplitude and phase with its standard error."""
    lines = [f"{what}: {len(m.harmonics)} harmonics of the period {m.period:.6g} {units.position}, "
             f"RMS {m.rms:.4g} {units.force}"]
    phase = np.arctan2(m.cosine, m.sine)
    for h, amp, se, ph in zip(m.harmonics, m.amplitude, m.amplitude_se, phase):
        lines.append(f"  harmonic {h:4d}: {amp:.4g} +- {se:.2g} {units.force}, phase {ph % (2 * np.pi):.3f} rad")
    return lines


def train_with_cogging(columns: Mapping[str, np.ndarray], *, pitch: Optional[float], rotary: bool,
                       inertia: Optional[float], force_constant: Optional[float],
                       train_friction: Callable[[Mapping[str, np.ndarray], Optional[float], str], FitReport],
                       name: str, symmetric: bool = False,
                       fed_forward: Tuple[Optional[CoggingMap], Optional[CoggingMap]] = (None, None)
                       ) -> CoggingReport:
    """The map and the friction model (see the module docstring); ``train_friction(columns,
    mass, mass_source)`` fits the default model to columns (the map's force removed) and may refuse them;
    ``mass`` is the inertia the map took out where it was given or identified (a slow move
    at one speed accelerates too little to tell it again), else None, and ``mass_source``
    "cogging" where the map identified it, else "given". ``symmetric``: the
    friction of a move the default fit refuses is one curve (--symmetric), not one per
    direction. ``fed_forward``: the map and the friction's ripple of a first calibration whose
    map the drive fed forward in this move (``identify_cogging``'s)."""
    if "x" not in columns or "t" not in columns:
        raise UsageError("--cogging needs a motion log with time t and position x (the map is a "
                         "function of the position)")
    units = units_of(rotary)
    given = pitch is not None
    if rotary and given:
        check_rotary_period(pitch, "--pitch", DataError)
    travel = float(np.ptp(np.asarray(columns["x"], dtype=float)))
    if given and not rotary and pitch > travel:
        raise DataError(f"--pitch {pitch:.6g} m is longer than the log's travel ({travel:.6g} m): a "
                        "cogging map needs the whole period each way (--pitch is in m: 0.032 for 32 mm)")
    first_map, first_ripple = fed_forward
    second = first_map is not None
    if pitch is None and rotary and not second:
        pitch = 2 * np.pi
    force = log_force(columns, force_constant)
    fit = identify_cogging(columns["t"], columns["x"], force, pitch, inertia=inertia,
                           fed_forward=first_map, fed_forward_friction=first_ripple)
    if second and fit.map is None:
        raise DataError("the second calibration's force holds none of the fed-forward map's harmonics: "
                        "was its current logged without the feedforward? (log the whole current command)")
    check_period(fit, columns["t"], columns["x"], force, inertia, units, given)
    cleaned = {k: c for k, c in columns.items() if k != "i"}
    cleaned["force"] = force - (fit.map.force(columns["x"]) if fit.map is not None else 0.0)
    lines = []
    try:
        report = train_friction(cleaned, None if fit.inertia_source == "undetermined" else fit.inertia,
                                "cogging" if fit.inertia_source == "identified" else "given")
        model, text, warnings = report.model, report.text, list(report.warnings)
    except (DataError, ModelError, ValueError):
        speed = np.abs(np.gradient(columns["x"], columns["t"]))
        model = _law_of_the_move(fit, speed[speed > 0], name, units, symmetric)
        text = (f"friction: Coulomb + viscous {'symmetric' if symmetric else 'per direction'} from "
                "the move (a calibration at one speed each way holds too few speeds for the "
                "default fit)")
        warnings = []
    if fit.speeds[2] < ONE_SPEED * fit.speeds[0]:
        model, text = _level_at_one_speed(model, fit.speeds, units, text)
    if fit.inertia_source == "identified":      # the friction was fitted with the map's J
        model, text = _inertia_recorded(model, text, "option", {"mass_from": "cogging"},
                                        lambda row: row.replace(" as given", " from the cogging map's "
                                                                "ripple (below)"))
    elif fit.inertia_source == "undetermined" and fit.map is not None:
        # the map took out no J (its J a is in the map): the friction fit's J from the same log,
        # found in the ripple the map holds, is no measurement of the axis's (a new user's 14-bit
        # calibration emitted one 27 times too small, with a standard error of 4 %)
        model, text = _inertia_recorded(
            model, text, "data", {"mass": None, "mass_se": None, "mass_from": None},
            lambda row: f"{units.inertia_name:9s} not determined: the calibration accelerates only "
                        "by the ripple the cogging map holds (give --mass)")
    model = replace(recording_force_constant(model, columns, force_constant), cogging_map=fit.map,
                    cogging_friction=fit.friction)
    j = {"given": "given", "identified": "identified from the two directions' ripple",
         "undetermined": "not determined by this log, taken as 0" + (
             ": the ripple the fed-forward map leaves is too small to matter" if second else
             ": the map holds the inertia's ripple; move slower or give --mass" if fit.map is not None
             else "")}[fit.inertia_source]
    if second:
        lines.append(f"cogging: a second calibration, the first map fed forward: its harmonics "
                     f"({', '.join(map(str, first_map.harmonics))}) the candidates")
    elif pitch is None and fit.map is not None:
        lines.append(f"cogging: period {fit.map.period:.6g} +- {fit.period_se:.2g} {units.position} found "
                     "from the data (the strongest position harmonic's wavelength, or its fundamental; "
                     "--pitch gives a longer one)")
    lines.append(f"cogging: inertia {fit.inertia:.4g} {units.mass} ({j}); harmonics screened "
                 f"up to {fit.highest_harmonic} (set by {fit.screened_by}); {fit.rows} rows in motion")
    if fit.screened_by.startswith(SAMPLE_RATE_LIMIT):
        warnings.append(f"warning: the move is fast for the log's rate: harmonics above {fit.highest_harmonic} "
                        f"are not screened ({fit.screened_by})")
    elif UNVISITED in fit.screened_by:
        warnings.append(f"warning: harmonics above {fit.highest_harmonic} are not screened, set by "
                        f"{fit.screened_by}: the move stalls, skips or swings in speed (a velocity "
                        "loop that lets the cogging through), and the map misses what lies above: "
                        "stiffen the loop or move slower, and calibrate again")
    if fit.count_alias is not None and fit.map is not None:
        warnings.append(f"warning: the encoder's count rate at this speed is above half the log's "
                        f"rate, which folds it to harmonic {fit.count_alias} of the period: the drive's "
                        "ripple there, modulated by the cogging, can pass for harmonics of the map "
                        f"(the cogging's -+ {fit.count_alias}): log at the drive's loop rate, or move "
                        "slower, and calibrate again")
    if fit.steady_travel < STEADY_TRAVEL:
        warnings.append(f"warning: the move covers {fit.steady_travel:.0%} of its travel at a steady "
                        "speed; the rest stalls or turns back (a velocity loop that lets the cogging "
                        "through, or oscillates): the map, fitted on the steady rows alone, misses the "
                        "cogging held in the rest (stiffen the velocity loop and calibrate again)")
    if fit.unexplained_wavelength is not None and fit.map is not None:    # check_period refused the rest
        warnings.append("warning: " + _unexplained(
            fit.unexplained_wavelength, fit.period, units, "a period longer than the one found, x in "
            f"other units than {units.position}, or a ripple aliased by a log slower than the drive's loop?"))
    if rotary and fit.period < 2 * np.pi * (1 - TURN_TOLERANCE):
        dropped = turn_harmonics_dropped(columns["t"], columns["x"], force, fit.period, inertia)
        if dropped:
            many = len(dropped) > 1
            warnings.append(f"warning: the map of a whole turn holds harmonic{'s' if many else ''} "
                            f"{', '.join(map(str, dropped))} of the turn, which no harmonic of --pitch "
                            f"{fit.period:.6g} rad holds (a turn is {2 * np.pi / fit.period:.4g} of it): "
                            f"leave --pitch out to keep {'them' if many else 'it'}")
    if fit.map is None:
        lines.append("cogging: none found (no harmonic above the noise): no map is emitted")
    else:
        lines += describe(fit.map, "cogging map (position force)", units)
    if fit.friction is not None:
        lines += describe(fit.friction, "position-dependent friction (times sgn(v); reported, "
                          "not emitted)", units)
    return CoggingReport(model=model, text=text + "\n" + "\n".join(lines), warnings=tuple(warnings))


#: The least share of a calibration's travel covered at a steady speed without a warning.
STEADY_TRAVEL = 0.9
#: How close (relative) a harmonic of the turn must fall to a harmonic of a shorter pitch to be one.
TURN_TOLERANCE = 1e-3


def turn_harmonics_dropped(t, x, force, pitch: float, inertia: Optional[float]) -> Tuple[int, ...]:
    """The harmonics of a turn that the map of a rotary log over a whole turn holds and no
    harmonic of a shorter ``pitch`` does (the once-per-turn unbalance under a pole pitch); ()
    for a log shorter than a turn."""
    if np.ptp(x) < 2 * np.pi:
        return ()
    turn = identify_cogging(t, x, force, 2 * np.pi, inertia=inertia).map
    per_turn = 2 * np.pi / pitch
    return () if turn is None else tuple(h for h in turn.harmonics
                                         if abs(h / per_turn - round(h / per_turn)) > TURN_TOLERANCE * h / per_turn)


#: The position unit a log is often written in, per kind of axis.
OTHER_POSITION_UNITS = {"rotary": "deg", "linear": "mm"}
#: How close (in harmonics) a wavelength read in the other unit must fall on a harmonic ...
UNIT_TOLERANCE = 0.01
#: ... of at most this number: a motor's cogging lies at multiples of the least common multiple
#: of its slots and poles, below 2000 on servo motors' windings.
UNIT_HARMONICS = 2048


def _in_other_units(wavelength: float, period: float, units) -> bool:
    """Whether ``wavelength``, read in the unit a log is often written in (degrees, mm), is a
    harmonic of the period, at most UNIT_HARMONICS (a map in other units has its harmonics at
    the same numbers as the cogging's; UNIT_TOLERANCE holds for 2 % of any wavelengths by
    chance, and a wavelength of 2 pi / 515 had been called harmonic 29516 in degrees)."""
    h = period / (wavelength * unit_size(OTHER_POSITION_UNITS[units.kind]))
    return 1 <= round(h) <= UNIT_HARMONICS and abs(h - round(h)) <= UNIT_TOLERANCE


def _unexplained(wavelength: float, period: float, units, why: str) -> str:
    """What a position-periodic force that no harmonic of the period holds says: where it is a
    harmonic in other units (``_in_other_units``), that unit and the --scale that converts it;
    else the wavelength and ``why``."""
    name = OTHER_POSITION_UNITS[units.kind]
    size = unit_size(name)
    h = period / (wavelength * size)
    if _in_other_units(wavelength, period, units):
        return (f"the log's position force repeats every {wavelength:.6g} {units.position}: "
                f"harmonic {round(h)} of the period {period:.6g} if x is in {name}. Is x in {name}? "
                f"--scale x={size:.6g} converts it")
    return (f"the log holds a position-periodic force of wavelength {wavelength:.6g} "
            f"{units.position} that no harmonic of the period {period:.6g} holds: {why}")


#: The multiples of a linear axis's --pitch whose maps are checked for a force it cannot hold.
LONGER_PERIODS = (2, 3)


def check_period(fit: CoggingFit, t, x, force, inertia: Optional[float], units,
                 given: bool) -> None:
    """``DataError`` where the map of the period misses a position force the log holds, at
    least UNEXPLAINED_SHARE of the map's strongest harmonic (any, without a map): a wavelength no
    harmonic of the period holds (``CoggingFit.unexplained_wavelength``) that is one in other
    units (x in degrees or mm), or any such wavelength where the period was ``given`` (--pitch);
    and, on a linear axis with --pitch, harmonics of a multiple of it that none of its own are
    (half the pole pitch given), where the travel holds two of that multiple. A map that
    leaves out such a force is wrong by about its size (a new user's half pole pitch gave a map
    56 % off, with no warning), and the force left out can hide the rest ("none found" on a
    synthetic motor). A period not given (a turn, or found) keeps a map beside the other
    wavelengths with a warning: a drive's loop leaves ripples of its own at a steady speed."""
    left = fit.unexplained_wavelength
    if left is not None and (given or _in_other_units(left, fit.period, units)):
        raise DataError(_unexplained(left, fit.period, units,
                                     "check --pitch (or leave it out for the period the data show)"))
    if units.kind == "rotary" or not given:
        return
    strongest = max(fit.map.amplitude) if fit.map is not None else 0.0
    for m in LONGER_PERIODS:
        longer = m * fit.period
        if np.ptp(x) < FUNDAMENTAL_PERIODS * longer:
            return
        wider = identify_cogging(t, x, force, longer, inertia=inertia).map
        missed = [] if wider is None else [
            (h, amp) for h, amp in zip(wider.harmonics, wider.amplitude)
            if h % m and amp >= UNEXPLAINED_SHARE * strongest]
        if missed:
            named = ", ".join(f"{h} ({amp:.3g} {units.force})" for h, amp in missed)
            raise DataError(f"the log's position force repeats every {longer:.6g} {units.position}, "
                            f"{m} times --pitch {fit.period:.6g}: its harmonic{'s' * (len(missed) > 1)} "
                            f"{named} of that period {'are' if len(missed) > 1 else 'is'} no harmonic "
                            f"of --pitch; give --pitch {longer:.6g} (or leave it out for the period "
                            "the data show)")


def log_position(columns: Mapping[str, np.ndarray]) -> np.ndarray:
    """The position of a log: ``x``, or the velocity ``v`` integrated over ``t`` (trapezoids)."""
    if "x" in columns:
        return np.asarray(columns["x"], dtype=float)
    return cumulative_trapezoid(np.asarray(columns["v"], dtype=float),
                                np.asarray(columns["t"], dtype=float), initial=0.0)


def less_position_force(columns: Mapping[str, np.ndarray], report: FitReport,
                        train_friction: Callable[[Mapping[str, np.ndarray]], FitReport]) -> FitReport:
    """``report`` (the default fit of a motion log) trained again on the log less the position
    force it holds: the cogging map (``fit.cogging``) of the force less the model's friction and
    the identified mass's m a, its force taken out, and the map kept in the model. A log whose
    residual holds no map, or that cannot show one (too little travel or motion), or whose
    training again fails, gives ``report`` as it is. ``train_friction`` fits columns whose
    drive force is ``force`` (no current). Without it, the cogging's ripple at slow passes that
    cover a fraction of its period reads as friction, and a change of the cogging as a change
    of the friction."""
    ident = report.identification
    if ident is None or "t" not in columns:
        return report
    constant = ident.force_constant[0] if ident.force_constant else None
    if "force" not in columns and constant is None:
        return report
    force = log_force(columns, constant)
    t, x = np.asarray(columns["t"], dtype=float), log_position(columns)
    v = np.asarray(columns["v"], dtype=float) if "v" in columns else np.gradient(x, t)
    try:
        fit = identify_cogging(t, x, force - report.model.force_with_offset(v), inertia=ident.body.mass)
    except DataError:
        return report
    if fit.map is None:
        return report
    cleaned = {k: c for k, c in columns.items() if k != "i"}
    cleaned["force"] = force - fit.map.force(x)
    try:
        again = train_friction(cleaned)
    except (DataError, ModelError):
        return report
    model = recording_force_constant(again.model, columns, constant)
    return replace(again, model=replace(model, cogging_map=fit.map))


def _inertia_recorded(model: FrictionModel, text: str, was: str, axis: dict,
                      line: Callable[[str], str]) -> Tuple[FrictionModel, str]:
    """``model`` with ``axis`` written into its axis record and its report ``text`` with the
    inertia line rewritten by ``line``, where the friction fit recorded its inertia as ``was``
    (``mass_from``); both as they are otherwise."""
    record = model.training.get("axis")
    if record is None or record.get("mass_from") != was:
        return model, text
    lines = [line(row) if row.startswith(("inertia ", "mass ")) else row for row in text.splitlines()]
    return (replace(model, training={**model.training, "axis": {**record, **axis}}),
            "\n".join(lines))


def recording_force_constant(model: FrictionModel, columns: Mapping[str, np.ndarray],
                             force_constant: Optional[float]) -> FrictionModel:
    """``model`` whose axis record holds the force constant that made the log's current a force
    (the friction was trained on that force, which no longer says it); as it is otherwise."""
    axis = model.training.get("axis")
    if axis is None or force_constant is None or "i" not in columns or axis["force_constant"]:
        return model
    return replace(model, training={**model.training,
                                    "axis": {**axis, "force_constant": float(force_constant)}})
