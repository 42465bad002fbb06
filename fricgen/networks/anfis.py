"""The trained first-order Takagi-Sugeno network of ANFIS (section 3), one input."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .._validate import json_equal_lengths, json_vector
from ..errors import ModelError

MF_KINDS = ("bell", "gauss")
TINY = 1e-12


def check_mf(mf: str) -> str:
    if mf not in MF_KINDS:
        raise ValueError(f"mf must be one of {list(MF_KINDS)}, got {mf!r}")
    return mf


def memberships(mf, x, centers, widths, exponents):
    """mu (N x n) of every MF at every x."""
    u = (x[:, None] - centers[None, :]) / widths[None, :]
    if mf == "bell":
        return 1.0 / (1.0 + np.abs(u) ** (2.0 * exponents[None, :]))
    return np.exp(-0.5 * u * u)


@dataclass(frozen=True)
class AnfisNetwork:
    r"""A trained one-input first-order Takagi-Sugeno system (sec. 3), the AIM of [F3] as ANFIS.

    Parameters
    ----------
    mf : {"bell", "gauss"}
        The membership functions' kind.
    centers : array_like, shape (n,)
        c_j.
    widths : array_like, shape (n,)
        a_j (bell) or sigma_j (gauss).
    exponents : array_like, shape (n,), or None
        b_j of the bell; None for Gaussians.
    slopes, intercepts : array_like, shape (n,)
        The consequents p_j and r_j (units of t per unit x, and of t).

    Notes
    -----
    .. math::

        y(x) = \sum_j \bar w_j(x) (p_j x + r_j), \quad
        \bar w_j = \mu_j / \sum_i \mu_i, \quad
        \mu_j = 1 / (1 + |(x - c_j) / a_j|^{2 b_j}) \text{ or } e^{-(x - c_j)^2 / (2 \sigma_j^2)}

    Examples
    --------
    >>> from fricgen.networks import AnfisNetwork
    >>> net = AnfisNetwork("gauss", [0.0, 1.0], [0.5, 0.5], None, [0.0, 0.0], [1.0, 3.0])
    >>> round(float(net(0.5)), 3)          # equal firing: the mean of the intercepts
    2.0
    """

    mf: str
    centers: np.ndarray
    widths: np.ndarray
    exponents: Optional[np.ndarray]
    slopes: np.ndarray
    intercepts: np.ndarray

    kind = "anfis"

    def __post_init__(self):
        check_mf(self.mf)
        names = ("centers", "widths", "slopes", "intercepts")
        arrays = {k: np.asarray(getattr(self, k), dtype=float).ravel() for k in names}
        if self.mf == "bell":
            if self.exponents is None:
                raise ValueError("bell membership functions need exponents")
            arrays["exponents"] = np.asarray(self.exponents, dtype=float).ravel()
        elif self.exponents is not None:
            raise ValueError("gauss membership functions take no exponents, got some")
        sizes = {a.size for a in arrays.values()}
        if len(sizes) != 1 or 0 in sizes:
            raise ValueError(f"ANFIS parameter vectors must have one equal, non-zero length, got "
                             f"{ {k: a.size for k, a in arrays.items()} }")
        for k, a in arrays.items():
            if not np.all(np.isfinite(a)):
                raise ValueError(f"ANFIS {k} must be finite")
            if k in ("widths", "exponents") and not np.all(a > 0):
                raise ValueError(f"ANFIS {k} must be > 0, got {a.min()}")
            object.__setattr__(self, k, a)

    @property
    def n_mfs(self) -> int:
        return self.centers.size

    def memberships(self, x) -> np.ndarray:
        """mu_j(x), one row per input, one column per MF."""
        return memberships(self.mf, np.asarray(x, dtype=float).ravel(), self.centers,
                            self.widths, self.exponents)

    def firing(self, x) -> np.ndarray:
        """Normalized firing strengths wbar_j(x) (layer 3 of ANFIS)."""
        mu = self.memberships(x)
        return mu / np.maximum(mu.sum(axis=1, keepdims=True), TINY)

    def __call__(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        xr = x.ravel()
        y = np.sum(self.firing(xr) * (xr[:, None] * self.slopes + self.intercepts), axis=1)
        return y.reshape(x.shape)

    def to_dict(self) -> dict:
        d = {"kind": self.kind, "mf": self.mf, "centers": self.centers.tolist(),
             "widths": self.widths.tolist()}
        if self.mf == "bell":
            d["exponents"] = self.exponents.tolist()
        d.update(slopes=self.slopes.tolist(), intercepts=self.intercepts.tolist())
        return d

    @classmethod
    def from_dict(cls, d: dict) -> "AnfisNetwork":
        """The network of model.json's ``aim`` object, every field validated (``ModelError``)."""
        mf = d.get("mf")
        if not isinstance(mf, str) or mf not in MF_KINDS:
            raise ModelError(f"aim.mf must be one of {list(MF_KINDS)}, got {mf!r}"[:200])
        if mf == "gauss" and "exponents" in d:
            raise ModelError("aim.exponents: gauss membership functions take no exponents")
        keys = ["centers", "widths"] + (["exponents"] if mf == "bell" else []) + ["slopes", "intercepts"]
        vectors = {k: json_vector(d, k, "aim", positive=k in ("widths", "exponents")) for k in keys}
        json_equal_lengths("aim", vectors)
        return cls(mf, vectors["centers"], vectors["widths"], vectors.get("exponents"),
                   vectors["slopes"], vectors["intercepts"])
