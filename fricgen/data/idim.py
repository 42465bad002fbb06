"""The axis's mass and constant force by inverse dynamics (IDIM-LS), jointly with its friction.

[C1] with a constant force o (gravity on an inclined axis, a cable's pull) reads
f = m dv/dt + F(v) + o. Before F is modelled it is stood in for by a flexible basis that is
linear in its coefficients: per direction of motion a Coulomb level, a viscous slope and
Stribeck drops exp(-|v| / v_k) on a log grid of the measured speeds. Ordinary least squares then
gives m with a standard error whose residual variance counts the rows correlated by smoothing
as fewer (``least_squares_errors``).

The offset is the even part of the force: at the mass found, o is fitted beside an odd friction
(the same basis times sgn v). A friction that differs between the directions cannot be told
apart from it on moving rows (1 = [v > 0] + [v < 0]), which the report says.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

from ..errors import DataError
from ..metrics import least_squares_errors
from ..units import axis_units

#: Stribeck drops in the stand-in friction basis, per direction.
STRIBECK_TERMS = 3
#: Columns of the per-direction basis (``friction_basis(v, odd=False)``): a level, a slope and
#: the drops, for each direction.
BASIS_COLUMNS = 2 * (2 + STRIBECK_TERMS)
#: The identified mass must stand this many standard errors above 0.
MASS_SIGMAS = 3.0
#: Independent samples (rows kept times the filter's variance ratio) per fitted parameter.
SAMPLES_PER_PARAMETER = 10
#: The masses identified apart where the axis speeds up and where it brakes disagree when they
#: differ by more than PHASE_SIGMAS standard errors of the difference and PHASE_SHARE of the
#: larger (``RigidBody.phases_disagree``).
PHASE_SIGMAS = 3.0
PHASE_SHARE = 0.1
#: A run's constant force is told from the others' by the friction at the speeds they share:
#: fewer than this share of its samples there, and its standard error understates it.
RUN_SHARE = 0.25


def _apart(pair, mass: float) -> bool:
    """Whether the two (mass, standard error) of ``pair`` differ by more than PHASE_SIGMAS
    standard errors of the difference and PHASE_SHARE of the larger, each a mass (MASS_SIGMAS
    standard errors above 0) with ``mass``, the one of all rows, between them (within
    PHASE_SIGMAS standard errors): fits that part the rows so that their dv/dt is nearly a
    function of v (a speed ramp's phase) leave the mass to the friction curve's misfit, a
    negative mass or two on one side of the whole's (False for None)."""
    if pair is None:
        return False
    (m1, s1), (m2, s2) = sorted(pair)
    gap = m2 - m1
    masses = min(m1 - MASS_SIGMAS * s1, m2 - MASS_SIGMAS * s2) > 0
    between = m1 - PHASE_SIGMAS * s1 <= mass <= m2 + PHASE_SIGMAS * s2
    return (masses and between and gap > PHASE_SIGMAS * float(np.hypot(s1, s2))
            and gap > PHASE_SHARE * m2)


def friction_basis(v: np.ndarray, odd: bool, terms: int = STRIBECK_TERMS) -> np.ndarray:
    """Columns spanning a friction law of v: [1, |v|, exp(-|v| / v_k)] per direction (``odd``
    False), or those of one odd law, times sgn v (``odd`` True). The ``terms`` v_k are
    log-spaced between twice the 2 % and half the 98 % quantile of |v|."""
    speed = np.abs(v)
    lo, hi = np.quantile(speed, [0.02, 0.98])
    grid = np.geomspace(max(2.0 * lo, 1e-12), max(0.5 * hi, 2.0 * lo, 1e-12), terms)
    terms = [np.ones_like(speed), speed] + [np.exp(-speed / g) for g in grid]
    if odd:
        return np.column_stack([np.sign(v) * c for c in terms])
    return np.column_stack([(np.sign(v) == s) * c for s in (1, -1) for c in terms])


@dataclass(frozen=True)
class RigidBody:
    """What inverse dynamics found or was told: m (kg) and o (N), with standard errors (None
    where a value was given, not identified)."""

    mass: float
    mass_se: Optional[float]
    offset: float
    offset_se: float
    #: the least-squares estimate where it fell clearly below 0 (beyond MASS_SIGMAS standard
    #: errors; ``mass`` is then 0): a residual inertia of a force whose inertia model was
    #: removed before, overestimated
    mass_estimate: Optional[float] = None
    #: (G_s, G_c) of a gravity-like force G_s sin x + G_c cos x of the position (``--gravity``)
    #: and their standard errors; None where not asked for
    gravity: Optional[Tuple[float, float]] = None
    gravity_se: Optional[Tuple[float, float]] = None
    #: A log concatenated from runs: of the runs that move both ways (``determined_runs``),
    #: each one's constant force less the first such run's (a sensor zeroed again, another
    #: pose), as (run, offset, standard error) from 0; the other runs are taken to share the
    #: first's. None for one run, or fewer than two runs that move both ways
    run_offsets: Optional[Tuple[Tuple[int, float, float], ...]] = None
    #: ... and that first run (the reference), where there are run offsets
    run_reference: Optional[int] = None
    #: The mass (and its standard error) identified on the rows where the axis speeds up and on
    #: those where it brakes (``phase_masses``); None where given or not determined
    phase_masses: Optional[Tuple[Tuple[float, float], Tuple[float, float]]] = None
    #: ... and with the rows that do neither clearly in both (``phase_masses(pinned=True)``)
    pinned_phase_masses: Optional[Tuple[Tuple[float, float], Tuple[float, float]]] = None
    #: The least and the largest mass (and its standard error) of the smoothing windows whose
    #: dv/dt explains the force about as well as the best one's (``explaining_window``); None
    #: where the window was given or the mass not determined
    window_masses: Optional[Tuple[Tuple[float, float], Tuple[float, float]]] = None
    #: Where the mass was given: the mass (and its standard error) the log's accelerations
    #: determine (``inverse_dynamics.identify_friction``), else None
    log_mass: Optional[Tuple[float, float]] = None
    #: With run offsets: each such run's share of samples at speeds the others move at too
    #: (``shared_speeds``)
    run_shares: Optional[Tuple[Tuple[int, float], ...]] = None
    #: Where a mass not identified came from: "given" (--mass), or "cogging" (the ripple of a
    #: cogging calibration's map, ``training.with_cogging``), which the doubts name
    mass_source: str = "given"

    def given_mass_disagrees(self) -> bool:
        """Whether the mass given and the one the log's accelerations determine (``log_mass``)
        differ by more than PHASE_SIGMAS standard errors of the latter and PHASE_SHARE of the
        larger: a mass given in other units (g, or a gearbox's ratio squared left out)."""
        if self.log_mass is None:
            return False
        found, se = self.log_mass
        gap = abs(found - self.mass)
        return gap > PHASE_SIGMAS * se and gap > PHASE_SHARE * max(found, self.mass)

    def phases_disagree(self) -> bool:
        """Whether speeding up and braking give masses apart beyond their noise (PHASE_SIGMAS,
        PHASE_SHARE), fitted on each phase's rows alone and with the rows that do neither
        (``phase_masses``): the force differs between the two at the same speed, friction
        with memory (the bristles' build-up after each start, a frictional lag) that a static
        curve leaves out, and the mass of both together is off by about the difference. Each
        fit alone misleads on a motion of its own: a trapezoidal move's phase rows hold
        a = A sgn v, which the first cannot tell from Coulomb friction, and a sweep's short
        speed steps leave the second the friction curve's misfit at the steps."""
        return all(_apart(pair, self.mass) for pair in (self.phase_masses, self.pinned_phase_masses))

    def windows_disagree(self) -> bool:
        """Whether smoothing windows that explain the force about equally well give masses
        apart beyond their noise (``window_masses``, PHASE_SIGMAS, PHASE_SHARE): the fast part
        of the force follows dv/dt with another mass than its slow part, as where bristles
        carry the force after each start; which window fits best is then chance, and its mass
        of small standard error wrong."""
        return _apart(self.window_masses, self.mass)

    def doubts(self, unit: str) -> List[str]:
        """One sentence for each reason the identified mass is uncertain beyond its standard
        error (``phases_disagree``, ``windows_disagree``; ``unit``: the mass's)."""
        memory = ("friction with memory (pre-sliding after each start, a frictional lag) or "
                  "forces a curve of v leaves out (a friction that varies with the position, "
                  "which fricgen diagnose names), so the mass is uncertain by about the "
                  "difference; train --dynamic models pre-sliding, --mass sets the mass")
        out = []
        if self.given_mass_disagrees():
            found, se = self.log_mass
            out.append(f"the log's accelerations give {found:.4g} +- {se:.2g} {unit}, "
                       f"{found / self.mass:.3g} times the {self.mass:.4g} {unit} " + (
                           "given, which is used: is the mass given in other units, or the log "
                           "of another axis?" if self.mass_source == "given" else
                           "the cogging map's ripple gave, which is used: the inertia is "
                           "uncertain by about the difference (give --mass)"))
        if self.phases_disagree():
            (m1, s1), (m2, s2) = self.phase_masses
            out.append(f"speeding up gives {m1:.4g} +- {s1:.2g} {unit} and braking {m2:.4g} +- "
                       f"{s2:.2g} {unit}: the force differs between the two at the same speed: "
                       + memory)
        if self.windows_disagree():
            (m1, s1), (m2, s2) = self.window_masses
            out.append(f"smoothing windows that explain the force about equally well give "
                       f"{m1:.4g} +- {s1:.2g} {unit} and {m2:.4g} +- {s2:.2g} {unit}: the force "
                       "follows dv/dt with another mass at short time scales than at long "
                       "ones: " + memory)
        return out

    def runs_doubt(self) -> Optional[str]:
        """Why run offsets are less sure than their standard errors say: the runs that share
        fewer than RUN_SHARE of their samples' speeds with the others (``run_shares``: a new
        user's run of fast speeds beside one of slow speeds had its offset 15 standard errors
        off, and one more Stribeck term per direction moved it by 20 times the offset); None
        where every run shares them."""
        few = [(r, share) for r, share in self.run_shares or () if share < RUN_SHARE]
        if not few:
            return None
        said = " and ".join(f"run {r + 1}{' has' if k == 0 else ''} {100 * share:.0f} %"
                            for k, (r, share) in enumerate(few))
        return (f"the runs' constant forces are told apart only by the shape of the friction curve "
                f"between their speeds, less surely than their +- say: {said} of "
                f"{'its' if len(few) == 1 else 'their'} samples at speeds another run moves at too "
                "(log runs that share speeds)")

    def run_force(self, runs: Optional[np.ndarray]) -> np.ndarray:
        """The constant force of each row's run less the reference run's (0 without run
        offsets, and for the runs without one of their own)."""
        if runs is None:
            return np.zeros(())
        runs = np.asarray(runs, dtype=int)
        force = np.zeros(runs.shape)
        for run, offset, _ in self.run_offsets or ():
            force[runs == run] = offset
        return force

    def gravity_force(self, x: Optional[np.ndarray]) -> np.ndarray:
        """G_s sin x + G_c cos x at the positions ``x`` (0 without gravity)."""
        if self.gravity is None or x is None:
            return np.zeros(() if x is None else np.shape(x))
        return gravity_basis(x) @ np.asarray(self.gravity)

    @property
    def inertia(self) -> float:
        """The coefficient of dv/dt in the force: the mass, or the residual inertia."""
        return self.mass if self.mass_estimate is None else self.mass_estimate

    @property
    def mass_identified(self) -> bool:
        return self.mass_se is not None

    @property
    def mass_determined(self) -> bool:
        """Given, or identified at least MASS_SIGMAS standard errors above 0."""
        return self.mass_se is None or self.mass > MASS_SIGMAS * self.mass_se


def gravity_basis(x: np.ndarray) -> np.ndarray:
    """Columns [sin x, cos x] of a joint's gravity torque at its angle x (rad): a link's
    weight acting at a fixed lever, whatever the angle's zero, is G_s sin x + G_c cos x."""
    return np.column_stack([np.sin(x), np.cos(x)])


def determined_runs(v: np.ndarray, runs: Optional[np.ndarray]) -> np.ndarray:
    """The runs whose constant force can be told from the friction: those that move both ways
    (a run in one direction only holds its offset and its friction level as one sum); none
    unless there are two or more of them."""
    if runs is None:
        return np.zeros(0, dtype=int)
    both = np.array([r for r in np.unique(runs) if np.any(v[runs == r] > 0) and np.any(v[runs == r] < 0)],
                    dtype=int)
    return both if both.size >= 2 else np.zeros(0, dtype=int)


def shared_speeds(v: np.ndarray, runs: np.ndarray, determined: np.ndarray) -> Tuple[Tuple[int, float], ...]:
    """For each of the ``determined`` runs, the share of its samples at speeds the others move
    at too (within the 2 to 98 % quantiles of their speeds, the better of the two directions):
    where it is small, a run's constant force is told from theirs only by the shape of the
    friction curve between their speeds (``RigidBody.runs_doubt``)."""
    out = []
    for r in determined:
        mine, others = runs == r, np.isin(runs, determined) & (runs != r)
        share = 0.0
        for side in (v > 0, v < 0):
            own, theirs = np.abs(v[mine & side]), np.abs(v[others & side])
            if own.size and theirs.size:
                lo, hi = np.quantile(theirs, [0.02, 0.98])
                share = max(share, float(np.mean((own >= lo) & (own <= hi))))
        out.append((int(r), share))
    return tuple(out)


def run_basis(runs: np.ndarray, determined: np.ndarray) -> np.ndarray:
    """Indicator columns of the ``determined`` runs after the first: their constant forces
    less the first's (the other runs share the first's)."""
    return np.column_stack([runs == r for r in determined[1:]]).astype(float)


def known_columns(v: np.ndarray, x: Optional[np.ndarray] = None,
                  runs: Optional[np.ndarray] = None) -> Tuple[list, np.ndarray]:
    """The columns of the forces of known shape fitted beside the mass and the friction: a
    gravity force of the positions ``x`` (``gravity_basis``) and the constant forces of the runs
    that determine them (``run_basis``); and those runs (``determined_runs``)."""
    determined = determined_runs(v, runs)
    columns = ([] if x is None else [gravity_basis(x)]) + \
        ([run_basis(runs, determined)] if determined.size else [])
    return columns, determined


def operating_basis(v: np.ndarray, load: Optional[np.ndarray] = None,
                    temperature: Optional[np.ndarray] = None) -> Optional[np.ndarray]:
    """Columns spanning a friction that changes with the operating point, beside
    ``friction_basis``: sgn(v) |L| where the drive drives the load (v L > 0) and where it is
    driven, sgn(v) dT and v dT (dT the temperature less its mean); None without either."""
    columns = []
    if load is not None:
        driving = v * load > 0
        columns += [np.sign(v) * np.abs(load) * driving, np.sign(v) * np.abs(load) * ~driving]
    if temperature is not None:
        dt = temperature - np.mean(temperature)
        columns += [np.sign(v) * dt, v * dt]
    return np.column_stack(columns) if columns else None


def _with(basis: np.ndarray, extra: Optional[np.ndarray]) -> np.ndarray:
    return basis if extra is None else np.column_stack([basis, extra])


def mass_basis(a: np.ndarray, v: np.ndarray, extra: Optional[np.ndarray] = None,
               terms: int = STRIBECK_TERMS) -> np.ndarray:
    """The columns f = m a + F(v) + o is fitted on: dv/dt, then ``friction_basis`` per
    direction (which also absorbs o; ``terms`` Stribeck terms), then ``extra``."""
    return _with(np.column_stack([a, friction_basis(v, odd=False, terms=terms)]), extra)


def identify_mass(a: np.ndarray, v: np.ndarray, force: np.ndarray, independent: float,
                  extra: Optional[np.ndarray] = None):
    """m, its standard error and the raw estimate from f = m a + F(v) + o over moving rows (F
    by ``friction_basis`` per direction, which also absorbs o). Where the accelerations do not
    determine it (within MASS_SIGMAS standard errors of 0: a slow log, or one whose inertia was
    removed before), m is that estimate, at least 0, and ``RigidBody.mass_determined`` says so.
    A clearly negative m is a reversed sign only where the friction fitted beside it pushes
    the axis as well (``DataError``); where that friction opposes the motion it is a residual
    inertia (a rigid-body model removed from the force, overestimated): m is 0, and the
    estimate is taken out of the friction samples (``RigidBody.inertia``). ``extra``:
    columns of a friction that changes with the operating point (``operating_basis``)."""
    basis = mass_basis(a, v, extra)
    coef, se = least_squares_errors(basis, force, independent)
    mass, mass_se = float(coef[0]), float(se[0])
    friction = basis[:, 1:] @ coef[1:]
    if -mass > MASS_SIGMAS * mass_se and np.mean(np.sign(v) * friction) <= 0:
        units = axis_units()
        raise DataError(f"the {units.inertia_name} comes out negative ({mass:.3g} +- {mass_se:.2g} "
                        f"{units.mass} by inverse dynamics): the {units.effort} (or current) and the "
                        "motion have opposite signs; is the sign of the force or of the position reversed?")
    return max(mass, 0.0), mass_se, mass


def phase_masses(a: np.ndarray, v: np.ndarray, force: np.ndarray, independent: float,
                 extra: Optional[np.ndarray] = None, accel_noise: float = 0.0,
                 pinned: bool = False):
    """The mass and its standard error as ``identify_mass`` fits it, on the rows where the
    axis speeds up (a v > 0) and, apart, on those where it brakes (a v < 0): a static friction
    curve gives the two one mass (``RigidBody.phases_disagree``). Only rows where |a| exceeds
    PHASE_SIGMAS times ``accel_noise`` (the SD of dv/dt's noise) count as a phase's: a phase
    chosen by the noise of a would bias the mass of each (an encoder's counts). ``pinned``:
    the rows of smaller |a| count in both phases, pinning the friction. None where either
    phase has fewer independent samples than SAMPLES_PER_PARAMETER per column (of a friction
    curve of twice the Stribeck terms), or where a phase's mass moves by more than PHASE_SIGMAS
    standard errors with those terms: its dv/dt is then nearly a function of v (a sine's, a
    speed ramp's), and the mass follows the friction curve's shape, whatever the friction's
    memory."""
    bases = [mass_basis(a, v, extra, terms) for terms in (STRIBECK_TERMS, 2 * STRIBECK_TERMS)]
    clear = np.abs(a) > PHASE_SIGMAS * accel_noise
    out = []
    for phase in (clear & (a * v > 0), clear & (a * v < 0)):
        if independent * phase.mean() < SAMPLES_PER_PARAMETER * bases[-1].shape[1]:
            return None
        rows = phase | ~clear if pinned else phase
        (coef, se), (richer, _) = (least_squares_errors(basis[rows], force[rows],
                                                        independent * rows.mean())
                                   for basis in bases)
        if abs(richer[0] - coef[0]) > PHASE_SIGMAS * se[0]:
            return None
        out.append((float(coef[0]), float(se[0])))
    return tuple(out)


def identify_offset(a: np.ndarray, v: np.ndarray, force: np.ndarray, mass: float,
                    independent: float, extra: Optional[np.ndarray] = None):
    """o and its standard error from f - m a = o + F(v), F odd (``friction_basis``; ``extra``
    as ``identify_mass``)."""
    basis = _with(np.column_stack([np.ones_like(v), friction_basis(v, odd=True)]), extra)
    coef, se = least_squares_errors(basis, force - mass * a, independent)
    return float(coef[0]), float(se[0])


def identify_rigid_body(a: np.ndarray, v: np.ndarray, force: np.ndarray, independent: float,
                        mass: Optional[float] = None, extra: Optional[np.ndarray] = None,
                        x: Optional[np.ndarray] = None,
                        runs: Optional[np.ndarray] = None,
                        accel_noise: Optional[float] = None) -> RigidBody:
    """The mass (unless given) and the offset of the axis from smoothed dv/dt, v and force at
    rows where it moves (``extra`` as ``identify_mass``); with the positions ``x``, a gravity
    force G_s sin x + G_c cos x beside them (``gravity_basis``); with the run of each row
    (``runs``, a log concatenated from runs), each later run's constant force less the first's,
    where the runs determine them (``determined_runs``). With ``accel_noise`` (the SD of the
    noise of dv/dt), the mass of each phase as well (``phase_masses``)."""
    gravity = gravity_se = run_offsets = None
    known, determined = known_columns(v, x, runs)
    if known:
        extra = _with(np.column_stack(known), extra)
    mass_se = estimate = None
    if mass is None:
        mass, mass_se, estimate = identify_mass(a, v, force, independent, extra)
    residual = estimate if estimate is not None and -estimate > MASS_SIGMAS * mass_se else None
    offset = offset_se = None
    if np.any(v > 0) and np.any(v < 0):
        offset, offset_se = identify_offset(a, v, force, mass if residual is None else residual,
                                            independent, extra)
    if known:                               # at the mass found, beside a per-direction friction
        basis = _with(friction_basis(v, odd=False), extra)
        coef, se = least_squares_errors(basis, force - (mass if residual is None else residual) * a,
                                        independent)
        at = BASIS_COLUMNS
        if x is not None:
            gravity, gravity_se = (float(coef[at]), float(coef[at + 1])), (float(se[at]), float(se[at + 1]))
            at += 2
        if determined.size:
            run_offsets = tuple((int(r), float(c), float(e)) for r, c, e in
                                zip(determined[1:], coef[at:], se[at:]))
    phases = pinned = None
    if accel_noise is not None and mass_se is not None and mass > MASS_SIGMAS * mass_se:
        phases, pinned = (phase_masses(a, v, force, independent, extra, accel_noise, pin)
                          for pin in (False, True))
    return RigidBody(float(mass), mass_se, offset, offset_se, residual, gravity, gravity_se,
                     run_offsets, int(determined[0]) if determined.size else None, phases, pinned,
                     run_shares=shared_speeds(v, runs, determined) if run_offsets else None)
