"""The named effects of the axis's mechanics rather than its friction: a force periodic in
position (cogging, ripple), a constant load, and a mass or force constant other than the nominal
one [C1]; each one small class of the ``Effect`` contract (``base``)."""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar, Tuple

import numpy as np

from ..c_literal import c_float
from .base import Effect
from .fitting import fit_linear, lstsq, refine


@dataclass(frozen=True)
class PositionRipple(Effect):
    """Cogging / force ripple, periodic in position: A sin(2 pi x / P + phase).

    Parameters
    ----------
    amplitude : float
        A (N).
    period : float
        P (m), > 0.
    phase : float
        Phase (rad).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), t=np.array([0.0, 1.0]), x=np.array([0.0, 0.25]),
    ...               v=np.array([0.1, -0.1]), a=np.array([2.0, 2.0]), i=np.array([1.0, 1.0]),
    ...               sample_time=1.0)
    >>> from fricgen.effects import PositionRipple
    >>> PositionRipple(amplitude=2.0, period=1.0, phase=0.0).force(sig).round(3).tolist()
    [0.0, 2.0]
    """

    amplitude: float
    period: float
    phase: float
    name: ClassVar[str] = "position_ripple"
    in_xv: ClassVar[bool] = True
    acts_at_rest: ClassVar[bool] = True
    positive: ClassVar[Tuple[str, ...]] = ("period",)

    def force(self, sig):
        return self.amplitude * np.sin(2 * np.pi / self.period * np.asarray(sig.x) + self.phase)

    def linear(self, sig):
        k = 2 * np.pi / self.period * np.asarray(sig.x)
        return (np.column_stack([np.sin(k), np.cos(k)]),
                self.amplitude * np.array([math.cos(self.phase), math.sin(self.phase)]))

    def with_coefficients(self, coef):
        a, c = coef
        return replace(self, amplitude=float(math.hypot(a, c)), phase=float(math.atan2(c, a) % (2 * np.pi)))

    @classmethod
    def fit(cls, problem, rows) -> "PositionRipple":
        """Least-squares periodogram over wavenumbers (problem.ripple_bank), refined by Brent."""
        ks, bank = problem.ripple_bank()
        r = problem.target[rows]
        B = bank[:, rows, :]                                   # (K, n, 2)
        G = np.einsum("kni,knj->kij", B, B)
        b = np.einsum("kni,n->ki", B, r)
        coef = np.linalg.solve(G + 1e-12 * np.eye(2), b[..., None])[..., 0]
        gain = np.einsum("ki,ki->k", coef, b)                  # RSS reduction per wavenumber
        j = int(np.argmax(gain))

        x = problem.signals.x

        def waves(k):
            return lambda i: np.stack([np.sin(k * x[i]), np.cos(k * x[i])], axis=-1)

        def rss(k):
            return lstsq(problem.at_rows(waves(k), rows), r)[1]

        lo, hi = ks[max(j - 1, 0)], ks[min(j + 1, ks.size - 1)]
        k = refine(rss, lo, hi)
        (a, c), _ = lstsq(problem.at_rows(waves(k), rows), r)
        return cls(amplitude=float(math.hypot(a, c)), period=float(2 * np.pi / k),
                   phase=float(math.atan2(c, a) % (2 * np.pi)))

    def c_expr(self):
        return (f"{c_float(self.amplitude)} * sinf(({c_float(2 * np.pi / self.period)} * x) + "
                f"{c_float(self.phase)})")

    def force_f32(self, v, x, base):
        f32 = np.float32
        arg = f32(2 * np.pi / self.period) * x + f32(self.phase)
        return f32(self.amplitude) * np.sin(arg.astype(np.float64)).astype(f32)


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
