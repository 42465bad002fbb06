"""The curve of one direction of [F3] (``Direction``) and its normalization [F9] (``Scaling``):
what a model.json holds for v >= 0 (its top-level ``aim``, ``scaling``, ``viscous``, ``v_sat``)
and, for an asymmetric model, in ``negative``; each validates its own fields and whether the
float32 C can run it as the friction of a real axis."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ._validate import (ACCEPT_UNUSUAL, FLOAT32_MAX, FLOAT32_SCALE, PHYSICAL, float32_overflow, float32_scale,
                        json_number, physical_problem)
from .errors import ModelError
from .networks import network_from_dict
from .units import axis_units

#: The fields of version 2's ``negative`` object, the curve for v < 0.
_DIRECTION_FIELDS = ("aim", "scaling", "viscous", "v_sat")

#: A friction curve must oppose the motion up to this many times v_sat: a negative B may bend
#: the force down beyond v_sat, not through zero.
OPPOSES_MOTION_UP_TO = 10.0
#: ... and on [0, v_sat] it may point with the motion by at most this share of its largest
#: magnitude: a fit may dip a little below zero where the friction is about nil, a hand-edited
#: offset, slope or weight that makes the friction push the axis may not.
PUSHES_AT_MOST = 0.05
#: The largest friction force of a real axis, N (``_validate.PHYSICAL``).
PHYSICAL_FORCE_MAX = PHYSICAL["force"][1]
#: Speeds, in units of v_sat, at which a curve's force is checked (``Direction.check``).
CHECK_SPEEDS = np.linspace(0.0, 1.0, 129)
#: How far K_in v_sat may be from 1 ([F9]: K_in = 1/v_sat, written and read back in float64).
K_IN_TOLERANCE = 1e-9


def opposes_motion(force) -> bool:
    """Whether a curve's force on the speeds ``CHECK_SPEEDS`` opposes the motion: nowhere below
    -PUSHES_AT_MOST of its largest magnitude (``Direction.check``).

    Parameters
    ----------
    force : array_like
        The force (or the normalized level) of one direction at |v| = CHECK_SPEEDS x v_sat.

    Returns
    -------
    bool

    Examples
    --------
    >>> opposes_motion([2.0, 1.5, 1.0]), opposes_motion([-0.2, 1.0, 2.0])
    (True, False)
    """
    force = np.asarray(force, dtype=float)
    return bool(np.min(force) >= -PUSHES_AT_MOST * np.max(np.abs(force)))


@dataclass(frozen=True)
class Scaling:
    """Normalization of [F9]: x = K_in v, t = K_out (F - B v).

    Parameters
    ----------
    k_in : float
        K_in (s/m): 1 / v_sat, so that x is in [0, 1] on the trained range.
    k_out : float
        K_out (1/N): scales the target to at most 1 in magnitude.

    Examples
    --------
    >>> from fricgen.direction import Scaling
    >>> Scaling(k_in=1 / 0.06, k_out=0.05).k_out
    0.05
    """

    k_in: float
    k_out: float


@dataclass(frozen=True)
class Direction:
    """The curve of [F3] for one direction of motion, as a function of the speed |v|:
    AIM(K_in min(|v|, v_sat)) / K_out + B |v|.

    Parameters
    ----------
    aim : network
        The trained network of any kind (``fricgen.networks``), from x to t of [F9].
    scaling : Scaling
        K_in and K_out of [F9].
    viscous : float
        B (N s/m), identified above v_sat.
    v_sat : float
        The speed (m/s) beyond which the network input saturates (3 vs_max).

    Examples
    --------
    >>> import fricgen
    >>> model = fricgen.FrictionModel.fit(
    ...     fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset,
    ...     fricgen.ELMRegressor(random_state=0))
    >>> round(model.positive.v_sat, 2)
    0.06
    """

    aim: Any
    scaling: Scaling
    viscous: float
    v_sat: float

    @classmethod
    def fit(cls, dataset, estimator) -> "Direction":
        """Fit ``estimator`` to the [F9] data of one direction."""
        estimator.fit(dataset.x, dataset.t)
        return cls(aim=estimator.network_, scaling=dataset.scaling, viscous=dataset.viscous,
                   v_sat=dataset.v_sat)

    def network_input(self, speed) -> np.ndarray:
        """x = K_in min(|v|, v_sat)."""
        return self.scaling.k_in * np.minimum(np.abs(np.asarray(speed, dtype=float)), self.v_sat)

    def stribeck(self, speed) -> np.ndarray:
        """AIM(K_in min(|v|, v_sat)) / K_out: the force at |v| without B |v|."""
        return self.aim(self.network_input(speed)) / self.scaling.k_out

    def magnitude(self, speed) -> np.ndarray:
        """|F| at the speed |v| in this direction."""
        speed = np.abs(np.asarray(speed, dtype=float))
        return self.stribeck(speed) + self.viscous * speed

    def check(self) -> "Direction":
        """This curve, if the float32 C can run it as friction; else ``ModelError``: v_sat, the
        force scale 1/K_out, B or a Stribeck velocity of [F1] beyond FLOAT32_SCALE, a force on [0, v_sat] that is not finite
        or beyond it, a force that points with the motion (beyond PUSHES_AT_MOST of its largest), or a
        negative B that reverses the force before OPPOSES_MOTION_UP_TO v_sat."""
        for what, value, unit in (("v_sat", self.v_sat, "m/s"),
                                  ("the force scale 1/k_out", 1.0 / self.scaling.k_out, "N"),
                                  ("viscous", self.viscous, "N s/m")):
            if value != 0:
                float32_scale(what, value, unit, "not a model for the float32 C", ModelError)
        for k, xs in enumerate(getattr(self.aim, "stribeck", ())):     # [F1]'s, normalized
            float32_scale(f"aim.stribeck[{k}]", xs, "(normalized)", "not a model for the float32 C",
                          ModelError)
        with np.errstate(over="ignore", invalid="ignore"):
            force = self.magnitude(self.v_sat * CHECK_SPEEDS)
        worst = float(np.max(np.abs(force)))
        units = axis_units()
        if not worst <= FLOAT32_SCALE[1]:
            raise ModelError(f"the {units.effort} reaches {worst:.3g} {units.force} within [0, v_sat]; "
                             f"the float32 C needs it below {FLOAT32_SCALE[1]:g}")
        lowest = int(np.argmin(force))
        if not opposes_motion(force):
            raise ModelError(f"the friction is {force[lowest]:.3g} {units.force} at |v| = "
                             f"{self.v_sat * CHECK_SPEEDS[lowest]:.3g} {units.speed}: it pushes the axis "
                             "instead of opposing the motion (an edited offset, slope or weight?)")
        if self.viscous < 0:
            reversal = -self.stribeck(self.v_sat) / self.viscous
            if reversal < OPPOSES_MOTION_UP_TO * self.v_sat:
                raise ModelError(f"viscous = {self.viscous:.3g} {units.viscous} turns the friction against "
                                 f"|v| beyond {float(reversal):.3g} {units.speed}, within "
                                 f"{OPPOSES_MOTION_UP_TO:g} v_sat: friction must oppose the motion")
        return self

    def check_physical(self) -> "Direction":
        """This curve, if it is one of a real axis (``_validate.PHYSICAL``): v_sat within the
        bounds of v_sat, and the largest force on [0, v_sat] within those of a friction force;
        else ``ModelError`` naming the field (a decimal point lost by a hand edit, other units)."""
        problem = physical_problem("v_sat", "v_sat", self.v_sat)
        if not problem:
            worst = float(np.max(np.abs(self.magnitude(self.v_sat * CHECK_SPEEDS))))
            units = axis_units()
            problem = physical_problem("force", f"the largest {units.effort} on [0, v_sat]", worst)
            if problem and self.viscous * self.v_sat > PHYSICAL_FORCE_MAX:
                problem = f"viscous = {self.viscous:.6g} {units.viscous}: {problem}"
        if problem:
            raise ModelError(f"{problem} (a digit or decimal point lost, or other units? "
                             f"{ACCEPT_UNUSUAL} at training accepts it)")
        return self

    def to_dict(self) -> dict:
        return {"aim": self.aim.to_dict(),
                "scaling": {"k_in": self.scaling.k_in, "k_out": self.scaling.k_out},
                "viscous": self.viscous, "v_sat": self.v_sat}

    @classmethod
    def from_dict(cls, d: dict) -> "Direction":
        """The validated curve of an object holding aim, scaling, viscous and v_sat."""
        network = network_from_dict(d.get("aim"))
        scaling = d.get("scaling")
        if not isinstance(scaling, dict):
            raise ModelError("missing or invalid field 'scaling' (an object)")
        k_in = json_number(scaling, "k_in", "scaling", positive=True)
        k_out = json_number(scaling, "k_out", "scaling", positive=True)
        viscous = json_number(d, "viscous", "model")
        v_sat = json_number(d, "v_sat", "model", positive=True)
        if not abs(k_in * v_sat - 1.0) <= K_IN_TOLERANCE:
            raise ModelError(f"scaling.k_in ({k_in:.6g} 1/(m/s)) times v_sat ({v_sat:.6g} m/s) is "
                             f"{k_in * v_sat:.6g}; the normalization [F9] needs k_in = 1/v_sat "
                             "(was one of them edited?)")
        for key in ("aim", "scaling", "viscous", "v_sat"):
            where = float32_overflow(d.get(key), key)
            if where:
                raise ModelError(f"{where} is beyond {FLOAT32_MAX:.4g}, the largest float32: the C "
                                 "would hold infinity there")
        return cls(network, Scaling(k_in, k_out), viscous, v_sat).check()


def _negative_from_dict(d: dict) -> Direction:
    """Version 2's ``negative`` object, validated strictly (exactly its four fields)."""
    negative = d.get("negative")
    if not isinstance(negative, dict):
        raise ModelError("missing or invalid field 'negative' (an object): an asymmetric model "
                         "needs the curve for v < 0")
    unknown = sorted(set(negative) - set(_DIRECTION_FIELDS))
    if unknown:
        raise ModelError(f"unknown field 'negative.{unknown[0]}'"[:200])
    try:
        return Direction.from_dict(negative)
    except ModelError as exc:
        raise ModelError(f"negative: {exc}") from None
