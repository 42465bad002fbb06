"""The named effects of the axis's mechanics rather than its friction: a constant load, and a
mass or force constant other than the nominal one [C1]; each one small class of the ``Effect``
contract (``base``). Forces periodic in position (cogging) are in ``position_series``."""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar, Tuple

import numpy as np

from ..c_literal import c_float
from .base import Effect
from .fitting import fit_linear


@dataclass(frozen=True)
class ConstantLoad(Effect):
    """Gravity or another constant external force (positive: opposes positive motion).

    Parameters
    ----------
    load : float
        The force (N).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), t=np.array([0.0, 1.0]), x=np.array([0.0, 0.25]),
    ...               v=np.array([0.1, -0.1]), a=np.array([2.0, 2.0]), i=np.array([1.0, 1.0]),
    ...               sample_time=1.0)
    >>> from fricgen.effects import ConstantLoad
    >>> ConstantLoad(load=5.0).force(sig).tolist()
    [5.0, 5.0]
    """

    load: float
    name: ClassVar[str] = "constant_load"
    in_xv: ClassVar[bool] = True
    acts_at_rest: ClassVar[bool] = True

    def force(self, sig):
        return np.full(np.shape(sig.v if sig.v is not None else sig.x), self.load)

    def linear(self, sig):
        return np.ones((np.size(sig.v), 1)), np.array([self.load])

    def with_coefficients(self, coef):
        return replace(self, load=float(coef[0]))

    @classmethod
    def fit(cls, problem, rows):
        return fit_linear(cls(load=0.0), problem, rows)

    def c_expr(self):
        return c_float(self.load)

    def force_f32(self, v, x, base):
        return np.full(np.shape(v), np.float32(self.load), dtype=np.float32)


@dataclass(frozen=True)
class InertiaMismatch(Effect):
    """The true mass differs from the nominal one: (m - m_nominal) dv/dt.

    Parameters
    ----------
    mass : float
        The true m (kg), > 0.
    nominal_mass : float
        The mass the model assumed (kg), > 0; held fixed by the fit.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), t=np.array([0.0, 1.0]), x=np.array([0.0, 0.25]),
    ...               v=np.array([0.1, -0.1]), a=np.array([2.0, 2.0]), i=np.array([1.0, 1.0]),
    ...               sample_time=1.0)
    >>> from fricgen.effects import InertiaMismatch
    >>> InertiaMismatch(mass=2.5, nominal_mass=2.0).force(sig).tolist()    # 0.5 kg x 2 m/s^2
    [1.0, 1.0]
    """

    mass: float
    nominal_mass: float
    name: ClassVar[str] = "inertia_mismatch"
    positive: ClassVar[Tuple[str, ...]] = ("mass", "nominal_mass")
    nominal_of: ClassVar[Tuple[Tuple[str, str], ...]] = (("mass", "nominal_mass"),)
    fixed: ClassVar[Tuple[str, ...]] = ("nominal_mass",)
    via_dynamics: ClassVar[bool] = True

    @property
    def mass_delta(self):
        return self.mass - self.nominal_mass

    def for_log(self, mass, force_constant, t_start):
        """The carried mass is the axis' mass, whatever mass is given now."""
        return replace(self, nominal_mass=float(mass))

    def force(self, sig):
        return self.mass_delta * np.asarray(sig.a)

    def linear(self, sig):
        return np.asarray(sig.a, dtype=float)[:, None], np.array([self.mass_delta])

    def with_coefficients(self, coef):
        m = self.nominal_mass
        return replace(self, mass=float(max(m + coef[0], 1e-3 * m)))

    @classmethod
    def fit(cls, problem, rows):
        return fit_linear(cls(mass=problem.mass, nominal_mass=problem.mass), problem, rows)


@dataclass(frozen=True)
class ForceConstantMismatch(Effect):
    """The true force constant differs from the nominal one: -(phi - phi_nominal) i.

    Parameters
    ----------
    force_constant : float
        The true phi (N/A), > 0.
    nominal_force_constant : float
        The phi the model assumed (N/A), > 0; held fixed by the fit.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), t=np.array([0.0, 1.0]), x=np.array([0.0, 0.25]),
    ...               v=np.array([0.1, -0.1]), a=np.array([2.0, 2.0]), i=np.array([1.0, 1.0]),
    ...               sample_time=1.0)
    >>> from fricgen.effects import ForceConstantMismatch
    >>> ForceConstantMismatch(force_constant=19.0, nominal_force_constant=20.0).force(sig).tolist()
    [1.0, 1.0]
    """

    force_constant: float
    nominal_force_constant: float
    name: ClassVar[str] = "force_constant_mismatch"
    positive: ClassVar[Tuple[str, ...]] = ("force_constant", "nominal_force_constant")
    nominal_of: ClassVar[Tuple[Tuple[str, str], ...]] = (("force_constant", "nominal_force_constant"),)
    fixed: ClassVar[Tuple[str, ...]] = ("nominal_force_constant",)
    via_dynamics: ClassVar[bool] = True

    @property
    def force_constant_delta(self):
        return self.force_constant - self.nominal_force_constant

    def for_log(self, mass, force_constant, t_start):
        """The carried force constant is the axis', whatever force constant is given now."""
        return replace(self, nominal_force_constant=float(force_constant))

    def force(self, sig):
        return -self.force_constant_delta * np.asarray(sig.i)

    def linear(self, sig):
        return -np.asarray(sig.i, dtype=float)[:, None], np.array([self.force_constant_delta])

    def with_coefficients(self, coef):
        phi = self.nominal_force_constant
        return replace(self, force_constant=float(max(phi + coef[0], 1e-3 * phi)))

    @classmethod
    def fit(cls, problem, rows):
        phi = problem.force_constant
        return fit_linear(cls(force_constant=phi, nominal_force_constant=phi), problem, rows)
