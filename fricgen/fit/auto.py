"""``elm_auto``: fricgen's automatic ELM, beyond the paper. No user tuning.

The hidden units are not drawn blindly (section 4) but placed where the data needs them:

1. A *dictionary* of sigmoids h(x) = sigma(s (x - c)), [F8] with w = s, b = -s c, whose
   centres c lie on a grid over the data range and whose steepness s spreads over scales
   (``steepness``, in units of 1 / data range: transitions from the whole range down to about
   1/12 of it, the Stribeck drop near v = 0), plus one constant unit (w = b = 0).
2. *Forward selection* (orthogonal least squares) orders the dictionary by how much each unit
   lowers the residual, for ``n_members`` dictionaries whose centre grids are shifted by
   fractions of the grid spacing (0, 1/2, 1/4, 3/4, ...: the first k members spread evenly).
3. *The smallest adequate model.* A candidate is the average of the first k members, each with
   its first m units; an average of ELMs is one ELM (the union of the hidden units with
   beta / k), and its leave-one-out residual is the average of the members' (PRESS, closed
   form). The model is the candidate with the fewest units whose PRESS is within
   ``tolerance_se`` standard errors of the best candidate's (the one-standard-error rule) or
   within ``resolution`` (RMS, a fraction of the largest target) of it, whichever is larger, so
   that the size follows the accuracy the data can confirm, not the amount of data: the
   standard error shrinks as 1/rows, and without the resolution a million rows would buy units
   for differences of a few thousandths of a newton. ``max_neurons`` caps the units for firmware.
4. C of [F15] is then chosen per member by leave-one-out within the float32 parity bound
   (``LeaveOneOut``); the average's float32 error is at most the largest member's.
"""
from __future__ import annotations

import time
from typing import Optional, Sequence

import numpy as np
from scipy.linalg import blas

from .._validate import integer, positive
from ..metrics import rmse
from ..networks.elm import ElmNetwork, hidden_matrix
from .base import Estimator
from .elm import SVD, LeaveOneOut, log10_cond, loo_residuals, prefix_loo_residuals


def forward_selection(D: np.ndarray, t: np.ndarray, m_max: int) -> list:
    """Columns of D in the order orthogonal least squares picks them (largest residual drop first),
    at most ``m_max`` and at most as many as D has rows.

    The residual matrix R is deflated in place (a rank-one BLAS update of its Fortran-ordered
    copy): no temporary of the size of D per step."""
    R, r = np.array(D, dtype=float, order="F"), t.astype(float).copy()
    norms = np.einsum("ij,ij->j", R, R)
    floor = 1e-8 * norms
    selected = []
    for _ in range(min(m_max, *D.shape)):       # never more columns than rows
        gain = np.where(norms > floor, (R.T @ r) ** 2 / np.maximum(norms, 1e-300), -1.0)
        gain[selected] = -1.0
        k = int(np.argmax(gain))
        if gain[k] <= 0:
            break
        q = R[:, k] / np.sqrt(norms[k])
        selected.append(k)
        R = blas.dger(-1.0, q, q @ R, a=R, overwrite_a=True)
        r -= q * (q @ r)
        norms = np.einsum("ij,ij->j", R, R)
    return selected


def sigmoid_dictionary(lo: float, hi: float, n_centres: int, steepness: Sequence[float],
                       shift: float = 0.0):
    """(w, b) of sigma(s (x - c)) for ``n_centres`` centres on a grid from 5% of the range below
    ``lo`` up to ``hi`` (shifted by ``shift`` grid spacings; the Stribeck drop starts at the
    lower end) times every steepness s / (hi - lo), plus the constant unit w = b = 0."""
    span = hi - lo
    spacing = 1.05 * span / (n_centres - 1)
    c = lo - 0.05 * span + spacing * (np.arange(n_centres) + shift)
    s = np.asarray(steepness, dtype=float) / span
    w = np.repeat(s, c.size)
    b = -w * np.tile(c, s.size)
    return np.append(w, 0.0), np.append(b, 0.0)


def van_der_corput(j: int) -> float:
    """The j-th shift in [0, 1) of the base-2 van der Corput sequence: 0, 1/2, 1/4, 3/4, 1/8, ..."""
    shift, scale = 0.0, 0.5
    while j:
        shift += scale * (j & 1)
        j >>= 1
        scale /= 2
    return shift


class AutoELMRegressor(Estimator):
    """Sigmoid ELM whose units, size M and C are chosen from the data by leave-one-out (``elm_auto``).

    Each member draws a dictionary of sigmoids sigma(s (x - c)) (``n_centres`` centres shifted per
    member, every ``steepness``), picks up to ``max_hidden`` of them by orthogonal least squares,
    and the smallest candidate within ``tolerance_se`` standard errors of the best PRESS wins; the
    members' networks are averaged into one. Fitting is deterministic. x and t are the normalized
    data of [F9].

    Parameters
    ----------
    n_members : int
        Shifted dictionaries, at most.
    n_centres : int
        Sigmoid centres per dictionary (>= 2).
    steepness : sequence of float
        The slopes s, relative to the input range.
    max_hidden : int
        Units per member, at most.
    max_beta_l1 : float, optional
        A fixed bound on ||beta||_1 of each member; None: the float32 parity bound of the
        leave-one-out solver.
    tolerance_se : float
        Standard errors of PRESS the chosen model may lie above the best.
    resolution : float
        RMS difference (a fraction of max |t|) below which candidates count as equally good.
    max_neurons : int, optional
        A cap on the units of the model (None: no cap).
    random_state : object
        Accepted for a uniform interface; unused.

    Attributes
    ----------
    network_ : ElmNetwork
        The averaged network, the AIM of [F3].
    input_weights_, biases_ : ndarray
        w and b of its units (dimensionless).
    beta_ : ndarray
        Output weights, in units of t (normalized force).
    C_ : float
        Median of the members' regularization C (dimensionless); ``member_C_``: each member's.
    member_sizes_ : ndarray of int
        Units of each member used.
    loo_rmse_ : float
        Leave-one-out RMSE of the average, in units of t.
    log10_cond_ : float
        Largest log10 cond(H^T H) among the members' solves.
    press_best_, press_se_ : float
        The best candidate's PRESS (mean squared leave-one-out residual, units of t squared) and
        its standard error.
    fit_seconds_ : float
        Wall time of ``fit`` (s).

    Notes
    -----
    Beyond the paper: it replaces the hand-picked M and C of secs. 4-5 by leave-one-out
    (PRESS) over nested subsets, solved as [F13] on each prefix.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import AutoELMRegressor
    >>> x = np.linspace(0, 1, 40)
    >>> t = 0.5 + 0.5 * np.exp(-(x / 0.2) ** 2)      # [F1] shape, normalized
    >>> elm = AutoELMRegressor(max_neurons=6).fit(x, t)
    >>> bool(elm.beta_.size <= 6), bool(elm.loo_rmse_ < 0.01)
    (True, True)
    """

    activation = "sigmoid"
    scheme = "auto"

    def __init__(self, n_members: int = 8, n_centres: int = 16,
                 steepness: Sequence[float] = (3.0, 6.0, 12.0, 24.0, 48.0),
                 max_hidden: int = 30, max_beta_l1: Optional[float] = None,
                 tolerance_se: float = 1.0, resolution: float = 2e-4,
                 max_neurons: Optional[int] = None, random_state=None):
        self.n_members = n_members
        self.n_centres = n_centres
        self.steepness = steepness
        self.max_hidden = max_hidden
        self.max_beta_l1 = max_beta_l1
        self.tolerance_se = tolerance_se
        self.resolution = resolution
        self.max_neurons = max_neurons
        self.random_state = random_state   # accepted for a uniform interface; fit is deterministic

    def _check(self):
        integer("n_members", self.n_members)
        integer("max_hidden", self.max_hidden)
        integer("n_centres", self.n_centres, minimum=2)
        if len(self.steepness) == 0:
            raise ValueError("steepness must hold at least one scale")
        for s in self.steepness:
            positive("steepness", s)
        if self.max_beta_l1 is not None:
            positive("max_beta_l1", self.max_beta_l1)
        for name in ("tolerance_se", "resolution"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and 0 <= value < np.inf):
                raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
        if self.max_neurons is not None:
            integer("max_neurons", self.max_neurons)

    def _members(self, x, t):
        """Per member: dictionary (w, b), the selection order and the leave-one-out residuals
        (pseudo-inverse, n x len(order)) of each prefix of it."""
        members = []
        for j in range(int(self.n_members)):
            w, b = sigmoid_dictionary(x.min(), x.max(), int(self.n_centres), self.steepness,
                                      van_der_corput(j))
            D = hidden_matrix("sigmoid", x, w, b)
            order = forward_selection(D, t, int(self.max_hidden))
            res = prefix_loo_residuals(D[:, order], t)
            members.append((w, b, D, order, res))
        return members

    def _choose(self, members, n, scale):
        """(k members, m units each) of the smallest candidate within tolerance of the best."""
        ids = {}   # unit (w, b) -> one id: the constant unit is shared by every member
        for w, b, _, order, _ in members:
            for i in order:
                ids.setdefault((w[i], b[i]), len(ids))
        unit_ids = [[ids[(w[i], b[i])] for i in order] for w, b, _, order, _ in members]
        cands, total = [], None
        m_max = len(members[0][3])
        for k, (_, _, _, order, res) in enumerate(members, start=1):
            m_max = min(m_max, len(order))
            total = res[:, :m_max].copy() if total is None else total[:, :m_max] + res[:, :m_max]
            sq = (total / k) ** 2
            press, se = sq.mean(axis=0), sq.std(axis=0) / np.sqrt(n)
            seen = set()                  # the distinct units of the first k members' first m
            for m in range(1, m_max + 1):
                seen.update(member[m - 1] for member in unit_ids[:k])
                cands.append((len(seen), press[m - 1], se[m - 1], k, m))
        cap = self.max_neurons
        allowed = [c for c in cands if cap is None or c[0] <= cap]
        best = min(allowed, key=lambda c: c[1])
        limit = best[1] + max(float(self.tolerance_se) * best[2], (self.resolution * scale) ** 2)
        chosen = min((c for c in allowed if c[1] <= limit), key=lambda c: (c[0], c[1]))
        return best, chosen

    def fit(self, x, t) -> "AutoELMRegressor":
        self._check()
        x, t = self._inputs(x, t)
        if x.size < 3:
            raise ValueError(f"x and t must have one equal length >= 3, got {x.size}, {t.size}")
        if not np.ptp(x) > 0:
            raise ValueError("x must span a range")
        start = time.perf_counter()
        members = self._members(x, t)
        best, (_, _, _, k, m) = self._choose(members, t.size, float(np.max(np.abs(t))))
        solver = LeaveOneOut(max_beta_l1=self.max_beta_l1)
        units, Cs, conds, loo = {}, [], [], np.zeros_like(t)
        for w, b, D, order, _ in members[:k]:
            keep = order[:m]
            svd = SVD.of(D[:, keep])
            C = solver.choose_C(svd, t)
            for wk, bk, betak in zip(w[keep], b[keep], svd.solve(t, C)):
                units[(wk, bk)] = units.get((wk, bk), 0.0) + betak / k
            Cs.append(C)
            conds.append(log10_cond(svd.s, n_hidden=m))
            loo += loo_residuals(svd, t, C) / k   # LOO residual of an average = average of the LOO residuals
        keys = sorted(units)
        w = np.array([key[0] for key in keys])
        b = np.array([key[1] for key in keys])
        self.beta_ = np.array([units[key] for key in keys])
        self.network_ = ElmNetwork("sigmoid", w, b, self.beta_)
        self.input_weights_, self.biases_ = w, b
        self.member_C_ = np.array(Cs)
        self.C_ = float(np.median(self.member_C_))
        self.member_sizes_ = np.full(k, m)
        self.press_best_, self.press_se_ = float(best[1]), float(best[2])
        self.loo_rmse_ = rmse(loo, 0.0)
        self.log10_cond_ = float(max(conds))
        self.fit_seconds_ = time.perf_counter() - start
        return self

    @property
    def n_hidden(self) -> int:
        """Hidden units of the fitted network (the union over members)."""
        return self.network_.n_hidden

    @property
    def beta_norm_(self) -> float:
        """||beta||, the size of the output weights."""
        return float(np.linalg.norm(self.beta_))
