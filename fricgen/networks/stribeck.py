"""[F1] as a network in the normalized coordinates of [F9]: the grey-box Stribeck curve."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import json_equal_lengths, json_number, json_vector
from ..errors import ModelError
from ..friction import SHAPES


@dataclass(frozen=True)
class StribeckCurve:
    r"""[F1] with S sources of one shape g, in the normalized coordinates of [F9]: the AIM of
    [F3] of the grey-box model.

    Parameters
    ----------
    shape : {"gauss", "exponential", "rational"}
        g of [F2].
    offset : float
        c, gathering every f_ck (scaled by K_out).
    amplitudes : array_like, shape (S,)
        a_k = K_out (f_sk - f_ck).
    stribeck : array_like, shape (S,)
        x_sk = K_in v_sk (> 0).
    slope : float
        d, absorbing an error of the identified B (0 when B is trusted).

    Notes
    -----
    .. math::

        t(x) = c + \sum_{k=1}^S a_k g(x, x_{sk}) + d x

    Examples
    --------
    >>> from fricgen.networks import StribeckCurve
    >>> curve = StribeckCurve("gauss", offset=0.5, amplitudes=[0.5], stribeck=[0.2])
    >>> round(float(curve(0.0)), 3), round(float(curve(1.0)), 3)
    (1.0, 0.5)
    """

    shape: str
    offset: float
    amplitudes: np.ndarray
    stribeck: np.ndarray
    slope: float = 0.0

    kind = "stribeck"

    def __post_init__(self):
        if self.shape not in SHAPES:
            raise ValueError(f"shape must be one of {sorted(SHAPES)}, got {self.shape!r}")
        a = np.asarray(self.amplitudes, dtype=float).ravel()
        xs = np.asarray(self.stribeck, dtype=float).ravel()
        if a.size != xs.size or a.size == 0:
            raise ValueError(f"amplitudes and stribeck must have one equal, non-zero length, "
                             f"got {a.size}, {xs.size}")
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(xs)) and np.isfinite(self.offset)
                and np.isfinite(self.slope)):
            raise ValueError("Stribeck curve parameters must be finite")
        if not np.all(xs > 0):
            raise ValueError(f"Stribeck velocities must be > 0, got {xs.min()}")
        object.__setattr__(self, "amplitudes", a)
        object.__setattr__(self, "stribeck", xs)
        object.__setattr__(self, "offset", float(self.offset))
        object.__setattr__(self, "slope", float(self.slope))

    @property
    def n_sources(self) -> int:
        return self.amplitudes.size

    def __call__(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        g = SHAPES[self.shape]
        y = self.offset + self.slope * x
        for a, xs in zip(self.amplitudes, self.stribeck):
            y = y + a * g(x, xs)
        return y

    def to_dict(self) -> dict:
        return {"kind": self.kind, "shape": self.shape, "offset": self.offset,
                "amplitudes": self.amplitudes.tolist(), "stribeck": self.stribeck.tolist(),
                "slope": self.slope}

    @classmethod
    def from_dict(cls, d: dict) -> "StribeckCurve":
        """The curve of model.json's ``aim`` object, every field validated (``ModelError``)."""
        shape = d.get("shape")
        if not isinstance(shape, str) or shape not in SHAPES:
            raise ModelError(f"aim.shape must be one of {sorted(SHAPES)}, got {shape!r}"[:200])
        vectors = {"amplitudes": json_vector(d, "amplitudes", "aim"),
                   "stribeck": json_vector(d, "stribeck", "aim", positive=True)}
        json_equal_lengths("aim", vectors)
        return cls(shape, json_number(d, "offset", "aim"), vectors["amplitudes"],
                   vectors["stribeck"], json_number(d, "slope", "aim"))
