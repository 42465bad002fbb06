"""``elm_auto``: fricgen's automatic ELM, beyond the paper. No user tuning.

The hidden units are not drawn blindly (section 4) but placed where the data needs them:

1. A *dictionary* of sigmoids h(x) = sigma(s (x - c)), eq. (8) with w = s, b = -s c, whose
   centres c lie on a grid over the data range and whose steepness s spreads over scales
   (``steepness``, in units of 1 / data range: transitions from the whole range down to about
   1/12 of it, the Stribeck drop near v = 0), plus one constant unit (w = b = 0).
2. *Forward selection* (orthogonal least squares) orders the dictionary by how much each unit
   lowers the residual; the number of units M is the prefix with the smallest closed-form
   leave-one-out error (PRESS), and C of eq. (15) is then chosen by leave-one-out with
   ||beta||_1 bounded (``LeaveOneOut``), so float32 firmware stays within eps32 ||beta||_1.
3. Steps 1-2 run for ``n_members`` dictionaries whose centre grids are shifted by fractions of
   the grid spacing; the model is the average of the members. An average of ELMs is one ELM
   (the union of the hidden units with beta / n_members), and ||beta||_1 of the average is at
   most the largest member's, so the float32 bound holds for the result.
"""
from __future__ import annotations

import time
from typing import Sequence

import numpy as np

from .._validate import integer, positive
from ..metrics import rmse
from ..networks.elm import ElmNetwork, hidden_matrix
from .base import Estimator
from .elm import SVD, LeaveOneOut, log10_cond, loo_residuals


def forward_selection(D: np.ndarray, t: np.ndarray, m_max: int) -> list:
    """Columns of D in the order orthogonal least squares picks them (largest residual drop first)."""
    R, r = D.copy(), t.astype(float).copy()
    norms = np.einsum("ij,ij->j", R, R)
    floor = 1e-8 * norms
    selected = []
    for _ in range(min(m_max, D.shape[1])):
        gain = np.where(norms > floor, (R.T @ r) ** 2 / np.maximum(norms, 1e-300), -1.0)
        gain[selected] = -1.0
        k = int(np.argmax(gain))
        if gain[k] <= 0:
            break
        q = R[:, k] / np.sqrt(norms[k])
        selected.append(k)
        R -= np.outer(q, q @ R)
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


class AutoELMRegressor(Estimator):
    """Sigmoid ELM whose units, size M and C are chosen from the data by leave-one-out.

    Parameters (defaults need no tuning): ``n_members`` shifted dictionaries averaged,
    ``n_centres`` centres per dictionary, ``steepness`` scales, ``max_hidden`` units per member,
    ``max_beta_l1`` the bound on ||beta||_1 of each member. After ``fit``: ``network_``,
    ``beta_``, ``C_`` (median of the members' C), ``member_C_``, ``member_sizes_``,
    ``loo_rmse_`` (leave-one-out error of the average for the selected units),
    ``log10_cond_`` (largest log10 cond(H^T H) among the members' solves), ``fit_seconds_``.
    """

    activation = "sigmoid"
    scheme = "auto"

    def __init__(self, n_members: int = 8, n_centres: int = 16,
                 steepness: Sequence[float] = (3.0, 6.0, 12.0, 24.0, 48.0),
                 max_hidden: int = 30, max_beta_l1: float = 100.0, random_state=None):
        self.n_members = n_members
        self.n_centres = n_centres
        self.steepness = steepness
        self.max_hidden = max_hidden
        self.max_beta_l1 = max_beta_l1
        self.random_state = random_state   # accepted for a uniform interface; fit is deterministic

    def _check(self):
        integer("n_members", self.n_members)
        integer("max_hidden", self.max_hidden)
        integer("n_centres", self.n_centres, minimum=2)
        if len(self.steepness) == 0:
            raise ValueError("steepness must hold at least one scale")
        for s in self.steepness:
            positive("steepness", s)
        positive("max_beta_l1", self.max_beta_l1)

    def _member(self, x, t, w, b):
        D = hidden_matrix("sigmoid", x, w, b)
        order = forward_selection(D, t, int(self.max_hidden))
        press = [np.mean(loo_residuals(SVD.of(D[:, order[:m]]), t, np.inf) ** 2)
                 for m in range(1, len(order) + 1)]
        keep = order[:int(np.argmin(press)) + 1]
        svd = SVD.of(D[:, keep])
        C = LeaveOneOut(max_beta_l1=self.max_beta_l1).choose_C(svd, t)
        return w[keep], b[keep], svd.solve(t, C), C, svd, loo_residuals(svd, t, C)

    def fit(self, x, t) -> "AutoELMRegressor":
        self._check()
        x, t = self._inputs(x, t)
        if x.size < 3:
            raise ValueError(f"x and t must have one equal length >= 3, got {x.size}, {t.size}")
        if not np.ptp(x) > 0:
            raise ValueError("x must span a range")
        start = time.perf_counter()
        K = int(self.n_members)
        units, Cs, conds, sizes, loo = {}, [], [], [], np.zeros_like(t)
        for j in range(K):
            w0, b0 = sigmoid_dictionary(x.min(), x.max(), int(self.n_centres), self.steepness, j / K)
            w, b, beta, C, svd, res = self._member(x, t, w0, b0)
            for wk, bk, betak in zip(w, b, beta):
                units[(wk, bk)] = units.get((wk, bk), 0.0) + betak / K
            Cs.append(C)
            conds.append(log10_cond(svd.s, n_hidden=w.size))
            sizes.append(w.size)
            loo += res / K      # LOO residual of an average = average of the LOO residuals
        keys = sorted(units)
        w = np.array([k[0] for k in keys])
        b = np.array([k[1] for k in keys])
        self.beta_ = np.array([units[k] for k in keys])
        self.network_ = ElmNetwork("sigmoid", w, b, self.beta_)
        self.input_weights_, self.biases_ = w, b
        self.member_C_ = np.array(Cs)
        self.C_ = float(np.median(self.member_C_))
        self.member_sizes_ = np.array(sizes)
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
