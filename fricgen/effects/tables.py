"""Nonparametric corrections: a force tabulated along one signal, for residual structure that no
named effect explains. They carry no physical name: ``table_position`` is "a force that depends
on x", nothing more.

A table holds ``values`` at equally spaced knots from ``lo`` to ``hi`` and is interpolated
linearly between them (constant beyond the ends). Its smoothness (a penalty on second
differences) is chosen by blocked cross-validation when it is fitted. The position tables sit
on a finer grid and penalize the absolute second differences (trend filtering): the fit is
straight wherever the data allows and bends only at the few knots where it needs to, so a
tight spot over 2 % of the travel is followed without noise elsewhere. The kinds:

- ``table_position``: T(x), an additive force that acts at rest too;
- ``table_position_friction``: sgn(v) T(x), a friction level that changes along the travel;
- ``table_velocity``: T(v), a correction of the friction curve;
- ``table_time``: T(t), an additive force that changes over the log (not emitted to C).

The C form is the same interpolation in float32 (``force_f32`` mirrors it operation by
operation); the table is a ``static const`` array inside NAME_force_xv.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Dict, List, Tuple

import numpy as np
from scipy.linalg import solveh_banded

from ..c_literal import c_float
from .._validate import finite_number
from ..errors import ModelError
from .base import Effect
from .carried import KNOWN

#: Knots of a fitted table.
KNOTS = 48
#: Knots of a fitted position table (sparse kinks: a bend where the data needs one).
FINE_KNOTS = 192
#: Reweighted solves of the absolute second-difference penalty.
KINK_ITERATIONS = 12
#: Most knots a table in model.json may hold.
MAX_KNOTS = 256
#: Second-difference penalties tried by the cross-validation (relative to trace(H^T H) / K).
PENALTIES = 10.0 ** np.arange(-6.0, 3.5, 1.0)


def _positions(u, lo: float, hi: float, knots: int):
    """Knot index k and fraction of each u (clamped to [lo, hi]) for linear interpolation."""
    pos = np.clip((np.asarray(u, dtype=float) - lo) * ((knots - 1) / (hi - lo)), 0.0, knots - 1)
    k = np.minimum(pos.astype(np.intp), knots - 2)
    return k, pos - k


def hat_basis_at_rows(problem, coord: np.ndarray, lo: float, hi: float, knots: int, rows,
                      weight=None) -> np.ndarray:
    """The interpolation basis of ``coord`` (full rate, optionally times ``weight``) smoothed
    with the residual's filter at ``rows``: an (n, knots) array, built sparsely (two knots per
    sample), so memory stays n x knots at any window length."""
    rows = np.asarray(rows)
    idx = problem.rows[rows][:, None] + problem.offsets
    k, frac = _positions(coord[idx], lo, hi, knots)
    c = np.broadcast_to(problem.coeffs, idx.shape)
    if weight is not None:
        c = c * weight[idx]
    line = np.repeat(np.arange(rows.size) * knots, idx.shape[1]).reshape(idx.shape)
    out = np.bincount((line + k).ravel(), weights=(c * (1.0 - frac)).ravel(), minlength=rows.size * knots)
    out += np.bincount((line + k + 1).ravel(), weights=(c * frac).ravel(), minlength=rows.size * knots)
    return out.reshape(rows.size, knots)


def _bands(M: np.ndarray, u: int) -> np.ndarray:
    """The upper bands of symmetric ``M`` (u above the diagonal), as ``solveh_banded`` reads them."""
    ab = np.zeros((u + 1, M.shape[0]))
    for k in range(u + 1):
        ab[u - k, k:] = np.diagonal(M, k)
    return ab


def _weighted_differences(w: np.ndarray, u: int) -> np.ndarray:
    """The upper bands of D^T diag(w) D, D the second differences (pentadiagonal), in O(knots)."""
    n = w.size + 2
    wp = np.concatenate([[0.0, 0.0], w, [0.0, 0.0]])
    ab = np.zeros((u + 1, n))
    ab[u] = wp[2:] + 4.0 * wp[1:-1] + wp[:-2]
    ab[u - 1, 1:] = -2.0 * (wp[2:-1] + wp[1:-2])
    ab[u - 2, 2:] = wp[2:-2]
    return ab


def _penalized(A, b, penalty, kinks: bool) -> np.ndarray:
    """argmin |r - H c|^2 + penalty (c^T D^T D c, or with ``kinks`` the absolute second
    differences: reweighted least squares, each weight 1 / |D c| of the previous solve, scaled
    so that the first solve is the quadratic one), from A = H^T H + ridge and b = H^T r, given
    as its upper bands (``_bands``): banded Cholesky solves."""
    u = A.shape[0] - 1
    c = solveh_banded(A + penalty * _weighted_differences(np.ones(b.size - 2), u), b)
    if not kinks:
        return c
    d = np.abs(np.diff(c, 2))
    typical = float(np.mean(d)) + 1e-300
    for _ in range(KINK_ITERATIONS):
        w = typical / np.maximum(d, 1e-3 * typical)
        c = solveh_banded(A + penalty * _weighted_differences(w, u), b)
        d = np.abs(np.diff(c, 2))
    return c


def smooth_table(H: np.ndarray, r: np.ndarray, folds: int = 5, kinks: bool = False) -> Tuple[np.ndarray, float]:
    """Table values for basis ``H`` and target ``r``: penalized least squares whose penalty is
    chosen by blocked ``folds``-fold cross-validation, on the squared second differences or
    (``kinks``) their absolute values. Returns the values and the penalty."""
    knots = H.shape[1]
    HtH, Htr = H.T @ H, H.T @ r
    scale = float(np.trace(HtH)) / knots + 1e-300
    ridge = 1e-9 * scale * np.eye(knots)        # knots no sample reaches stay defined
    # H^T H is banded (a smoothed sample reaches the knots its window spans), so are the folds'
    i, j = np.nonzero(HtH)
    u = max(2, int(np.max(j - i, initial=0)))
    blocks = np.array_split(np.arange(r.size), folds)
    # each fold's normal equations: all rows' less the block's
    normal = [(_bands(HtH + ridge - H[b].T @ H[b], u), Htr - H[b].T @ r[b]) for b in blocks]
    best, best_err = PENALTIES[0], math.inf
    for lam in PENALTIES:
        err = 0.0
        for b, (A, rhs) in zip(blocks, normal):
            c = _penalized(A, rhs, lam * scale, kinks)
            err += float(np.sum((r[b] - H[b] @ c) ** 2))
        if err < best_err:
            best, best_err = lam, err
    return _penalized(_bands(HtH + ridge, u), Htr, best * scale, kinks), float(best)


@dataclass(frozen=True)
class TableEffect(Effect):
    """Base of the tables: ``values`` at ``len(values)`` equally spaced knots on [lo, hi],
    interpolated linearly and held at the end values outside.

    Parameters
    ----------
    lo, hi : float
        The range of the table's signal (its unit: m for position, m/s for velocity, s for time).
    values : tuple of float
        The force (N) or the friction level at each knot.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals, TABLES
    >>> table = TABLES["table_position"](lo=0.0, hi=1.0, values=(0.0, 4.0))
    >>> table.force(Signals(preset("paper3"), x=np.array([0.25, 2.0]), v=np.ones(2))).tolist()
    [1.0, 4.0]
    """

    lo: float
    hi: float
    values: Tuple[float, ...]
    #: The signal the table reads (an attribute of ``Signals``) and the word for it.
    signal: ClassVar[str] = ""
    #: Multiplied by sgn(v): a friction level rather than an additive force.
    signed: ClassVar[bool] = False
    #: Knots of a fitted table, and whether it bends only where the data needs (``smooth_table``).
    knots: ClassVar[int] = KNOTS
    kinks: ClassVar[bool] = False

    @property
    def n_params(self) -> int:
        return len(self.values)

    def parameters(self) -> Dict[str, Any]:
        return {"lo": self.lo, "hi": self.hi, "values": list(self.values)}

    def _coord(self, sig):
        return np.asarray(getattr(sig, self.signal), dtype=float)

    def force(self, sig):
        u = self._coord(sig)
        k, frac = _positions(u, self.lo, self.hi, len(self.values))
        t = np.asarray(self.values)
        out = t[k] + frac * (t[k + 1] - t[k])
        return np.sign(np.asarray(sig.v)) * out if self.signed else out

    @classmethod
    def fit(cls, problem, rows) -> "TableEffect":
        sig = problem.signals
        coord = np.asarray(getattr(sig, cls.signal), dtype=float)
        inside = coord[problem.rows[rows]]
        lo, hi = float(np.min(inside)), float(np.max(inside))
        if not hi > lo:
            hi = lo + 1.0
        weight = np.sign(sig.v) if cls.signed else None
        H = hat_basis_at_rows(problem, coord, lo, hi, cls.knots, rows, weight)
        values, _ = smooth_table(H, problem.target[rows], kinks=cls.kinks)
        return cls(lo=lo, hi=hi, values=tuple(float(c) for c in values))

    @classmethod
    def from_dict(cls, d: dict) -> "TableEffect":
        params, where = cls.parameters_of(d, ("lo", "hi", "values"))
        for key in ("lo", "hi"):
            value = params.get(key)
            if not finite_number(value):
                raise ModelError(f"{where}.parameters.{key} must be a finite number, got {value!r}"[:200])
        if not params["hi"] > params["lo"]:
            raise ModelError(f"{where}.parameters: hi must be > lo, got lo {params['lo']}, hi {params['hi']}")
        values = params.get("values")
        if (not isinstance(values, list) or not 2 <= len(values) <= MAX_KNOTS
                or not all(finite_number(c) for c in values)):
            raise ModelError(f"{where}.parameters.values must be a list of 2 to {MAX_KNOTS} finite numbers")
        return cls(lo=float(params["lo"]), hi=float(params["hi"]), values=tuple(float(c) for c in values))

    # C: the table is a static const array named by the caller, read by NAME_interp
    c_variable: ClassVar[str] = ""

    def c_declaration(self, symbol: str) -> str:
        body = ", ".join(c_float(c) for c in self.values)
        return f"static const float {symbol}[{len(self.values)}] = {{{body}}};"

    def c_call(self, symbol: str, interp: str) -> str:
        call = (f"{interp}({symbol}, {len(self.values)}, {c_float(self.lo)}, "
                f"{c_float((len(self.values) - 1) / (self.hi - self.lo))}, {self.c_variable})")
        return f"sgn * {call}" if self.signed else call

    def force_f32(self, v, x, base):
        """Float32 mirror of the emitted interpolation (NAME_interp)."""
        f32 = np.float32
        u = np.asarray(v if self.c_variable == "v" else x, dtype=f32)
        t = np.asarray(self.values, dtype=f32)
        n = t.size
        pos = (u - f32(self.lo)) * f32((n - 1) / (self.hi - self.lo))
        inside = (pos > f32(0)) & (pos < f32(n - 1))
        k = np.where(inside, pos, f32(0)).astype(np.intp)
        k = np.minimum(k, n - 2)
        frac = pos - k.astype(f32)
        mid = t[k] + frac * (t[k + 1] - t[k])
        out = np.where(inside, mid, np.where(pos >= f32(n - 1), t[n - 1], t[0])).astype(f32)
        out = np.where(np.isnan(u), u, out).astype(f32)
        if self.signed:
            sgn = np.where(v > 0, f32(1), np.where(v < 0, f32(-1), f32(0))).astype(f32)
            out = sgn * out
        return out


@dataclass(frozen=True)
class TablePosition(TableEffect):
    """An additive force tabulated along the position x."""

    name: ClassVar[str] = "table_position"
    signal: ClassVar[str] = "x"
    in_xv: ClassVar[bool] = True
    acts_at_rest: ClassVar[bool] = True
    c_variable: ClassVar[str] = "x"
    knots: ClassVar[int] = FINE_KNOTS
    kinks: ClassVar[bool] = True


@dataclass(frozen=True)
class TablePositionFriction(TableEffect):
    """A friction level tabulated along the position x: sgn(v) T(x)."""

    name: ClassVar[str] = "table_position_friction"
    signal: ClassVar[str] = "x"
    signed: ClassVar[bool] = True
    in_xv: ClassVar[bool] = True
    acts_at_rest: ClassVar[bool] = True       # the simulation reads x only in external forces
    c_variable: ClassVar[str] = "x"
    knots: ClassVar[int] = FINE_KNOTS
    kinks: ClassVar[bool] = True


@dataclass(frozen=True)
class TableVelocity(TableEffect):
    """A correction of the friction curve tabulated along the velocity v."""

    name: ClassVar[str] = "table_velocity"
    signal: ClassVar[str] = "v"
    in_xv: ClassVar[bool] = True
    c_variable: ClassVar[str] = "v"


@dataclass(frozen=True)
class TableTime(TableEffect):
    """An additive force tabulated along the time t of the log (not a function of v and x)."""

    name: ClassVar[str] = "table_time"
    signal: ClassVar[str] = "t"
    acts_at_rest: ClassVar[bool] = True


def range_notes(effects, signals) -> List[str]:
    """One line per table whose signal along ``signals`` leaves the table's range on more than 1 %
    of the samples: there it holds its end values.

    Parameters
    ----------
    effects : iterable of Effect
        The effects (tables among them).
    signals : MotionLog or Signals
        The samples.

    Returns
    -------
    list of str

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals, TABLES, range_notes
    >>> table = TABLES["table_position"](lo=0.0, hi=0.1, values=(0.0, 4.0))
    >>> range_notes([table], Signals(preset("paper3"), x=np.array([0.0, 0.25]), v=np.ones(2)))
    ["50% of the log's x lies outside table_position's range [0, 0.1], where the table holds its end values"]
    """
    notes = []
    for e in effects:
        if isinstance(e, TableEffect):
            u = e._coord(signals)
            out = float(np.mean((u < e.lo) | (u > e.hi))) if u.size else 0.0
            if out > 0.01:
                notes.append(f"{out:.0%} of the log's {e.signal} lies outside {e.name}'s range "
                             f"[{e.lo:.4g}, {e.hi:.4g}], where the table holds its end values")
    return notes


#: The tables, by name.
TABLES = {cls.name: cls for cls in (TablePosition, TablePositionFriction, TableVelocity, TableTime)}
KNOWN.update(TABLES)
