"""The fuzzy baseline of section 3: first-order Takagi-Sugeno ANFIS for one input.

Initialization follows MATLAB's ``genfis1`` (grid partition of [min x, max x] into ``n_mfs``
membership functions, centres ``linspace(min, max, n)``, half-width a = (max - min) / (2 (n - 1));
generalized bell MFs [a, b = 2, c], Gaussian MFs sigma = a / sqrt(2 ln 2); consequents zero).
Training is the ANFIS hybrid rule: each epoch solves the linear consequents by least squares,
then moves the premise parameters by a gradient step of fixed length ``step`` (the normalized
gradient), growing the step by 10% after four consecutive error decreases and shrinking it by
10% after two down/up alternations; the parameters of the best epoch are kept.
"""
from __future__ import annotations

import time

import numpy as np

from .._validate import integer, positive
from ..metrics import rmse
from .base import Estimator
from ..networks.anfis import TINY, AnfisNetwork, check_mf

def genfis1(x, n_mfs: int, mf: str = "bell") -> AnfisNetwork:
    """The initial system of MATLAB ``genfis1``: grid partition of [min x, max x], zero consequents."""
    check_mf(mf)
    if int(n_mfs) != n_mfs or n_mfs < 2:
        raise ValueError(f"n_mfs must be an integer >= 2, got {n_mfs}")
    x = np.asarray(x, dtype=float).ravel()
    lo, hi = float(x.min()), float(x.max())
    if not hi > lo:
        raise ValueError(f"x must span a range, got min = max = {lo}")
    n = int(n_mfs)
    centers = np.linspace(lo, hi, n)
    a = (hi - lo) / (2.0 * (n - 1))
    if mf == "bell":
        widths, exponents = np.full(n, a), np.full(n, 2.0)
    else:
        widths, exponents = np.full(n, a / np.sqrt(2.0 * np.log(2.0))), None
    return AnfisNetwork(mf, centers, widths, exponents, np.zeros(n), np.zeros(n))


def _premise_gradient(net: AnfisNetwork, x, err, f, y, S, mu):
    """dE/d(premise) for E = sum err^2: one array per premise parameter kind."""
    common = 2.0 * err[:, None] * (f - y[:, None]) / S[:, None]      # dE/dmu_j, N x n
    c, w = net.centers[None, :], net.widths[None, :]
    d = x[:, None] - c
    if net.mf == "gauss":
        dmu_dc = mu * d / w ** 2
        dmu_ds = mu * d * d / w ** 3
        return [np.sum(common * dmu_dc, 0), np.sum(common * dmu_ds, 0)]
    b = net.exponents[None, :]
    u = d / w
    au = np.maximum(np.abs(u), TINY)
    q = au ** (2.0 * b)
    dmu_dq = -mu * mu
    dq_du = 2.0 * b * np.sign(u) * au ** (2.0 * b - 1.0)
    dq_da = dq_du * (-u / w)
    dq_db = np.where(np.abs(u) > TINY, q * 2.0 * np.log(au), 0.0)
    dq_dc = dq_du * (-1.0 / w)
    return [np.sum(common * dmu_dq * dq_dc, 0), np.sum(common * dmu_dq * dq_da, 0),
            np.sum(common * dmu_dq * dq_db, 0)]


class AnfisRegressor(Estimator):
    r"""The fuzzy baseline of sec. 3: first-order Takagi-Sugeno ANFIS for one input, with MATLAB
    ``genfis1`` initialization and hybrid learning.

    Parameters
    ----------
    n_mfs : int
        Membership functions over the input (the paper chose 4).
    mf : {"bell", "gauss"}
        Their kind.
    epochs : int
        Training epochs.
    step : float
        Initial step length of the premise gradient step.
    step_increase, step_decrease : float
        MATLAB's step factors (1.1 after four decreases of the error, 0.9 after two alternations).

    Attributes
    ----------
    network_ : AnfisNetwork
        The system of the best epoch, the AIM of [F3].
    train_rmse_ : ndarray, shape (epochs,)
        Training RMSE per epoch (units of t, normalized force).
    best_epoch_ : int
        The epoch of ``network_``.
    step_sizes_ : ndarray
        Step length per epoch.
    n_parameters_ : int
        Consequent plus premise parameters.
    fit_seconds_ : float
        Wall time of ``fit`` (s).

    Notes
    -----
    Rule i: if x is A_i then :math:`y_i = p_i x + r_i`; the output is
    :math:`\sum_i \bar w_i y_i` with normalized firing strengths; consequents by least squares,
    premises by gradient descent.

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen.fit import AnfisRegressor
    >>> x = np.linspace(0, 1, 40)
    >>> anfis = AnfisRegressor(epochs=20).fit(x, 0.5 + 0.5 * np.exp(-(x / 0.2) ** 2))
    >>> anfis.train_rmse_.shape, anfis.n_parameters_
    ((20,), 20)
    """

    def __init__(self, n_mfs: int = 4, mf: str = "bell", epochs: int = 100, step: float = 0.01,
                 step_increase: float = 1.1, step_decrease: float = 0.9):
        self.n_mfs = n_mfs
        self.mf = mf
        self.epochs = epochs
        self.step = step
        self.step_increase = step_increase
        self.step_decrease = step_decrease

    def _consequents(self, net, x, t):
        wbar = net.firing(x)
        A = np.hstack([wbar * x[:, None], wbar])
        coef, *_ = np.linalg.lstsq(A, t, rcond=None)
        n = net.n_mfs
        return AnfisNetwork(net.mf, net.centers, net.widths, net.exponents, coef[:n], coef[n:])

    def fit(self, x, t) -> "AnfisRegressor":
        integer("epochs", self.epochs)
        positive("step", self.step)
        x, t = self._inputs(x, t)
        if x.size != t.size or x.size == 0:
            raise ValueError(f"x and t must have one equal, non-zero length, got {x.size}, {t.size}")
        start = time.perf_counter()
        net = genfis1(x, self.n_mfs, self.mf)
        step = float(self.step)
        history, steps = [], []
        best, best_err, best_epoch = None, np.inf, 0
        for epoch in range(int(self.epochs)):
            net = self._consequents(net, x, t)                      # forward pass: LS
            mu = net.memberships(x)
            S = np.maximum(mu.sum(axis=1), TINY)
            f = x[:, None] * net.slopes + net.intercepts
            y = np.sum(mu / S[:, None] * f, axis=1)
            err = y - t
            history.append(rmse(y, t))
            steps.append(step)
            if history[-1] < best_err:
                best, best_err, best_epoch = net, history[-1], epoch
            if epoch == int(self.epochs) - 1:
                break
            step = self._adapt_step(step, history)
            grads = _premise_gradient(net, x, err, f, y, S, mu)  # backward pass: premises
            norm = np.sqrt(sum(float(np.sum(g * g)) for g in grads))
            if not norm > 0:
                break
            eta = step / norm
            centers = net.centers - eta * grads[0]
            widths = np.maximum(np.abs(net.widths - eta * grads[1]), 1e-6)
            exponents = None
            if net.mf == "bell":
                exponents = np.maximum(np.abs(net.exponents - eta * grads[2]), 1e-3)
            net = AnfisNetwork(net.mf, centers, widths, exponents, net.slopes, net.intercepts)
        self.network_ = best
        self.train_rmse_ = np.array(history)
        self.step_sizes_ = np.array(steps)
        self.best_epoch_ = best_epoch
        self.fit_seconds_ = time.perf_counter() - start
        return self

    def _adapt_step(self, step: float, history) -> float:
        """MATLAB's rule: x1.1 after 4 consecutive decreases, x0.9 after down/up/down/up."""
        if len(history) < 5:
            return step
        down = [b < a for a, b in zip(history[-5:-1], history[-4:])]
        if all(down):
            return step * self.step_increase
        if down in ([True, False, True, False], [False, True, False, True]):
            return step * self.step_decrease
        return step


    @property
    def n_parameters_(self) -> int:
        """Linear (consequent) plus nonlinear (premise) parameters: 2n + 3n (bell), 2n + 2n (gauss)."""
        return self.network_.n_mfs * (5 if self.mf == "bell" else 4)
