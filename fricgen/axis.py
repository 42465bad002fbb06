"""The axis record of model.json (``training.axis``): what training identified or was told
about the axis that produced the data, besides its friction.

    phi i = m v' + F(v) + offset            ([C1], with a constant force)

``mass`` (kg) and ``offset`` (N, the constant part of the drive force, as IDIM-LS writes it:
the drive holds -offset of gravity on an inclined axis, or of a cable's pull) come with their standard errors when training identified
them from a motion log; ``force_constant`` phi (N/A) is what training was told (null when the
log held a force column); ``speed_min`` and ``speed_max`` (m/s) bound |v| of the training data.
A sweep gives no mass, force constant or offset (null). The record does not take part in the
force: ``FrictionModel.model_hash`` ignores it, and ``FrictionModel.axis_hash`` covers it (a load
warns when a hand edit changed it).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any, Optional

from ._validate import ACCEPT_UNUSUAL, PHYSICAL, in_rotary_axis, json_number, physical_problem
from .errors import ModelError

#: Where the mass came from: identified from the data, or given by ``--mass``.
MASS_SOURCES = ("data", "option", "cogging")
#: What each source says of the mass.
MASS_FROM = {"data": "identified from the data", "option": "given to train by --mass",
             "cogging": "identified from the cogging map's ripple"}
#: The record's keys, every one required (a value may be null where the field says so).
FIELDS = ("mass", "mass_se", "mass_from", "force_constant", "offset", "offset_se",
          "speed_min", "speed_max")
_WHERE = "training.axis"


def _optional(d: dict, key: str, positive: bool = False, nonnegative: bool = False) -> Optional[float]:
    """``d[key]``: null, or a finite number (> 0 with ``positive``, >= 0 with ``nonnegative``)."""
    if d.get(key, 0) is None:
        return None
    value = json_number(d, key, _WHERE, positive=positive)
    if nonnegative and value < 0:
        raise ModelError(f"{_WHERE}.{key} must be >= 0, got {value}")
    return value


@dataclass(frozen=True)
class Axis:
    """The axis of the training data (``training.axis`` of model.json); see the module."""

    speed_min: float
    speed_max: float
    mass: Optional[float] = None
    mass_se: Optional[float] = None
    mass_from: Optional[str] = None
    force_constant: Optional[float] = None
    offset: Optional[float] = None
    offset_se: Optional[float] = None

    def mass_text(self, unit: str = "kg") -> str:
        """``m = 95.1 kg (identified from the data)`` or ``(given by --mass)``, the mass in
        ``unit`` (kg m^2 on a rotary axis); '' without mass."""
        if self.mass is None:
            return ""
        return f"m = {self.mass:.4g} {unit} ({MASS_FROM[self.mass_from]})"

    def to_dict(self) -> dict:
        d = asdict(self)
        return {key: d[key] for key in FIELDS}

    @classmethod
    def from_dict(cls, d: Any, physical: bool = True) -> "Axis":
        """The validated record; ``ModelError`` naming the field otherwise. With ``physical``
        (a model trained without ``--accept-unusual``), the mass, the offset and the speeds must
        lie within the range of a real axis (``PHYSICAL``): a hand-edited 1e9 kg or 50 m/s would
        set the plant of ``simulate`` and the fixed-point range of ``emit``."""
        if not isinstance(d, dict):
            raise ModelError(f"{_WHERE} must be an object, got {type(d).__name__}")
        unknown = sorted(set(d) - set(FIELDS))
        if unknown:
            raise ModelError(f"unknown field '{_WHERE}.{unknown[0]}'"[:200])
        for key in FIELDS:
            if key not in d:
                raise ModelError(f"{_WHERE}: missing field {key!r}")
        mass = _optional(d, "mass", positive=True)
        mass_se = _optional(d, "mass_se", nonnegative=True)
        mass_from = d["mass_from"]
        if mass_from is not None and mass_from not in MASS_SOURCES:
            raise ModelError(f"{_WHERE}.mass_from must be one of {list(MASS_SOURCES)} or null, "
                             f"got {mass_from!r}"[:200])
        if (mass is None) != (mass_from is None):
            raise ModelError(f"{_WHERE}.mass_from must be null exactly when mass is null, got "
                             f"mass {mass!r} and mass_from {mass_from!r}"[:200])
        if mass_se is not None and mass_from != "data":
            raise ModelError(f"{_WHERE}.mass_se must be null unless the mass was identified "
                             f"(mass_from 'data'), got {mass_se!r}")
        force_constant = _optional(d, "force_constant", positive=True)
        offset = _optional(d, "offset")
        offset_se = _optional(d, "offset_se", nonnegative=True)
        if offset is None and offset_se is not None:
            raise ModelError(f"{_WHERE}.offset_se must be null when offset is null, got {offset_se!r}")
        speed_min = json_number(d, "speed_min", _WHERE)
        if speed_min < 0:
            raise ModelError(f"{_WHERE}.speed_min must be >= 0, got {speed_min}")
        speed_max = json_number(d, "speed_max", _WHERE, positive=True)
        if speed_max < speed_min:
            raise ModelError(f"{_WHERE}.speed_max ({speed_max:g} m/s) must be >= speed_min "
                             f"({speed_min:g} m/s)")
        if physical:        # an offset may be 0: only its upper bound
            problems = [mass is not None and physical_problem("mass", f"{_WHERE}.mass", mass),
                        physical_problem("speed", f"{_WHERE}.speed_max", speed_max),
                        offset is not None and abs(offset) > PHYSICAL["force"][1]
                        and physical_problem("force", f"{_WHERE}.offset", offset)]
            problem = next(filter(None, problems), "")
            if problem and problems[0] and mass < PHYSICAL["mass"][0] and not in_rotary_axis():
                problem += " (a joint's or a shaft's inertia in kg m^2? train it with --rotary)"
            if problem:
                raise ModelError(f"{problem} (an edited record? a model trained with "
                                 f"{ACCEPT_UNUSUAL} may hold it)")
        return cls(speed_min=speed_min, speed_max=speed_max, mass=mass, mass_se=mass_se,
                   mass_from=mass_from, force_constant=force_constant, offset=offset,
                   offset_se=offset_se)


__all__ = ["Axis", "FIELDS", "MASS_FROM", "MASS_SOURCES"]
