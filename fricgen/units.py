"""The units an axis speaks: a linear axis in m, m/s, N and kg, a rotary one (a robot joint, a
motor shaft) in rad, rad/s, Nm and kg m^2. fricgen computes in either alike; only the words
differ."""
from __future__ import annotations

from dataclasses import dataclass

from ._validate import in_rotary_axis


@dataclass(frozen=True)
class Units:
    """The unit names of one kind of axis.

    Examples
    --------
    >>> from fricgen.units import units_of
    >>> units_of(True).viscous, units_of(False).mass, units_of(True).effort
    ('Nm s/rad', 'kg', 'torque')
    """

    kind: str
    position: str
    speed: str
    force: str
    viscous: str
    mass: str
    effort: str = "force"

    @property
    def inertia_name(self) -> str:
        """What the moving body's inertia is called: "mass" (linear) or "inertia" (rotary)."""
        return "inertia" if self.kind == "rotary" else "mass"

    @property
    def force_constant(self) -> str:
        """The unit of a force constant, force per ampere: "N/A" or "Nm/A"."""
        return f"{self.force}/A"

    @property
    def per_force_constant(self) -> str:
        """The unit of a mass over a force constant (a current log's M/K): "kg/(N/A)"."""
        return f"{self.mass}/({self.force_constant})"


LINEAR = Units("linear", "m", "m/s", "N", "N s/m", "kg")
ROTARY = Units("rotary", "rad", "rad/s", "Nm", "Nm s/rad", "kg m^2", "torque")


def units_of(rotary: bool) -> Units:
    """ROTARY or LINEAR."""
    return ROTARY if rotary else LINEAR


def axis_units() -> Units:
    """The units of the axis at hand: ROTARY within ``_validate.rotary_axis(True)``, else LINEAR."""
    return units_of(in_rotary_axis())
