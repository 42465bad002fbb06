"""What inverse dynamics [C1] found in a motion log (``data.inverse_dynamics``): the friction
samples F = f - m dv/dt at the rows where the axis moves steadily, those near its reversals, the
rigid body (mass, constant force, the runs' offsets, a link's weight) and how they were
obtained, with the report's lines on them."""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Dict, Optional, Tuple

import numpy as np

from ..units import LINEAR
from .idim import SAMPLES_PER_PARAMETER, RigidBody
from .sweep import Sweep

#: Where a constant force beside the friction is compensated: the report's words.
COMPENSATED = "eval and the C's NAME_force_with_offset add it"


@dataclass(frozen=True)
class Identification:
    """Friction samples of a log and how they were obtained."""

    sweep: Sweep            # (v, F) at the rows kept
    n_rows: int             # rows of the log
    window: int             # Savitzky-Golay window, samples
    sample_time: float      # s
    velocity_noise: float   # m/s, standard deviation
    independent: float      # rows kept times the filter's variance ratio
    body: RigidBody         # mass and constant force, identified or given
    #: (K, its standard error) of a current log: the error None when K was given
    force_constant: Optional[Tuple[float, Optional[float]]] = None
    #: The offset is a load beside the friction (``as_load``), not held in asymmetric curves:
    #: "" (it is not), "push" (held there it would make one push the axis) or "textbook" (the
    #: per-direction textbook law leaves it out, as every textbook law does)
    load: str = ""
    #: The log's jittering time stamps were resampled onto a uniform grid
    resampled: bool = False
    #: The window (samples) at which the mass and offset were identified, where it is not
    #: ``window``: the one whose dv/dt explains the force best (``explaining_window``)
    body_window: Optional[int] = None
    #: The operating point at the rows of ``sweep`` (``load``, ``temperature``; smoothed as v),
    #: for a log with those columns
    conditions: Dict[str, np.ndarray] = field(default_factory=dict)
    #: The runs the log was concatenated from (``motionlog.resampled_runs``)
    n_runs: int = 1
    #: Without ``gravity``: the textbook law's RMS residual without and with a weight of the
    #: position where it explains much of the force (``log_columns.check_log_columns``), else None
    weight: Optional[Tuple[float, float]] = None
    #: (v, F) at the moving rows within half a window of a reversal or a stop, which ``sweep``
    #: leaves out: F from the raw force less m dv/dt (smoothed, the force there would mix the two
    #: directions' friction). A Coulomb + viscous law's final fit adds them (``fit.law_choice``), as the
    #: spreadsheet's least squares takes every moving row: without them a UR10e joint's law,
    #: the same as that fit's, was 1.13 times its error on the joint's held-out sweep
    reversals: Optional[Sweep] = None
    #: dv/dt was the log's own acceleration column (a, ddq), not the derivative of v
    acceleration_given: bool = False
    #: The RMS residuals of the force with the log's acceleration column and with dv/dt of v,
    #: where the column explained it clearly less well and was not used
    acceleration_unused: Optional[Tuple[float, float]] = None

    @property
    def n_kept(self) -> int:
        return len(self.sweep)

    @property
    def velocity_range(self) -> Tuple[float, float]:
        return float(self.sweep.v.min()), float(self.sweep.v.max())

    def summary(self, units=LINEAR) -> str:
        """The lines ``fricgen train`` prints about the log, in ``units`` (``fricgen.units``)."""
        lo, hi = self.velocity_range
        moving = np.abs(self.sweep.v)
        return "\n".join([
            f"log       {self.n_rows} rows at {1 / self.sample_time:.6g} Hz"
            + (f" in {self.n_runs} runs (t restarts or pauses between them; no window spans "
               "two)" if self.n_runs > 1 else "")
            + (" (resampled from jittering time stamps)" if self.resampled else "")
            + f"; {self.n_kept} kept where the axis moves (about {self.independent:.0f} "
            "independent samples)",
            f"smoothing zero-phase Savitzky-Golay, cubic, {self.window} samples "
            f"({self.window * self.sample_time * 1e3:.3g} ms), from velocity noise "
            f"{self.velocity_noise:.3g} {units.speed}"
            + ("" if self.body_window in (None, self.window) else
               f"; the {units.inertia_name} at {self.body_window} samples, "
               "the window whose dv/dt explains the force best"),
            f"velocity  {lo:.4g} to {hi:.4g} {units.speed}; speeds {moving.min():.3g} to "
            f"{moving.max():.3g} {units.speed}",
        ] + self.body_lines(units))

    def body_lines(self, units=LINEAR) -> list:
        """The mass and the constant force, each with its standard error or its source."""
        b = self.body
        mass = (f"{b.mass:.5g} +- {b.mass_se:.2g} {units.mass} identified by inverse dynamics"
                + (" against the log's acceleration column" if self.acceleration_given else "")
                if b.mass_identified else f"{b.mass:.5g} {units.mass} as given")
        if b.mass_estimate is not None:
            mass = (f"0 {units.mass}: the log's accelerations give {b.mass_estimate:.3g} +- "
                    f"{b.mass_se:.2g} {units.mass}, below zero while the friction opposes the "
                    "motion: a residual inertia (was a rigid-body model removed from the force "
                    "already?), taken out of the friction samples and recorded as no mass; pass "
                    "--mass to set it")
        elif not b.mass_determined:
            mass = (f"not determined by the log's accelerations ({b.mass:.3g} +- {b.mass_se:.2g} "
                    f"{units.mass}, the inertia force within its noise): pass --mass, or log motion that "
                    "accelerates and brakes")
        lines = [f"{units.inertia_name:10s}{mass}"]
        if (doubt := self.acceleration_doubt(units)) is not None:
            lines.append(f"          {doubt}")
        lines += [f"          {doubt}" for doubt in b.doubts(units.mass)]
        if self.weight is not None and units.position == "rad":    # --gravity is a joint's
            without, with_weight = self.weight
            lines.append(f"gravity   not identified, yet a weight G_s sin x + G_c cos x of the position "
                         f"leaves {with_weight:.3g} {units.force} RMS of the force unexplained where "
                         f"the law without it leaves {without:.3g}: a link's weight in the friction "
                         "samples? --gravity identifies it apart")
        if b.gravity is not None:
            (g_s, g_c), (se_s, se_c) = b.gravity, b.gravity_se
            lines.append(f"gravity   G_s sin x + G_c cos x: G_s = {g_s:.5g} +- {se_s:.2g}, G_c = "
                         f"{g_c:.5g} +- {se_c:.2g} {units.force} (amplitude {np.hypot(g_s, g_c):.4g} "
                         f"{units.force}), taken out of the friction samples; compensate it apart")
        if b.run_offsets is not None:
            each = ", ".join(f"run {r + 1} {o:+.4g} +- {e:.2g}" for r, o, e in b.run_offsets)
            own = {b.run_reference, *(r for r, _, _ in b.run_offsets)}
            rest = [str(r + 1) for r in range(self.n_runs) if r not in own]
            lines.append(f"runs      constant force of each run less run {b.run_reference + 1}'s: "
                         f"{each} {units.force}, taken out of the friction samples"
                         + (f"; run{'s' * (len(rest) > 1)} {', '.join(rest)} (one way only, or "
                            f"left out) taken as run {b.run_reference + 1}'s" if rest else ""))
        elif self.n_runs > 1:
            lines.append("runs      one constant force for all runs: fewer than two runs move both "
                         "ways, and a run that moves one way only holds its own offset and its "
                         "friction level as one sum")
        if self.force_constant is not None and self.force_constant[1] is not None:
            k, k_se = self.force_constant
            lines.append(f"{units.effort:10s}constant K = {k:.5g} +- {k_se:.2g} {units.force_constant} from "
                         f"the {units.inertia_name} given (the current determines M/K)")
        return lines

    def acceleration_doubt(self, units=LINEAR) -> Optional[str]:
        """Why the log's acceleration column was not used, or None."""
        if self.acceleration_unused is None:
            return None
        given, own = self.acceleration_unused
        return (f"the log's acceleration column leaves {given:.3g} {units.force} RMS of the {units.effort} "
                f"unexplained where dv/dt of v leaves {own:.3g}: not used (a drive's estimate that "
                "lags, or another signal?)")

    def as_load(self, why: str = "push") -> "Identification":
        """This identification with the offset o a load (gravity, a cable's pull) beside the
        friction: where curves that held it would push the axis (``why`` "push"), or where the
        per-direction textbook law was kept ("textbook"; ``fricgen.train``)."""
        return replace(self, load=why)

    @property
    def offset_in_friction(self) -> float:
        """The offset still in ``friction``: o, or 0 when it is a load taken out (``as_load``)
        or the log does not determine it. A symmetric curve leaves it out."""
        return 0.0 if self.load or self.body.offset is None else self.body.offset

    @property
    def reversal_friction(self) -> Optional[Sweep]:
        """``reversals`` as ``friction`` gives ``sweep`` (``_less_load``)."""
        return None if self.reversals is None else self._less_load(self.reversals)

    @property
    def friction(self) -> Sweep:
        """The samples a friction model is fitted to: ``sweep`` (``_less_load``)."""
        return self._less_load(self.sweep)

    def _less_load(self, samples: Sweep) -> Sweep:
        """``samples`` less the offset when it is a load (``as_load``), else as they are."""
        return Sweep(samples.v, samples.f - self.body.offset) if self.load else samples

    def offset_line(self, asymmetric: bool, units=LINEAR) -> str:
        """The constant force o: beside a symmetric model, held in an asymmetric one, or beside
        it as a load (``as_load``)."""
        if self.body.offset is None:
            return ("offset    not determined: the log moves one way only, where a constant "
                    f"{units.effort} is one with the friction")
        o = f"offset    {self.body.offset:.4g} +- {self.body.offset_se:.2g} {units.force}"
        if self.load == "textbook":     # motion alone does not tell o from friction differing by direction
            return (f"{o}: the even part of the {units.effort}, a constant {units.effort} (a load) and half the difference of the "
                    "directions' Coulomb levels together, which the textbook law's curves leave out, per direction as symmetric "
                    f"({COMPENSATED}). Motion does not tell it from a friction that differs by direction, so no load of its own is "
                    "measured: on an axis without a constant load, each direction's F_c is its curve's plus (v > 0) or less (v < 0) o")
        if self.load:
            return (f"{o}: a load beside the friction (held in the two curves, it would make one "
                    f"of them push the axis; {COMPENSATED})")
        if asymmetric:
            return (f"{o}: the even part of the {units.effort}, held in the two curves (a constant "
                    f"{units.effort} and a friction that differs between the directions are not told apart)")
        return (f"{o}: a constant {units.effort} beside the friction (the even part of the "
                f"{units.effort}, which the symmetric model leaves out; {COMPENSATED})")

    @property
    def parameter_budget(self) -> int:
        """The most friction parameters the log supports: one per SAMPLES_PER_PARAMETER
        independent samples."""
        return int(self.independent // SAMPLES_PER_PARAMETER)
