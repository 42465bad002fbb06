"""The trained ELM network, [F7]: sum_k beta_k act(w_k x + b_k), with the activations of [F8]."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Dict

import numpy as np

from .._validate import json_equal_lengths, json_vector
from ..errors import ModelError


def _sigmoid(z):
    return 1.0 / (1.0 + np.exp(-z))


#: Activations of z = w x + b, [F8] and its smooth alternatives (section 5).
ACTIVATIONS: Dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "sigmoid": _sigmoid,
    "sine": np.sin,
    "rbf": lambda z: np.exp(-z * z),
    "multiquadric": lambda z: np.sqrt(1.0 + z * z),
}


def rounded_f32(fn, z):
    """fn(z) evaluated in double and rounded once to float: a correctly rounded libm float function."""
    with np.errstate(over="ignore"):
        return fn(z.astype(np.float64)).astype(np.float32)


#: |a| beyond which ``fric_exp_neg_f32`` clamps exp(-a)'s argument (FRIC_EXP_ARG_MAX in
#: c_runtime/fric_kernel.h): expf's result stays a normal float, so it never sets errno.
EXP_ARG_MAX = np.float32(87.0)


def exp_neg_f32(a):
    """Twin of ``fric_exp_neg_f32``: exp(-a) with a clamped to [-EXP_ARG_MAX, EXP_ARG_MAX] (NaN
    kept), correctly rounded to float."""
    a = np.asarray(a, dtype=np.float32)
    return rounded_f32(np.exp, -np.clip(a, -EXP_ARG_MAX, EXP_ARG_MAX))


#: The activations in float32 as the emitted C computes them (libm's expf, sinf, sqrtf taken as
#: correctly rounded; glibc's are within 1 ULP).
ACTIVATIONS_F32: Dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "sigmoid": lambda z: np.float32(1.0) / (np.float32(1.0) + exp_neg_f32(z)),
    "sine": lambda z: rounded_f32(np.sin, z),
    "rbf": lambda z: exp_neg_f32(z * z),
    "multiquadric": lambda z: rounded_f32(np.sqrt, np.float32(1.0) + z * z),
}


#: Inputs evaluated together by ``ElmNetwork.__call__`` (a block of H is EVAL_BLOCK x M).
EVAL_BLOCK = 1 << 14


def check_activation(name: str) -> str:
    if name not in ACTIVATIONS:
        raise ValueError(f"activation must be one of {sorted(ACTIVATIONS)}, got {name!r}")
    return name


def hidden_matrix(activation: str, x, w, b) -> np.ndarray:
    """H of [F11] for inputs x and hidden parameters (w, b)."""
    x = np.asarray(x, dtype=float).reshape(-1, 1)
    return ACTIVATIONS[activation](x * np.asarray(w) + np.asarray(b))


@dataclass(frozen=True)
class ElmNetwork:
    r"""A trained single-hidden-layer network, [F7]: the AIM of [F3] as an ELM.

    Parameters
    ----------
    activation : str
        The hidden units' function h ("sigmoid", ...).
    input_weights, biases : array_like, shape (M,)
        w_k and b_k (dimensionless; the input x = K_in v is in [0, 1]).
    output_weights : array_like, shape (M,)
        beta_k, in units of the normalized target t of [F9].

    Notes
    -----
    .. math::

        y(x) = \sum_{k=1}^M \beta_k h(w_k x + b_k) \quad (7)

    Examples
    --------
    >>> from fricgen.networks import ElmNetwork
    >>> net = ElmNetwork("sigmoid", [10.0], [0.0], [2.0])
    >>> net.n_hidden, round(float(net(0.0)), 3)       # 2 sigmoid(0)
    (1, 1.0)
    """

    activation: str
    input_weights: np.ndarray
    biases: np.ndarray
    output_weights: np.ndarray

    kind = "elm"

    def __post_init__(self):
        check_activation(self.activation)
        arrays = [np.asarray(a, dtype=float).ravel() for a in
                  (self.input_weights, self.biases, self.output_weights)]
        if not (arrays[0].size == arrays[1].size == arrays[2].size) or arrays[0].size == 0:
            raise ValueError("input_weights, biases, output_weights must have one equal, "
                             f"non-zero length, got {[a.size for a in arrays]}")
        if not all(np.all(np.isfinite(a)) for a in arrays):
            raise ValueError("network weights must be finite")
        for name, a in zip(("input_weights", "biases", "output_weights"), arrays):
            object.__setattr__(self, name, a)

    @property
    def n_hidden(self) -> int:
        return self.input_weights.size

    def hidden(self, x) -> np.ndarray:
        """The hidden-layer matrix H of [F11], one row per input."""
        return hidden_matrix(self.activation, x, self.input_weights, self.biases)

    def __call__(self, x) -> np.ndarray:
        """[F7] at every x, in blocks of EVAL_BLOCK inputs: memory stays bounded by the
        block, not by len(x) times the number of neurons."""
        x = np.asarray(x, dtype=float)
        flat = x.ravel()
        out = np.empty(flat.size)
        for start in range(0, flat.size, EVAL_BLOCK):
            block = flat[start:start + EVAL_BLOCK]
            out[start:start + block.size] = self.hidden(block) @ self.output_weights
        return out.reshape(x.shape)

    def float32(self, x) -> np.ndarray:
        """[F7] as the emitted ``fric_elm_<activation>_f32`` computes it: w, b, beta and x
        rounded to float, sum_k beta_k act(w_k x + b_k) in float32, k ascending."""
        x = np.asarray(x, dtype=np.float32)
        w, b, beta = (a.astype(np.float32) for a in (self.input_weights, self.biases, self.output_weights))
        act = ACTIVATIONS_F32[self.activation]
        acc = np.zeros_like(x)
        with np.errstate(over="ignore", invalid="ignore"):
            for k in range(w.size):
                acc = acc + beta[k] * act(w[k] * x + b[k])
        return acc

    def to_dict(self) -> dict:
        return {"kind": self.kind, "activation": self.activation,
                "input_weights": self.input_weights.tolist(), "biases": self.biases.tolist(),
                "output_weights": self.output_weights.tolist()}

    @classmethod
    def from_dict(cls, d: dict) -> "ElmNetwork":
        """The network of model.json's ``aim`` object, every field validated (``ModelError``)."""
        activation = d.get("activation")
        if not isinstance(activation, str) or activation not in ACTIVATIONS:
            raise ModelError(f"aim.activation must be one of {sorted(ACTIVATIONS)}, "
                             f"got {activation!r}"[:200])
        vectors = {k: json_vector(d, k, "aim") for k in ("input_weights", "biases", "output_weights")}
        json_equal_lengths("aim", vectors)
        return cls(activation, *vectors.values())
