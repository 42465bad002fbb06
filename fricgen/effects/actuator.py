"""The named effect of the actuator rather than of the mechanics: a force constant that falls
as the current grows (magnetic saturation of the motor), one small class of the ``Effect``
contract (``base``).

The motor's force is phi i (1 - d (i / i_pk)^2) instead of the phi i of [C1], so the residual
holds phi d i^3 / i_pk^2: d is the fraction by which the force constant has fallen at i_pk,
the 99th percentile of |i| on the log it is fitted on. The force is linear in d. It is a
function of the current, not of (v, x): the simulations subtract it from the motor's force
(``via_current``), and ``emit`` lists it among the effects not in C.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar, Tuple

import numpy as np

from .base import Effect
from .fitting import fit_linear

#: The largest fall of the force constant at the log's peak current read as saturation: beyond
#: it the motor would deliver less force at a larger current, which no drive is rated into.
MAX_DROOP = 0.5


@dataclass(frozen=True)
class ActuatorSaturation(Effect):
    """The force constant falls with the current: phi d i^3 / i_pk^2 less force than phi i.

    Parameters
    ----------
    droop : float
        d, the fraction by which the force constant has fallen at ``peak_current``, in
        [0, ``MAX_DROOP``] for a saturation (a negative fit, a force constant growing with the
        current, is refused by ``implausible``).
    peak_current : float
        i_pk (A), > 0: the 99th percentile of |i| on the log fitted; held fixed by the fit.
    nominal_force_constant : float
        phi (N/A), > 0; held fixed by the fit.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import ActuatorSaturation, Signals
    >>> sig = Signals(preset("paper3"), t=np.zeros(2), x=np.zeros(2), v=np.array([0.1, -0.1]),
    ...               a=np.zeros(2), i=np.array([2.0, -1.0]), sample_time=1.0)
    >>> ActuatorSaturation(droop=0.1, peak_current=2.0, nominal_force_constant=20.0).force(sig).tolist()
    [4.0, -0.5]
    """

    droop: float
    peak_current: float
    nominal_force_constant: float
    name: ClassVar[str] = "actuator_saturation"
    positive: ClassVar[Tuple[str, ...]] = ("peak_current", "nominal_force_constant")
    fixed: ClassVar[Tuple[str, ...]] = ("peak_current", "nominal_force_constant")
    via_current: ClassVar[bool] = True

    def for_log(self, mass, force_constant, t_start):
        """The same saturation of the axis' current, with the force constant given now."""
        return replace(self, nominal_force_constant=float(force_constant))

    def _cube(self, i) -> np.ndarray:
        i = np.asarray(i, dtype=float)
        return self.nominal_force_constant * i ** 3 / self.peak_current ** 2

    def force(self, sig):
        return self.droop * self._cube(sig.i)

    def linear(self, sig):
        return self._cube(sig.i)[:, None], np.array([self.droop])

    def with_coefficients(self, coef):
        return replace(self, droop=float(coef[0]))

    def mismatch(self):
        """The fall of the force constant at the peak current, |d|: a force-constant error
        where the current is largest."""
        return abs(self.droop)

    def limits(self):
        return {"droop": (0.0, MAX_DROOP), **super().limits()}

    def implausible(self):
        if self.droop < 0:
            return (f"the force constant grows with the current ({-self.droop:.1%} at "
                    f"{self.peak_current:.3g} A): not a saturation")
        if self.droop > MAX_DROOP:
            return (f"the force constant falls by {self.droop:.0%} at {self.peak_current:.3g} A, "
                    f"beyond the {MAX_DROOP:.0%} read as saturation")
        return ""

    @classmethod
    def fit(cls, problem, rows):
        i = np.asarray(problem.signals.i, dtype=float)
        peak = float(np.quantile(np.abs(i), 0.99)) or float(np.max(np.abs(i))) or 1.0
        return fit_linear(cls(droop=0.0, peak_current=peak,
                              nominal_force_constant=problem.force_constant), problem, rows)
