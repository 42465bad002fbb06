"""The contract of an effect a friction model may miss, and that model.json may carry.

Each effect is one small class: its parameters (dataclass fields), ``fit`` (a classmethod that
identifies it from a force residual), ``force`` (its contribution in newtons), ``to_dict`` /
``from_dict``. Sign convention, extending [C1]:

    m dv/dt = phi i - F(v) - sum_k effect_k        (F(v) of [F3]),

so an effect with positive force opposes positive motion. Effects that are functions of v and
x only (``in_xv``) are also emitted into C as part of ``NAME_force_xv(v, x)``.

Fitting sees a ``problem`` (built by ``fricgen.diagnose``) with the measured ``signals``, the
smoothed force residual ``target`` at decimated ``rows`` and ``at_rows(raw, rows)``, which
smooths a full-rate signal with the same filter as the residual and samples it at the rows.
"""
from __future__ import annotations

import math
from dataclasses import MISSING, asdict, dataclass, fields
from typing import Any, ClassVar, Dict, Tuple

import numpy as np

from .._validate import finite_number
from ..errors import ModelError
from ..friction import SHAPES
from .signals import Signals

#: A fitted mass or force constant further than this factor from the nominal one is not read as
#: a mismatch of it: a model that simulates well only with such a value is stiff or inert
#: enough to hide any force error, and the fit is other structure in the residual.
PLAUSIBLE_FACTOR = 5.0


def _ratio_implausible(what: str, value: float, nominal: float) -> str:
    ratio = value / nominal
    if 1.0 / PLAUSIBLE_FACTOR <= ratio <= PLAUSIBLE_FACTOR:
        return ""
    return (f"the fitted {what} is {ratio:.3g} x the nominal one, beyond the factor "
            f"{PLAUSIBLE_FACTOR:g} read as a mismatch")


@dataclass(frozen=True)
class Effect:
    """Base of the named effects a friction model may miss: parameters as dataclass fields, ``fit``
    (from a force residual), ``force(signals)`` (its contribution in N), ``to_dict``/``from_dict``.

    Notes
    -----
    Forces follow the sign convention of the module, extending [C1]:
    m dv/dt = phi i - F(v) - sum_k effect_k, so a positive force opposes positive motion.

    Examples
    --------
    >>> from fricgen.effects import EFFECTS, Effect
    >>> all(issubclass(cls, Effect) for cls in EFFECTS.values())
    True
    """

    name: ClassVar[str] = ""
    #: Function of (v, x) only: emitted into C as part of NAME_force_xv.
    in_xv: ClassVar[bool] = False
    #: Acts at rest too (part of the external force, not of sliding friction).
    acts_at_rest: ClassVar[bool] = False
    #: Parameters that must be > 0.
    positive: ClassVar[Tuple[str, ...]] = ()
    #: Parameters that must be >= 0.
    non_negative: ClassVar[Tuple[str, ...]] = ()
    #: (parameter, its nominal) pairs: a value further than PLAUSIBLE_FACTOR from the nominal one
    #: is not read as this effect (``implausible``).
    nominal_of: ClassVar[Tuple[Tuple[str, str], ...]] = ()
    #: Parameters not counted as fitted (fixed by context, e.g. the nominal mass).
    fixed: ClassVar[Tuple[str, ...]] = ()
    #: Simulated through the mass or the force constant (mass_delta, force_constant_delta).
    via_dynamics: ClassVar[bool] = False
    #: Simulated through the timing of the current that drives the axis (input_delay).
    via_timing: ClassVar[bool] = False
    #: A function of the current (the actuator's): simulated as a loss of the motor's force.
    via_current: ClassVar[bool] = False
    #: The contact's own friction with a state (pre-sliding): simulated as the axis's contact
    #: (``sim.bristle_axis``), no force of the sample alone.
    via_contact: ClassVar[bool] = False
    #: Time constants whose 0 means none (a linear drift): the output-error refinement fits
    #: their inverse, so that 0 is a value like any other (``diagnose.refine``).
    time_constants: ClassVar[Tuple[str, ...]] = ()
    #: Parameters a known pole pitch or screw lead (``--pitch``) fixes: no fit changes them.
    given_by_pitch: ClassVar[Tuple[str, ...]] = ()

    @property
    def n_params(self) -> int:
        return len([f for f in fields(self) if f.name not in self.fixed and f.name != "shape"])

    def parameters(self) -> Dict[str, Any]:
        return asdict(self)

    def force(self, sig: Signals) -> np.ndarray:
        raise NotImplementedError

    # simulation: effects that change the mass or the force constant instead of adding a force
    mass_delta: ClassVar[float] = 0.0
    force_constant_delta: ClassVar[float] = 0.0
    lag_tau: ClassVar[float] = 0.0
    #: The simulation drives the axis with the current this much earlier (s): a log's timing.
    input_delay: ClassVar[float] = 0.0

    def to_dict(self) -> dict:
        return {"effect": self.name, "parameters": self.parameters()}

    def linear(self, sig: Signals) -> Tuple[np.ndarray, np.ndarray]:
        """The regressors (N, k) of the parameters the force is linear in, with the others held,
        and their values (k,): force = fixed part + regressors @ values. None by default."""
        return np.zeros((np.size(sig.v), 0)), np.zeros(0)

    def with_coefficients(self, coef: np.ndarray) -> "Effect":
        """The effect whose linear parameters (``linear``) are ``coef``."""
        return self

    def for_log(self, mass: float, force_constant: float, t_start: float) -> "Effect":
        """The effect carried in a model, applied to a log that starts at ``t_start`` for an
        axis given as ``mass`` and ``force_constant``: as it is by default."""
        return self

    def variants(self) -> Tuple["Effect", ...]:
        """The effect and the other discrete choices of its form a joint linear solve should
        also try (``linear`` of each): the effect alone by default."""
        return (self,)

    def implausible(self) -> str:
        """Why the fitted values cannot be what the effect's name says ('' if they can)."""
        for p, nominal in self.nominal_of:
            why = _ratio_implausible(p.replace("_", " "), getattr(self, p), getattr(self, nominal))
            if why:
                return why
        return ""

    def implausible_beside(self, curve, speeds: np.ndarray) -> str:
        """Why the fitted values cannot be what the name says beside the friction ``curve`` at
        ``speeds`` (m/s, the log's): '' by default."""
        return ""

    def unresolved(self, sample_time: float) -> str:
        """Why a log sampled every ``sample_time`` cannot tell the fitted values from none
        ('' if it can)."""
        return ""

    def refused(self, sample_time: float) -> str:
        """Why the fitted values cannot be named on a log sampled every ``sample_time``: not
        what the name says (``implausible``) or not resolved by the log (``unresolved``); ''
        if they can."""
        return self.implausible() or self.unresolved(sample_time)

    def mismatch(self) -> float:
        """How far the fitted values are from their nominal ones (``nominal_of``): the largest
        |value / nominal - 1| (0 for an effect without nominal values)."""
        return max((abs(getattr(self, p) / getattr(self, nominal) - 1.0)
                    for p, nominal in self.nominal_of), default=0.0)

    def limits(self) -> Dict[str, Tuple[float, float]]:
        """The range [low, high] of each bounded parameter: from 0 (``positive``: above it,
        ``non_negative``: at it too), or within PLAUSIBLE_FACTOR of its nominal (``nominal_of``)."""
        out = {p: (0.0, math.inf) for p in (*self.positive, *self.non_negative)}
        for p, nominal in self.nominal_of:
            ref = getattr(self, nominal)
            out[p] = (ref / PLAUSIBLE_FACTOR, ref * PLAUSIBLE_FACTOR)
        return out

    @classmethod
    def parameters_of(cls, d: dict, allowed) -> Tuple[dict, str]:
        """``d["parameters"]`` (an object with no field outside ``allowed``) and the path to it
        for error messages, else ``ModelError``."""
        params = d.get("parameters")
        where = f"effects[{cls.name}]"
        if not isinstance(params, dict):
            raise ModelError(f"{where}.parameters must be an object")
        unknown = sorted(set(params) - set(allowed))
        if unknown:
            raise ModelError(f"{where}.parameters: unknown field {unknown[0]!r}"[:200])
        return params, where

    @classmethod
    def from_dict(cls, d: dict) -> "Effect":
        params, where = cls.parameters_of(d, {f.name for f in fields(cls)})
        values = {}
        for f in fields(cls):
            if f.name not in params and f.default is not MISSING:
                values[f.name] = f.default          # a field added later: its neutral value
                continue
            if f.name not in params:
                raise ModelError(f"{where}.parameters: missing field {f.name!r}")
            value = params[f.name]
            if f.name == "shape":
                if not isinstance(value, str) or value not in SHAPES:
                    raise ModelError(f"{where}.parameters.shape must be one of {sorted(SHAPES)}, "
                                     f"got {value!r}"[:200])
                values[f.name] = value
                continue
            if not finite_number(value):
                raise ModelError(f"{where}.parameters.{f.name} must be a finite number, got {value!r}"[:200])
            if f.name in cls.positive and value <= 0:
                raise ModelError(f"{where}.parameters.{f.name} must be > 0, got {value}")
            if f.name in cls.non_negative and value < 0:
                raise ModelError(f"{where}.parameters.{f.name} must be >= 0, got {value}")
            values[f.name] = float(value)
        return cls(**values)

    # C: an expression in v, x, speed (|v|), sgn (sign of v) and base (NAME_force(v)); or, for
    # an effect with a static helper function (``c_function``), ``c_call`` of that function
    def c_function(self, symbol: str) -> str:
        """C code of a static function named ``symbol`` that ``c_call(symbol)`` calls ('' if
        ``c_expr`` needs none)."""
        return ""

    def c_call(self, symbol: str) -> str:
        """The expression calling the helper ``symbol`` of ``c_function``."""
        raise NotImplementedError(f"{self.name} has no helper function")

    def c_expr(self) -> str:
        raise NotImplementedError(f"{self.name} is not a function of (v, x)")

    def force_f32(self, v, x, base) -> np.ndarray:
        """Float32 mirror of ``c_expr`` (same operations, same order)."""
        raise NotImplementedError(f"{self.name} is not a function of (v, x)")
