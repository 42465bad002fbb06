"""Friction sweeps (section 2): velocity v and force f, read from and written to CSV."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Union

import numpy as np

from ..errors import DataError
from .table import read_table_csv, table_csv_text

#: Fewest rows of a multi-source fit (the grey-box [F1] or an ELM, ``fit.directions``).
MIN_ROWS = 20
#: Fewest points a sweep may have: Coulomb + viscous, with one point left to judge it
#: (``fit.textbook``).
MIN_SWEEP_POINTS = 3


@dataclass(frozen=True)
class Sweep:
    """A measured (or synthesized) friction sweep: velocity v and force f (section 2).

    Parameters
    ----------
    v : array_like
        Velocities (m/s), any sign.
    f : array_like
        Friction forces (N), as many as ``v``; both finite, else ``DataError``.

    Examples
    --------
    >>> from fricgen import Sweep
    >>> sweep = Sweep([-0.02, 0.0, 0.01], [-9.0, 0.0, 8.5])
    >>> len(sweep), sweep.folded().f.tolist()      # (|v|, sgn(v) f), v = 0 left out
    (3, [9.0, 8.5])
    """

    v: np.ndarray
    f: np.ndarray

    def __post_init__(self):
        v = np.asarray(self.v, dtype=float).ravel()
        f = np.asarray(self.f, dtype=float).ravel()
        if v.shape != f.shape:
            raise DataError(f"v and f must have equal lengths, got {v.size} and {f.size}")
        if not (np.all(np.isfinite(v)) and np.all(np.isfinite(f))):
            raise DataError("sweep contains NaN or infinite values")
        object.__setattr__(self, "v", v)
        object.__setattr__(self, "f", f)

    def __len__(self):
        return self.v.size

    def folded(self) -> "Sweep":
        """The symmetric fold: (|v|, sgn(v) f), so negative velocities join the positive half."""
        s = np.sign(self.v)
        keep = s != 0
        return Sweep(np.abs(self.v[keep]), (s * self.f)[keep])

    def direction(self, sign: int) -> "Sweep":
        """The rows moving in direction ``sign`` (+1: v > 0, -1: v < 0), folded onto v > 0:
        (|v|, sign f), the data of one curve of an asymmetric model."""
        keep = np.sign(self.v) == sign
        return Sweep(np.abs(self.v[keep]), sign * self.f[keep])

    def concat(self, other: "Sweep") -> "Sweep":
        return Sweep(np.concatenate([self.v, other.v]), np.concatenate([self.f, other.f]))


def read_sweep_csv(path: Union[str, Path]) -> Sweep:
    """Read a sweep CSV whose header names columns ``v`` and ``f`` (SI units; other columns ignored).

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV file.

    Returns
    -------
    Sweep
        ``DataError`` naming the row for a non-finite value, or when there are fewer than
        ``MIN_SWEEP_POINTS`` rows.

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.data import sweep_csv_text
    >>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
    >>> _ = (tmp / "sweep.csv").write_text(sweep_csv_text(sweep))
    >>> len(fricgen.read_sweep_csv(tmp / "sweep.csv")) == len(sweep)
    True
    """
    return sweep_from_columns(read_table_csv(path, ("v", "f")), path)


def sweep_from_columns(cols: Dict[str, np.ndarray], path: Union[str, Path]) -> Sweep:
    """The sweep of the columns ``v`` and ``f`` read from ``path``, checked as ``read_sweep_csv``."""
    v, f = cols["v"], cols["f"]
    bad = ~(np.isfinite(v) & np.isfinite(f))
    if bad.any():
        raise DataError(f"{path}: data row {int(np.flatnonzero(bad)[0]) + 1}: NaN or infinite value")
    if v.size < MIN_SWEEP_POINTS:
        raise DataError(f"{path}: {v.size} data rows, need at least {MIN_SWEEP_POINTS}")
    return Sweep(v, f)


def sweep_csv_text(sweep: Sweep) -> str:
    """The CSV text of a sweep: columns v,f, floats written to round-trip.

    Parameters
    ----------
    sweep : Sweep
        The sweep to write.

    Returns
    -------
    str

    Examples
    --------
    >>> from fricgen import Sweep
    >>> from fricgen.data import sweep_csv_text
    >>> sweep_csv_text(Sweep([0.5], [2.0])).splitlines()
    ['v,f', '0.5,2.0']
    """
    return table_csv_text({"v": sweep.v, "f": sweep.f})
