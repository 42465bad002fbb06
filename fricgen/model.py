"""FrictionModel, eq. (3), and its model.json (format version 1).

model.json is untrusted input: ``FrictionModel.from_dict`` validates every field before any of
it is used, and raises ``ModelError`` with one line that names the field.
"""
from __future__ import annotations

import hashlib
import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, Tuple, Union

import numpy as np

from . import __version__
from .data import Scaling
from .elm import ACTIVATIONS, ElmNetwork
from .files import write_atomic
from .fuzzy import MF_KINDS, AnfisNetwork

FORMAT = "fricgen-model"
FORMAT_VERSION = 1
#: The largest hidden layer model.json may declare (fixed-size C tables).
MAX_HIDDEN = 4096

_C_KEYWORDS = frozenset("""auto break case char const continue default do double else enum extern
float for goto if inline int long register restrict return short signed sizeof static struct
switch typedef union unsigned void volatile while _Bool _Complex _Imaginary""".split())
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,62}\Z")


class ModelError(ValueError):
    """An invalid model.json; the message names the offending field."""


def check_c_identifier(name: Any, what: str = "name") -> str:
    """A C identifier (at most 63 characters, no keyword, no reserved leading underscore)."""
    if not isinstance(name, str) or not _IDENT.match(name) or name in _C_KEYWORDS \
            or name.startswith("__") or re.match(r"_[A-Z]", name):
        raise ModelError(f"{what} must be a C identifier (letters, digits, _; 1-63 characters), "
                         f"got {name!r}"[:200])
    return name


def _number(d: dict, key: str, where: str, positive: bool = False) -> float:
    if key not in d:
        raise ModelError(f"{where}: missing field {key!r}")
    value = d[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ModelError(f"{where}.{key} must be a number, got {type(value).__name__}")
    if not math.isfinite(value):
        raise ModelError(f"{where}.{key} must be finite, got {value}")
    if positive and value <= 0:
        raise ModelError(f"{where}.{key} must be > 0, got {value}")
    return float(value)


def _vector(d: dict, key: str, where: str) -> np.ndarray:
    if key not in d:
        raise ModelError(f"{where}: missing field {key!r}")
    value = d[key]
    if not isinstance(value, list) or not 1 <= len(value) <= MAX_HIDDEN:
        raise ModelError(f"{where}.{key} must be a list of 1 to {MAX_HIDDEN} numbers")
    for i, item in enumerate(value):
        if isinstance(item, bool) or not isinstance(item, (int, float)) or not math.isfinite(item):
            raise ModelError(f"{where}.{key}[{i}] must be a finite number, got {item!r}"[:200])
    return np.asarray(value, dtype=float)


def _elm_from_dict(d: dict) -> ElmNetwork:
    activation = d.get("activation")
    if activation not in ACTIVATIONS:
        raise ModelError(f"aim.activation must be one of {sorted(ACTIVATIONS)}, got {activation!r}"[:200])
    w, b, beta = (_vector(d, k, "aim") for k in ("input_weights", "biases", "output_weights"))
    if not w.size == b.size == beta.size:
        raise ModelError(f"aim: input_weights, biases, output_weights have lengths "
                         f"{w.size}, {b.size}, {beta.size}; they must be equal")
    return ElmNetwork(activation, w, b, beta)


def _anfis_from_dict(d: dict) -> AnfisNetwork:
    mf = d.get("mf")
    if mf not in MF_KINDS:
        raise ModelError(f"aim.mf must be one of {list(MF_KINDS)}, got {mf!r}"[:200])
    keys = ["centers", "widths"] + (["exponents"] if mf == "bell" else []) + ["slopes", "intercepts"]
    if mf == "gauss" and "exponents" in d:
        raise ModelError("aim.exponents: gauss membership functions take no exponents")
    vectors = {k: _vector(d, k, "aim") for k in keys}
    if len({v.size for v in vectors.values()}) != 1:
        raise ModelError(f"aim: {', '.join(keys)} have lengths "
                         f"{', '.join(str(v.size) for v in vectors.values())}; they must be equal")
    for k in ("widths", "exponents"):
        if k in vectors and not np.all(vectors[k] > 0):
            raise ModelError(f"aim.{k} must all be > 0, got {float(vectors[k].min())}")
    return AnfisNetwork(mf, vectors["centers"], vectors["widths"], vectors.get("exponents"),
                        vectors["slopes"], vectors["intercepts"])


#: Readers of the AIM kinds model.json may hold, by ``aim.kind``.
AIM_READERS: Dict[str, Callable[[dict], Any]] = {"elm": _elm_from_dict, "anfis": _anfis_from_dict}


@dataclass(frozen=True)
class FrictionModel:
    """Eq. (3): F(v) = AIM(K_in min(|v|, v_sat)) / K_out sgn(v) + B v.

    The network is trained on t = K_out (F - B v) (eq. 9), so its output is divided by K_out
    (the paper's eq. (3) writes the inverse scaling as K_out). Beyond v_sat = 3 vs_max the network
    input saturates. The model is odd: F(-v) = -F(v) exactly.
    """

    aim: Any
    scaling: Scaling
    viscous: float
    v_sat: float
    name: str = "fric_model"
    symmetric: bool = True
    effects: Tuple[dict, ...] = ()
    training: Dict[str, Any] = field(default_factory=dict)

    @classmethod
    def fit(cls, dataset, estimator, name: str = "fric_model", training=None) -> "FrictionModel":
        """Fit ``estimator`` (e.g. an ELMRegressor) to the eq. (9) data and wrap it in eq. (3)."""
        estimator.fit(dataset.x, dataset.t)
        return cls(aim=estimator.network_, scaling=dataset.scaling, viscous=dataset.viscous,
                   v_sat=dataset.v_sat, name=check_c_identifier(name),
                   training=dict(training or {}))

    def network_input(self, v) -> np.ndarray:
        """x = K_in min(|v|, v_sat): the saturated, normalized network input of eq. (3)."""
        return self.scaling.k_in * np.minimum(np.abs(np.asarray(v, dtype=float)), self.v_sat)

    def force(self, v) -> np.ndarray:
        """Friction force in newtons for any sign of v, eq. (3)."""
        v = np.asarray(v, dtype=float)
        g = self.aim(self.network_input(v)) / self.scaling.k_out
        return np.sign(v) * g + self.viscous * v

    __call__ = force

    def to_dict(self) -> dict:
        return {"format": FORMAT, "format_version": FORMAT_VERSION, "fricgen_version": __version__,
                "name": self.name, "aim": self.aim.to_dict(),
                "scaling": {"k_in": self.scaling.k_in, "k_out": self.scaling.k_out},
                "viscous": self.viscous, "v_sat": self.v_sat, "symmetric": self.symmetric,
                "effects": list(self.effects), "training": self.training}

    @property
    def model_hash(self) -> str:
        """SHA-256 (first 16 hex digits) of everything that determines the force."""
        d = self.to_dict()
        core = {k: d[k] for k in ("aim", "scaling", "viscous", "v_sat", "symmetric", "effects")}
        return hashlib.sha256(json.dumps(core, sort_keys=True).encode()).hexdigest()[:16]

    def save(self, path: Union[str, Path]) -> Path:
        return write_atomic(path, json.dumps(self.to_dict(), indent=1) + "\n")

    @classmethod
    def from_dict(cls, d: Any) -> "FrictionModel":
        if not isinstance(d, dict):
            raise ModelError("model.json must hold a JSON object")
        if d.get("format") != FORMAT:
            raise ModelError(f"format must be {FORMAT!r}, got {d.get('format')!r}"[:200])
        if d.get("format_version") != FORMAT_VERSION:
            raise ModelError(f"unknown format_version {d.get('format_version')!r}; "
                             f"this fricgen reads version {FORMAT_VERSION}"[:200])
        name = check_c_identifier(d.get("name"))
        aim = d.get("aim")
        if not isinstance(aim, dict):
            raise ModelError("missing or invalid field 'aim' (an object)")
        if aim.get("kind") not in AIM_READERS:
            raise ModelError(f"aim.kind must be one of {sorted(AIM_READERS)}, got {aim.get('kind')!r}"[:200])
        network = AIM_READERS[aim["kind"]](aim)
        scaling = d.get("scaling")
        if not isinstance(scaling, dict):
            raise ModelError("missing or invalid field 'scaling' (an object)")
        k_in = _number(scaling, "k_in", "scaling", positive=True)
        k_out = _number(scaling, "k_out", "scaling", positive=True)
        viscous = _number(d, "viscous", "model")
        v_sat = _number(d, "v_sat", "model", positive=True)
        if d.get("symmetric", True) is not True:
            raise ModelError("symmetric must be true: format version 1 holds symmetric models only")
        from .effects import validate_effects  # the effect library builds on this module
        effects = validate_effects(d.get("effects", []))
        training = d.get("training", {})
        if not isinstance(training, dict):
            raise ModelError("training must be an object")
        return cls(aim=network, scaling=Scaling(k_in, k_out), viscous=viscous, v_sat=v_sat,
                   name=name, effects=tuple(effects), training=training)

    @classmethod
    def load(cls, path: Union[str, Path]) -> "FrictionModel":
        try:
            text = Path(path).read_text()
        except OSError as exc:
            raise ModelError(f"{path}: cannot read ({exc.strerror})") from None
        try:
            d = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ModelError(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno})") from None
        return cls.from_dict(d)
