"""FrictionModel, [F3], and its model.json (format versions 1 and 2); the curve of each
direction is ``fricgen.direction``.

Version 1 holds a symmetric model, F(-v) = -F(v). Version 2 adds the asymmetric model: a
second curve of [F3] (``negative``: its own AIM of any network kind, scaling, B and v_sat)
for v < 0. Version 3 adds ``inputs``: friction that depends on the load and the temperature
(``effects.load_temperature``). Each model is written in the oldest version that holds it, so
that a reader too old for a model refuses it rather than dropping a field.

model.json is untrusted input: ``FrictionModel.from_dict`` validates every field before any of
it is used, and raises ``ModelError`` with one line that names the field.
"""
from __future__ import annotations

import errno
import hashlib
import json
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Dict, Optional, Tuple, Union

import numpy as np

from . import __version__
from ._io import read_only, write_atomic
from ._json import finite_or_null, read_json
from .axis import Axis
from ._validate import json_number, rotary_axis
from .c_names import check_c_identifier
from .direction import Direction, Scaling, _negative_from_dict  # noqa: F401  (Scaling: fricgen.model's API)
from .effects.cogging_map import CoggingMap, check_rotary_period
from .effects.load_temperature import LoadTemperature
from .effects.presliding import Bristles, BristleStepper, bristle_force
from .effects import validate_effects
from .errors import ModelError
from .units import Units, units_of

FORMAT = "fricgen-model"
#: The newest format version this fricgen reads and writes (models with inputs beside v).
FORMAT_VERSION = 3
#: The format version of a symmetric model.
SYMMETRIC_FORMAT_VERSION = 1
#: The format version of an asymmetric model.
ASYMMETRIC_FORMAT_VERSION = 2
#: Largest model.json read: MAX_HIDDEN neurons of three tables fit in well under 1 MB.
MAX_JSON_BYTES = 16 << 20

#: The name ``fricgen train`` gives a model without ``--name``.
DEFAULT_MODEL_NAME = "friction_model"


#: ``recorded_hash`` of a model.json that names the fricgen which wrote it yet holds no
#: ``model_hash``: removed by hand (or written before the field existed), so an edit of its
#: force fields cannot be told.
HASH_REMOVED = "(removed)"


@dataclass(frozen=True)
class FrictionModel:
    """A friction model, [F3]: F(v) = AIM(K_in min(|v|, v_sat)) / K_out sgn(v) + B v.

    The network is trained on t = K_out (F - B v) [F9], so its output is divided by K_out
    (the paper's [F3] writes the inverse scaling as K_out). Beyond v_sat = 3 vs_max the network
    input saturates. The model is odd: F(-v) = -F(v) exactly, unless it is asymmetric:
    then ``negative`` (a ``Direction``) gives F for v < 0, F(v) = -negative.magnitude(|v|),
    and aim, scaling, viscous, v_sat are the curve for v >= 0. ``fricgen.train`` fits one;
    ``load`` and ``save`` read and write model.json.

    Parameters
    ----------
    aim : network
        The trained network of [F3] (``fricgen.networks``: ELM, grey-box [F1], ANFIS).
    scaling : Scaling
        K_in (1/(m/s)) and K_out (1/N) of [F9].
    viscous : float
        B, N s/m.
    v_sat : float
        Speed beyond which the network input saturates, m/s.
    name : str, default "friction_model"
        The model's name, a C identifier (the prefix of the emitted C).
    symmetric : bool
        Derived: True unless ``negative`` is given.
    effects : tuple of dict
        Effects appended by ``fricgen diagnose``.
    training : dict
        How it was trained (model.json's ``training``); not part of the hash.
    negative : Direction, optional
        The curve for v < 0 of an asymmetric model.
    cogging_map : CoggingMap, optional
        The position force ``fricgen train --cogging`` identified (``cogging``).
    cogging_friction : CoggingMap, optional
        The friction that varies along the travel (times sgn(v)) identified with it; reported,
        not emitted.
    presliding : Bristles, optional
        The LuGre bristles ``fricgen train --dynamic`` identified (``presliding``): the
        friction then has a state (``stepper``).
    velocity_band : float, optional
        The speed, m/s, up to which ``compensation`` is 0 (it ramps to the force at twice
        it): what the velocity sensor resolves (``velocity_band``).
    inputs : LoadTemperature, optional
        The friction's dependence on the load and the temperature (``fricgen train`` on a log
        with those columns): ``force`` then needs them.
    recorded_hash : str, optional
        The ``model_hash`` model.json recorded.
    recorded_axis_hash : str, optional
        The ``axis_hash`` model.json recorded.

    Notes
    -----
    .. math:: F(v) = \\frac{\\mathrm{AIM}(K_{in} \\min(|v|, v_{sat}))}{K_{out}} \\operatorname{sgn}(v) + B v

    Examples
    --------
    >>> import fricgen
    >>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
    >>> model = fricgen.train(sweep, vs_max=0.02, estimator=fricgen.StribeckRegressor()).model
    >>> bool(model.force(-0.05) == -model.force(0.05))
    True
    >>> path = model.save(tmp / "model.json")
    >>> fricgen.FrictionModel.load(path).model_hash == model.model_hash
    True
    """

    aim: Any
    scaling: Scaling
    viscous: float
    v_sat: float
    name: str = DEFAULT_MODEL_NAME
    symmetric: bool = True
    effects: Tuple[dict, ...] = ()
    training: Dict[str, Any] = field(default_factory=dict)
    negative: Optional[Direction] = None
    cogging_map: Optional[CoggingMap] = None
    cogging_friction: Optional[CoggingMap] = None
    presliding: Optional[Bristles] = None
    velocity_band: Optional[float] = None
    inputs: Optional[LoadTemperature] = None
    #: The ``model_hash`` model.json recorded (None for a model not read from one, or read from
    #: a file written before the field existed; ``HASH_REMOVED`` where a file that names the
    #: fricgen which wrote it holds none).
    recorded_hash: Optional[str] = field(default=None, compare=False, repr=False)
    #: The ``axis_hash`` model.json recorded (None likewise, or for a model without an axis).
    recorded_axis_hash: Optional[str] = field(default=None, compare=False, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "symmetric", self.negative is None)

    @property
    def positive(self) -> Direction:
        """The curve for v >= 0 (for every v of a symmetric model)."""
        return Direction(self.aim, self.scaling, self.viscous, self.v_sat)

    @property
    def directions(self) -> Tuple[Direction, ...]:
        """The curves of the model: (positive,), or (positive, negative) when asymmetric."""
        return (self.positive,) if self.negative is None else (self.positive, self.negative)

    @property
    def reference(self) -> "FrictionModel":
        """The one-input curve of this model: itself without ``inputs``, the friction at load 0
        and the reference temperature (what ``NAME_force`` of its C computes)."""
        return self if self.inputs is None else replace(self, inputs=None)

    @property
    def axis(self) -> Optional[Axis]:
        """The axis of the training data (``training.axis``: mass, force constant, offset,
        speed range), or None for a model whose training recorded none."""
        return _training_axis(self.training)

    @property
    def format_version(self) -> int:
        """The model.json format version that holds this model: 3 with inputs, else 1 if
        symmetric, 2 if not."""
        if self.inputs is not None:
            return FORMAT_VERSION
        return SYMMETRIC_FORMAT_VERSION if self.negative is None else ASYMMETRIC_FORMAT_VERSION

    @classmethod
    def from_directions(cls, positive: Direction, negative: Optional[Direction] = None,
                        name: str = DEFAULT_MODEL_NAME, training=None) -> "FrictionModel":
        """The model of one curve (symmetric) or of one curve per direction (asymmetric)."""
        return cls(aim=positive.aim, scaling=positive.scaling, viscous=positive.viscous,
                   v_sat=positive.v_sat, name=check_c_identifier(name),
                   training=dict(training or {}), negative=negative)

    @classmethod
    def fit(cls, dataset, estimator, name: str = DEFAULT_MODEL_NAME, training=None) -> "FrictionModel":
        """Fit ``estimator`` (e.g. an ELMRegressor) to the [F9] data and wrap it in [F3]."""
        return cls.from_directions(Direction.fit(dataset, estimator), name=name, training=training)

    def network_input(self, v) -> np.ndarray:
        """x = K_in min(|v|, v_sat): the saturated, normalized network input of [F3]."""
        return self.scaling.k_in * np.minimum(np.abs(np.asarray(v, dtype=float)), self.v_sat)

    def stribeck(self, v) -> np.ndarray:
        """The velocity-weakening part AIM(K_in min(|v|, v_sat)) / K_out of [F3] (no sign,
        no B v): F(|v|) - B |v|, and F(0+) at v = 0. An asymmetric model gives that of the
        negative curve where v < 0."""
        positive = self.aim(self.network_input(v)) / self.scaling.k_out
        if self.negative is None:
            return positive
        v = np.asarray(v, dtype=float)
        return np.where(v < 0, self.negative.stribeck(v), positive)

    def force(self, v, load=None, temperature=None) -> np.ndarray:
        """Friction force for any sign of v, [F3]; each direction's own curve
        when the model is asymmetric; at the load and temperature given when the model has
        ``inputs`` (``effects.load_temperature``).

        Parameters
        ----------
        v : array_like
            Velocities, m/s.
        load : array_like, optional
            The external force on the axis, N (Nm on a rotary axis), broadcast with ``v``:
            needed by a model that depends on it (``UsageError`` without), ignored by one that
            does not.
        temperature : array_like, optional
            The temperature, degC, likewise.

        Returns
        -------
        numpy.ndarray
            Forces, N, of the broadcast shape.
        """
        v = np.asarray(v, dtype=float)
        if self.negative is None:
            base = np.sign(v) * self.stribeck(v) + self.viscous * v
        else:
            base = np.where(v < 0, -self.negative.magnitude(v), np.sign(v) * self.positive.magnitude(v))
        if self.inputs is None:
            return base
        level, viscous = self.inputs.factors(v, load, temperature)
        linear = self.viscous_force(v)
        return (base - linear) * level + linear * viscous

    __call__ = force

    def compensation(self, v) -> np.ndarray:
        """The static compensating force at the velocity ``v`` (measured or the reference's):
        0 while |v| <= ``velocity_band`` (what the sensor cannot tell from rest: its jitter at
        rest never switches the compensation on), then a ramp to ``force(+-2 band)`` at twice
        the band, and ``force(v)`` beyond: continuous, with no sign switch on an unresolved
        velocity (0 for a NaN or infinite v, as the C ``NAME_compensation``). ``force`` for a model without
        a band.

        Examples
        --------
        >>> import dataclasses, fricgen
        >>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
        >>> model = fricgen.train(sweep, vs_max=0.02, estimator=fricgen.StribeckRegressor()).model
        >>> banded = dataclasses.replace(model, velocity_band=0.001)
        >>> float(banded.compensation(0.0005)), bool(banded.compensation(0.0015) == model.force(0.002) / 2)
        (0.0, True)
        """
        v = np.asarray(v, dtype=float)
        band = self.velocity_band
        if band is None:
            return self.force(v)
        speed = np.abs(v)
        edge = self.force(np.where(v < 0, -2.0 * band, 2.0 * band))
        ramp = edge * (np.maximum(speed - band, 0.0) * (1.0 / band))
        return np.where(~np.isfinite(v), 0.0, np.where(speed < 2.0 * band, ramp, self.force(v)))

    def stepper(self, dt: float):
        """The friction sample by sample at the sample time ``dt`` (s): an object with
        ``step(v)`` -> force (v held over the sample) and ``reset()``. With ``presliding``, the
        exact LuGre update (``effects.presliding``) on this model's static curve; without, the
        static ``force``.

        Examples
        --------
        >>> import dataclasses, fricgen
        >>> from fricgen.effects.presliding import Bristles
        >>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
        >>> model = fricgen.train(sweep, vs_max=0.02, estimator=fricgen.StribeckRegressor()).model
        >>> lugre = dataclasses.replace(model, presliding=Bristles(stiffness=1e6, damping=0.0))
        >>> friction = lugre.stepper(1e-4)
        >>> forces = [friction.step(0.01) for _ in range(1000)]
        >>> round(forces[0] / forces[-1], 3), bool(abs(forces[-1] - model.force(0.01)) < 1e-9)
        (0.054, True)
        >>> bool(abs(lugre.force_along([0.01] * 1000, 1e-4) - forces).max() < 1e-9)   # at once
        True
        """
        if self.presliding is None:
            return StaticStepper(self.force)
        return BristleStepper(lambda v: float(self.stribeck(v)), lambda v: float(self.viscous_force(v)),
                              self.presliding, dt)

    def force_along(self, v, dt: float) -> np.ndarray:
        """The friction along a sampled velocity history ``v`` (each held over its sample of
        ``dt`` s), as ``stepper(dt)`` gives it sample by sample from a relaxed contact: the
        static ``force`` without ``presliding`` (``stepper``'s example compares the two).
        """
        if self.presliding is None:
            return self.force(v)
        return bristle_force(self.stribeck, self.viscous_force, self.presliding, v, dt)[0]

    def viscous_force(self, v) -> np.ndarray:
        """B v with each direction's own B: ``force(v)`` less its velocity-weakening part."""
        v = np.asarray(v, dtype=float)
        negative = self.viscous if self.negative is None else self.negative.viscous
        return np.where(v < 0, negative, self.viscous) * v

    @property
    def units(self) -> Units:
        """The unit names of the axis it was trained on: m, m/s, N, kg, or on a rotary one
        (``training.units``) rad, rad/s, Nm, kg m^2."""
        return units_of(self.training.get("units") == "rotary")

    @property
    def axis_offset(self) -> float:
        """The axis's constant force, N (Nm on a rotary axis): ``training.axis.offset``, 0 where
        training identified none. [C1] with a constant force reads phi i = m v' + F(v) + offset:
        the part of the drive force that does not depend on v (gravity on an inclined axis, a
        cable's pull), not friction."""
        axis = self.axis
        return 0.0 if axis is None or axis.offset is None else float(axis.offset)

    def force_with_offset(self, v) -> np.ndarray:
        """``force(v) + axis_offset``: the drive force at constant velocity v (``fricgen eval``'s
        default, the C ``NAME_force_with_offset``)."""
        return self.force(v) + self.axis_offset

    def _force_fields(self) -> dict:
        """The fields of model.json that determine the force (what ``model_hash`` covers)."""
        d = {**self.positive.to_dict(), "symmetric": self.symmetric, "effects": list(self.effects)}
        if self.negative is not None:
            d["negative"] = self.negative.to_dict()
        if self.presliding is not None:
            d["presliding"] = self.presliding.to_dict()
        if self.velocity_band is not None:
            d["velocity_band"] = self.velocity_band
        if self.inputs is not None:
            d["inputs"] = self.inputs.to_dict()
        if self.cogging_map is not None or self.cogging_friction is not None:
            d["cogging"] = {key: m.to_dict() for key, m in
                            (("map", self.cogging_map), ("friction", self.cogging_friction)) if m is not None}
        return d

    def cogging(self, x) -> np.ndarray:
        """The cogging map alone at positions ``x`` (m, or rad): array in, array out; zeros for
        a model without one.

        Examples
        --------
        >>> import fricgen
        >>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
        >>> model = fricgen.train(sweep, vs_max=0.02, estimator=fricgen.StribeckRegressor()).model
        >>> model.cogging([0.0, 0.1]).tolist()
        [0.0, 0.0]
        """
        x = np.asarray(x, dtype=float)
        return np.zeros(x.shape) if self.cogging_map is None else self.cogging_map.force(x)

    def to_dict(self) -> dict:
        core = self._force_fields()
        d = {"format": FORMAT, "format_version": self.format_version,
             "fricgen_version": __version__, "name": self.name, "model_hash": self.model_hash,
             **({} if self.axis_hash is None else {"axis_hash": self.axis_hash}),
             **{k: core[k] for k in ("aim", "scaling", "viscous", "v_sat", "symmetric", "effects")},
             "training": self.training}
        if self.negative is not None:
            d["negative"] = core["negative"]
        for key in ("presliding", "velocity_band", "inputs", "cogging"):
            if key in core:
                d[key] = core[key]
        return d

    @property
    def model_hash(self) -> str:
        """SHA-256 (first 16 hex digits) of everything that determines the force, and of a
        rotary axis's units (``training.units``: an edit to linear would read its Nm as N)."""
        rotary = self.training.get("units") == "rotary"
        return _digest({**self._force_fields(), **({"units": "rotary"} if rotary else {})})

    @property
    def axis_hash(self) -> Optional[str]:
        """SHA-256 (first 16 hex digits) of the axis record (``training.axis``), which
        ``simulate``, ``diagnose`` and ``emit --dtype q15|q31`` read; None without one."""
        axis = self.training.get("axis")
        return None if axis is None else _digest(axis)

    def _edits(self) -> list:
        """(field, recorded, content's) for each recorded hash the content no longer gives."""
        return [(name, recorded, now) for name, recorded, now in
                (("model_hash", self.recorded_hash, self.model_hash),
                 ("axis_hash", self.recorded_axis_hash, self.axis_hash))
                if recorded is not None and recorded != now]

    @property
    def edited_after_training(self) -> bool:
        """Whether model.json recorded a ``model_hash`` its force fields, or an ``axis_hash``
        its axis record, no longer give."""
        return bool(self._edits())

    def hash_warning(self, path) -> str:
        """The one-line warning for a model.json edited after training ('' if it was not)."""
        if self.recorded_hash == HASH_REMOVED:
            return (f"fricgen: warning: {path}: holds no model_hash (removed by hand, or written "
                    "before fricgen recorded it): an edit of its force fields cannot be told")
        edits = "; ".join(f"{name} {recorded} recorded, its content gives {now}"
                          for name, recorded, now in self._edits())
        return f"fricgen: warning: {path}: edited after training ({edits})" if edits else ""

    def to_json(self) -> str:
        """model.json's text: strict JSON (a non-finite number in ``training``, such as the C
        of the pseudo-inverse, is written as null)."""
        return json.dumps(finite_or_null(self.to_dict()), indent=1, allow_nan=False) + "\n"

    def checked_json(self) -> str:
        """``to_json``, read back as ``load`` would: ``ModelError`` where load would refuse the
        file (what the commands that write a model.json check before writing it)."""
        text = self.to_json()
        FrictionModel.from_dict(json.loads(text))
        return text

    def save(self, path: Union[str, Path], force: bool = False) -> Path:
        """Write model.json to ``path`` all or nothing.

        Parameters
        ----------
        path : str or Path
            The file to write.
        force : bool, default False
            Replace a read-only file. Without it an existing read-only file is refused
            (``PermissionError``): writing a new file and renaming it into place would otherwise
            replace it, which writing into it would not.

        Returns
        -------
        Path
            The file written.
        """
        if not force and Path(path).is_file() and read_only(Path(path)):
            raise PermissionError(errno.EACCES, "read-only file; save(..., force=True) replaces it",
                                  str(path))
        return write_atomic(path, self.to_json())

    @classmethod
    def from_dict(cls, d: Any) -> "FrictionModel":
        if not isinstance(d, dict):
            raise ModelError("model.json must hold a JSON object")
        training = d.get("training")
        with rotary_axis(isinstance(training, dict) and training.get("units") == "rotary"):
            return cls._from_dict(d)         # its checks speak the units of its axis

    @classmethod
    def _from_dict(cls, d: dict) -> "FrictionModel":
        if d.get("format") != FORMAT:
            raise ModelError(f"format must be {FORMAT!r}, got {d.get('format')!r}"[:200])
        version = d.get("format_version")
        if isinstance(version, bool) or version not in range(SYMMETRIC_FORMAT_VERSION, FORMAT_VERSION + 1):
            raise ModelError(f"unknown format_version {d.get('format_version')!r}; this fricgen "
                             f"reads versions {SYMMETRIC_FORMAT_VERSION} to {FORMAT_VERSION}"[:200])
        inputs = None if d.get("inputs") is None else LoadTemperature.from_dict(d["inputs"])
        if inputs is not None and version != FORMAT_VERSION:
            raise ModelError(f"field 'inputs' needs format_version {FORMAT_VERSION}, got {version}")
        if inputs is None and version == FORMAT_VERSION:
            raise ModelError(f"format_version {FORMAT_VERSION} holds models with inputs (load, "
                             "temperature) only, and this one has no field 'inputs': an edited "
                             "format_version?")
        name = check_c_identifier(d.get("name"))
        positive = Direction.from_dict(d)
        negative = None
        symmetric = d.get("symmetric", True)
        if version == SYMMETRIC_FORMAT_VERSION:
            if symmetric is not True:
                raise ModelError("symmetric must be true: format version 1 holds symmetric models only")
            if "negative" in d:
                raise ModelError("field 'negative' needs format_version 2")
        elif symmetric is False:
            negative = _negative_from_dict(d)
        elif symmetric is not True:
            raise ModelError(f"symmetric must be true or false, got {symmetric!r}"[:200])
        elif "negative" in d:
            raise ModelError("the model says symmetric: true, yet holds a curve 'negative' of v < 0, "
                             "which only an asymmetric model (symmetric: false) has: one of the two "
                             "was edited")
        effects = validate_effects(d.get("effects", []))
        training = d.get("training", {})
        if not isinstance(training, dict):
            raise ModelError("training must be an object")
        _training_axis(training)
        with rotary_axis(training.get("units") == "rotary"):    # the bounds of its units
            if training.get("accept_unusual") is not True:
                for where, curve in (("", positive), ("negative: ", negative)):
                    try:
                        curve is None or curve.check_physical()
                    except ModelError as exc:
                        raise ModelError(f"{where}{exc}") from None
        recorded = {key: d.get(key) for key in ("model_hash", "axis_hash")}
        for key, value in recorded.items():
            if value is not None and not isinstance(value, str):
                raise ModelError(f"{key} must be a string, got {type(value).__name__}")
        if recorded["model_hash"] is None and "fricgen_version" in d:
            recorded["model_hash"] = HASH_REMOVED     # every fricgen that names itself writes it
        cogging = _cogging_from_dict(d.get("cogging"), training.get("units") == "rotary")
        presliding = None if d.get("presliding") is None else Bristles.from_dict(d["presliding"])
        band = None if d.get("velocity_band") is None else json_number(d, "velocity_band", "model", positive=True)
        return cls(aim=positive.aim, scaling=positive.scaling, viscous=positive.viscous,
                   v_sat=positive.v_sat, name=name, effects=tuple(effects), training=training,
                   negative=negative, cogging_map=cogging.get("map"),
                   cogging_friction=cogging.get("friction"), presliding=presliding,
                   velocity_band=band, inputs=inputs, recorded_hash=recorded["model_hash"],
                   recorded_axis_hash=recorded["axis_hash"])

    @classmethod
    def load(cls, path: Union[str, Path]) -> "FrictionModel":
        """Read and validate a model.json.

        Parameters
        ----------
        path : str or Path
            The model.json to read.

        Returns
        -------
        FrictionModel

        Raises
        ------
        ModelError
            Any problem of the file, in one line naming ``path``.
        """
        d = read_json(path, MAX_JSON_BYTES, "a model.json")
        try:
            return cls.from_dict(d)
        except ModelError as exc:
            raise ModelError(f"{path}: {exc}") from None


class StaticStepper:
    """``FrictionModel.stepper`` of a model without state: ``step(v)`` is ``force(v)``.

    Parameters
    ----------
    force : callable
        F(v), the model's ``force``.

    Examples
    --------
    >>> from fricgen.model import StaticStepper
    >>> StaticStepper(lambda v: 2.0 * v).step(0.5)
    1.0
    """

    def __init__(self, force):
        self._force = force

    def reset(self) -> None:
        """Nothing to reset: the static friction has no state."""

    def step(self, v: float) -> float:
        return float(self._force(v))

    __call__ = step


def _training_axis(training: dict) -> Optional[Axis]:
    """The axis record of a training record, validated against the bounds of its units (rotary
    or linear) unless training accepted unusual data; None without one."""
    record = training.get("axis")
    if record is None:
        return None
    with rotary_axis(training.get("units") == "rotary"):
        return Axis.from_dict(record, physical=training.get("accept_unusual") is not True)


def _cogging_from_dict(d, rotary: bool) -> Dict[str, CoggingMap]:
    """The maps of model.json's optional ``cogging`` object: ``map``, ``friction`` (a rotary
    axis's of at most a turn)."""
    if d is None:
        return {}
    if not isinstance(d, dict) or not d or not set(d) <= {"map", "friction"}:
        raise ModelError(f"cogging must be an object with 'map' and/or 'friction', got {d!r}"[:200])
    maps = {key: CoggingMap.from_dict(value, f"cogging.{key}") for key, value in d.items()}
    for key, m in maps.items() if rotary else ():
        check_rotary_period(m.period, f"cogging.{key}.period")
    return maps


def _digest(fields) -> str:
    """SHA-256 (first 16 hex digits) of ``fields`` as sorted, strict JSON."""
    return hashlib.sha256(json.dumps(finite_or_null(fields), sort_keys=True).encode()).hexdigest()[:16]
