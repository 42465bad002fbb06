"""Extreme Learning Machines, [F7]-[F17]: hidden-layer schemes x activations x solvers.

A model is assembled from three interchangeable parts: a hidden-layer *scheme* that draws the
input weights w and biases b, an *activation* applied to z = w x + b, and a *solver* for the
output weights beta. All solvers work from one SVD of the hidden-layer matrix H [F11].
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple, Optional, Sequence, Tuple

import numpy as np

from .._validate import integer, positive
from ..metrics import rmse
from ..networks.elm import ElmNetwork, check_activation, hidden_matrix
from .base import Estimator, as_rng


# ----------------------------------------------------------------------------- schemes


def _logit(r: float) -> float:
    return float(np.log(r / (1.0 - r)))


@dataclass(frozen=True)
class StandardScheme:
    """The standard ELM draw: w and b uniform in [low, high] (section 4, [-1, 1])."""

    low: float = -1.0
    high: float = 1.0

    def draw(self, n: int, rng: np.random.Generator) -> Tuple[np.ndarray, np.ndarray]:
        return rng.uniform(self.low, self.high, n), rng.uniform(self.low, self.high, n)


@dataclass(frozen=True)
class EnlargedScheme:
    """Enlarged variability, [F16]-[F17]: w uniform in [-w_max, w_max]; b such that each
    sigmoid falls below r1 at one end of the input interval [0, 1] and rises above r2 at the other.

    For w > 0, (16) reads sigma(b) < r1 and sigma(w + b) > r2, so b is uniform in
    [logit(r2) - w, logit(r1)]; for w < 0 the roles of the ends swap: b in [logit(r2),
    logit(r1) - w]. (The extraction of [F17] prints ln(1/r2 - 1) = -logit(r2) in the lower
    bound, a sign slip: that bound only guarantees sigma(w + b) > 1 - r2.) The interval is empty
    when |w| < logit(r2) - logit(r1); such w are redrawn, so w is uniform over the feasible part
    of [-w_max, w_max].
    """

    w_max: float = 10.0
    r1: float = 0.1
    r2: float = 0.9

    def __post_init__(self):
        if not 0.0 < self.r1 < self.r2 < 1.0:
            raise ValueError(f"need 0 < r1 < r2 < 1, got r1={self.r1}, r2={self.r2}")
        if self.w_max <= _logit(self.r2) - _logit(self.r1):
            raise ValueError(f"w_max={self.w_max} too small for r1={self.r1}, r2={self.r2}: "
                             f"need w_max > {_logit(self.r2) - _logit(self.r1):.3f}")

    def draw(self, n: int, rng: np.random.Generator) -> Tuple[np.ndarray, np.ndarray]:
        lo1, lo2 = _logit(self.r1), _logit(self.r2)
        w_min = lo2 - lo1
        magnitude = rng.uniform(w_min, self.w_max, n)
        sign = np.where(rng.uniform(size=n) < 0.5, -1.0, 1.0)
        w = sign * magnitude
        low = np.where(w > 0, lo2 - w, lo2)
        high = np.where(w > 0, lo1, lo1 - w)
        return w, rng.uniform(low, high)


@dataclass(frozen=True)
class FixedScheme:
    """Given hidden parameters (used by conditioning optimization and for refits)."""

    input_weights: Sequence[float]
    biases: Sequence[float]

    def draw(self, n: int, rng: np.random.Generator) -> Tuple[np.ndarray, np.ndarray]:
        w, b = np.asarray(self.input_weights, float), np.asarray(self.biases, float)
        if w.size != n or b.size != n:
            raise ValueError(f"fixed scheme holds {w.size} neurons, asked for {n}")
        return w.copy(), b.copy()


SCHEMES = {"standard": StandardScheme, "enlarged": EnlargedScheme}


# ----------------------------------------------------------------------------- solvers


class HiddenLayer(NamedTuple):
    """The drawn hidden layer and the training inputs: what a solver needs to evaluate the
    network as float32 firmware would."""

    activation: str
    w: np.ndarray
    b: np.ndarray
    x: np.ndarray


def pinv_cutoff(s: np.ndarray, shape) -> float:
    """Singular values of an n x m matrix up to this are treated as 0 by the pseudo-inverse."""
    return float(s.max(initial=0.0) * max(shape) * np.finfo(float).eps)


class SVD(NamedTuple):
    """Thin SVD of H = U diag(s) V^T."""

    U: np.ndarray
    s: np.ndarray
    Vt: np.ndarray

    @classmethod
    def of(cls, H: np.ndarray) -> "SVD":
        U, s, Vt = np.linalg.svd(H, full_matrices=False)
        return cls(U, s, Vt)

    def filter_factors(self, C: float) -> np.ndarray:
        """Ridge filter s / (s^2 + 1/C) per singular value; C = inf is the pseudo-inverse."""
        if np.isinf(C):
            keep = self.s > pinv_cutoff(self.s, self.U.shape)
            return np.where(keep, 1.0 / np.where(keep, self.s, 1.0), 0.0)
        return self.s / (self.s ** 2 + 1.0 / C)

    def solve(self, t: np.ndarray, C: float) -> np.ndarray:
        """beta of [F13] (C = inf) or [F15]."""
        return self.Vt.T @ (self.filter_factors(C) * (self.U.T @ t))

    def hat_diagonal(self, C: float) -> np.ndarray:
        """diag of the hat matrix H (1/C I + H^T H)^-1 H^T."""
        shrink = self.filter_factors(C) * self.s
        return np.einsum("ij,j,ij->i", self.U, shrink, self.U)


def loo_residuals(svd: SVD, t: np.ndarray, C: float) -> np.ndarray:
    """Closed-form leave-one-out residuals (t_i - y_i) / (1 - h_ii) of the ridge fit (PRESS)."""
    y = svd.U @ (svd.filter_factors(C) * svd.s * (svd.U.T @ t))
    return (t - y) / np.maximum(1.0 - svd.hat_diagonal(C), 1e-12)


def prefix_loo_residuals(D: np.ndarray, t: np.ndarray) -> np.ndarray:
    """``loo_residuals(SVD.of(D[:, :m]), t, inf)`` for m = 1 .. D.shape[1], one column each.

    One thin QR D = Q R serves every prefix: the hat matrix of D[:, :m] is Q_m Q_m^T when its
    singular values (those of R[:m, :m]) are above the pseudo-inverse's cutoff, so the fitted
    values and the leverages are running sums over the columns of Q. A prefix whose singular
    values are not is solved by its own SVD. R[:m, :m]^T R[:m, :m] is a leading block of R^T R,
    so as m grows its smallest singular value falls and its largest rises (interlacing): the
    prefixes that fail the cutoff are all those from the first that does, found by bisection."""
    Q, R = np.linalg.qr(D)
    fitted = np.cumsum(Q * (Q.T @ t), axis=1)
    leverage = np.cumsum(Q * Q, axis=1)
    res = (t[:, None] - fitted) / np.maximum(1.0 - leverage, 1e-12)

    def fails(m: int) -> bool:
        s = np.linalg.svd(R[:m, :m], compute_uv=False)
        return not s.min() > pinv_cutoff(s, (D.shape[0], m))

    lo, hi = 1, D.shape[1] + 1                  # the first failing prefix lies in [lo, hi]
    while lo < hi:
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if fails(mid) else (mid + 1, hi)
    for m in range(lo, D.shape[1] + 1):
        res[:, m - 1] = loo_residuals(SVD.of(D[:, :m]), t, np.inf)
    return res


@dataclass(frozen=True)
class PseudoInverse:
    """Moore-Penrose solution beta = H^+ t, [F13]."""

    def choose_C(self, svd: SVD, t: np.ndarray, layer: Optional[HiddenLayer] = None) -> float:
        return float("inf")


@dataclass(frozen=True)
class Ridge:
    """Regularized solution with a given C, [F14]-[F15]."""

    C: float

    def __post_init__(self):
        positive("C", self.C)

    def choose_C(self, svd: SVD, t: np.ndarray, layer: Optional[HiddenLayer] = None) -> float:
        return float(self.C)


#: Unit roundoff of float32 (2^-23): one rounding of a float32 value near 1.
EPS32 = float(np.finfo(np.float32).eps)

#: The parity of the emitted float32 C with the float64 model, as a fraction of max |F| (README,
#: "Parity, as the tests prove it").
PARITY = 1e-5


def float32_error(H: np.ndarray, beta: np.ndarray) -> float:
    """About how far float32 evaluation of [F7] strays from float64 at the rows of H:
    eps32 max_i sum_k |beta_k h_k(x_i)|.

    Each term beta_k h_k carries about one float32 rounding: the activation (libm's expf, sinf
    and sqrtf are within 1 ULP), the product and the running sum add half an ULP each, and the
    errors of w, b and beta rounded to float32 are of the same order, with random signs. The
    sum of the terms' magnitudes, not |sum|, sets the error: large cancelling output weights
    make float32 lose what float64 keeps. It is an estimate, not a worst-case bound, and it
    ignores the order of the running sum; it is subadditive, so the estimate of an average of
    networks is at most the largest member's (``AutoELMRegressor``).
    """
    return EPS32 * float(np.max(np.abs(H) @ np.abs(beta), initial=0.0))


def accumulation_order(terms: np.ndarray) -> np.ndarray:
    """An order of the columns of ``terms`` (beta_k h_k(x_i), one row per input) whose running
    sums stay small: greedily, the next term is the one that keeps max_i |partial sum| least.

    The emitted C adds the terms in array order, and each float32 addition rounds the partial
    sum: with large cancelling output weights the partial sums, not the result, set the error.
    Reordering the neurons changes the float64 model only by rounding."""
    acc, used = np.zeros(terms.shape[0]), np.zeros(terms.shape[1], dtype=bool)
    order = np.empty(terms.shape[1], dtype=int)
    for step in range(terms.shape[1]):
        reach = np.max(np.abs(acc[:, None] + terms), axis=0)
        reach[used] = np.inf
        k = int(np.argmin(reach))
        order[step], used[k] = k, True
        acc += terms[:, k]
    return order


#: Uniform probes over the training inputs' range added to the inputs themselves by
#: ``float32_twin_error``.
TWIN_PROBES = 4097

#: Rows of the probe set from which ``accumulation_order`` picks its order (evenly spaced), at
#: most; fewer for large networks, so that the greedy search (rows x neurons^2 operations) stays
#: within ``ORDER_BUDGET``.
ORDER_ROWS = 256
ORDER_BUDGET = 10 ** 7

#: Factor between the float32 error measured on the probes and the parity bound it must meet.
#: It covers inputs between the probes (on a grid of 10^6 inputs the float32 error of 27
#: ``--method elm`` fits, 1e4 to 1e6 rows and 20 to 80 neurons, was at most 1.45 times the
#: probes'; ``benchmarks/scale.py --sections elm`` prints that ratio) and libm float functions
#: that round differently from the twin (glibc's expf: within 1 ULP, and bit-equal for more than
#: 99 % of inputs).
TWIN_MARGIN = 1.5


def probe_inputs(x: np.ndarray) -> np.ndarray:
    """The training inputs and ``TWIN_PROBES`` uniform points over their range, as float32."""
    x = np.asarray(x, dtype=float)
    grid = np.linspace(x.min(), x.max(), TWIN_PROBES)
    return np.unique(np.concatenate([x, grid]).astype(np.float32))


def order_rows(probes: np.ndarray, n_hidden: int) -> np.ndarray:
    """The evenly spaced probes from which ``accumulation_order`` picks the order of
    ``n_hidden`` neurons, as float64."""
    count = max(8, min(ORDER_ROWS, ORDER_BUDGET // n_hidden ** 2))
    return probes[::max(1, probes.size // count)].astype(float)


def ordered_network(layer: HiddenLayer, beta: np.ndarray, hidden_rows: np.ndarray) -> ElmNetwork:
    """The network of ``layer`` and ``beta`` with its neurons in ``accumulation_order`` on
    ``hidden_rows``, the hidden-layer matrix at ``order_rows``."""
    order = accumulation_order(hidden_rows * beta)
    return ElmNetwork(layer.activation, layer.w[order], layer.b[order], beta[order])


def float32_twin_error(net: ElmNetwork, probes: np.ndarray, exact: Optional[np.ndarray] = None) -> float:
    """max |float32 [F7] - float64 [F7]| over the float32 inputs ``probes``: the error of
    the emitted C there, operation by operation in the C's order (``ElmNetwork.float32``), not an
    estimate. ``exact``: the float64 outputs at the probes, if known."""
    exact = net(probes.astype(float)) if exact is None else exact
    return float(np.max(np.abs(net.float32(probes).astype(float) - exact), initial=0.0))


def parity_limit(t: np.ndarray, parity: float = PARITY) -> float:
    """The largest float32 error of the network output that keeps the emitted C within
    ``parity`` of max |F|.

    The network's output is t = K_out (F - B v) [F9], so an error e in t is e / K_out newtons,
    and max |F| >= max |t| / K_out on [0, v_sat] (B v >= 0 there): e <= parity max |t| keeps
    the force within parity max |F|."""
    return parity * float(np.max(np.abs(t), initial=0.0))


@dataclass(frozen=True)
class LeaveOneOut:
    """Ridge with C chosen by minimal closed-form leave-one-out error (PRESS) over a log grid.

    Only C that keep float32 firmware within the stated parity are eligible. Given the hidden
    layer (``ELMRegressor``), the network with its neurons in ``accumulation_order`` is
    evaluated in float32 exactly as the emitted C does it, on the training inputs and a uniform
    grid (``float32_twin_error``), and ``TWIN_MARGIN`` times that error must be within
    ``parity_limit``. Without it (the members of ``AutoELMRegressor``, whose average is emitted),
    the estimate ``float32_error`` must be; with ``max_beta_l1`` set, ||beta||_1 <= max_beta_l1
    instead. When the best eligible C of the grid borders an ineligible one, the largest
    eligible C between them is found by bisection (in log C) and taken if its PRESS is lower.
    """

    C_grid: Tuple[float, ...] = tuple(np.logspace(-2, 14, 65))
    max_beta_l1: Optional[float] = None
    parity: float = PARITY

    def __post_init__(self):
        positive("parity", self.parity)
        if self.max_beta_l1 is not None:
            positive("max_beta_l1", self.max_beta_l1)

    def _eligibility(self, svd: SVD, t: np.ndarray, layer: Optional[HiddenLayer]):
        """A test C -> bool of the bound in force."""
        limit = parity_limit(t, self.parity)
        if self.max_beta_l1 is not None:
            return lambda C: bool(np.abs(svd.solve(t, C)).sum() <= self.max_beta_l1)
        if layer is None:
            H = (svd.U * svd.s) @ svd.Vt
            return lambda C: float32_error(H, svd.solve(t, C)) <= limit
        probes = probe_inputs(layer.x)
        H = hidden_matrix(layer.activation, probes.astype(float), layer.w, layer.b)
        rows = hidden_matrix(layer.activation, order_rows(probes, layer.w.size), layer.w, layer.b)

        def twin_within(C):
            beta = svd.solve(t, C)
            net = ordered_network(layer, beta, rows)
            return TWIN_MARGIN * float32_twin_error(net, probes, H @ beta) <= limit
        return twin_within

    def choose_C(self, svd: SVD, t: np.ndarray, layer: Optional[HiddenLayer] = None) -> float:
        eligible = self._eligibility(svd, t, layer)
        grid = [float(C) for C in self.C_grid]
        press = [float(np.mean(loo_residuals(svd, t, C) ** 2)) for C in grid]
        ok = {}
        for i in sorted(range(len(grid)), key=lambda j: (press[j], j)):   # best PRESS first
            ok[i] = eligible(grid[i])
            if ok[i]:
                break
        else:
            return grid[0]
        best_C, best_press = grid[i], press[i]
        if i + 1 < len(grid) and not (ok[i + 1] if i + 1 in ok else eligible(grid[i + 1])):
            lo, hi = np.log(grid[i]), np.log(grid[i + 1])
            for _ in range(12):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if eligible(np.exp(mid)) else (lo, mid)
            edge = float(np.exp(lo))
            edge_press = np.mean(loo_residuals(svd, t, edge) ** 2)
            if edge_press < best_press:
                best_C = edge
        return best_C


SOLVERS = {"pinv": PseudoInverse, "ridge": Ridge, "loo": LeaveOneOut}


def log10_cond(s: np.ndarray, C: float = float("inf"), n_hidden: Optional[int] = None) -> float:
    """log10 cond(1/C I + H^T H) from the singular values s of H (C = inf: cond(H^T H)).

    Computed as ((s_max^2 + 1/C) / (s_min^2 + 1/C)); H^T H is M x M, so with fewer samples than
    neurons its smallest eigenvalue is 0.
    """
    s = np.asarray(s, dtype=float)
    lam = 0.0 if np.isinf(C) else 1.0 / C
    s_min = 0.0 if (n_hidden is not None and n_hidden > s.size) else s.min()
    num, den = s.max() ** 2 + lam, s_min ** 2 + lam
    return float("inf") if den == 0 else float(np.log10(num) - np.log10(den))


# ----------------------------------------------------------------------------- estimator


def make_part(kind, registry, what):
    """A scheme or solver given by name (from ``registry``) or as an object."""
    if isinstance(kind, str):
        if kind not in registry:
            raise ValueError(f"{what} must be one of {sorted(registry)}, got {kind!r}")
        return registry[kind]()
    return kind


class ELMRegressor(Estimator):
    r"""Extreme Learning Machine for one input, [F7]-[F17] (scikit-learn style).

    Parameters are stored unchanged; ``fit(x, t)`` draws the hidden layer from ``scheme`` with
    ``random_state``, solves for the output weights with ``solver`` and returns self. x and t are
    the normalized data of [F9] (both dimensionless).

    Parameters
    ----------
    n_hidden : int
        Hidden neurons M. The default here is 10 (the paper's enlarged-variability size);
        ``fricgen train --method elm`` uses ``DEFAULT_ELM`` instead: 40 neurons and
        ``EnlargedScheme(w_max=30.0)``. Pass ``**DEFAULT_ELM`` to get the command line's ELM.
    activation : str
        The hidden units' function of z = w x + b ("sigmoid", ...; ``networks.elm.ACTIVATIONS``).
    scheme : str or scheme object
        How w and b are drawn: "enlarged" ([F16]-[F17], w in [-10, 10]), "standard"
        (uniform in [-1, 1], sec. 4), or an object with ``draw(n, rng)`` such as
        ``EnlargedScheme(w_max=30.0)``.
    solver : str or solver object
        "pinv" [F13], "ridge" ([F15], needs ``C``), "loo" (C by closed-form leave-one-out
        error among those that keep the emitted float32 C within parity), or an object.
    C : float, optional
        The regularization C of [F15], for ``solver="ridge"`` only.
    random_state : int, numpy.random.Generator or None
        The one source of randomness (the hidden layer's draw).

    Attributes
    ----------
    network_ : ElmNetwork
        The trained AIM of [F3], neurons in the order the emitted C sums them.
    input_weights_, biases_ : ndarray, shape (n_hidden,)
        w and b of [F7] (dimensionless; x is in [0, 1]).
    beta_ : ndarray, shape (n_hidden,)
        The output weights of [F13]/[F15], in units of t (normalized force).
    C_ : float
        The C used (dimensionless): ``inf`` for "pinv", the given C for "ridge", the chosen
        one for "loo".
    singular_values_ : ndarray
        Singular values of the hidden-layer matrix H [F11].
    loo_rmse_ : float
        Leave-one-out RMSE of the fit (PRESS), in units of t.
    beta_norm_, log10_cond_ : float
        ||beta|| and log10 cond(H^T H) (properties).

    Notes
    -----
    The network is [F7], :math:`y(x) = \sum_{k=1}^M \beta_k h(w_k x + b_k)`, and the solvers
    minimize

    .. math::

        \beta = (I / C + H^T H)^{-1} H^T t \quad (15), \qquad C \to \infty:\ \beta = H^+ t \quad (13)

    through one SVD of H.

    Examples
    --------
    >>> import fricgen
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> elm = fricgen.ELMRegressor(n_hidden=10, random_state=0).fit(data.x, data.t)
    >>> elm.beta_.shape, bool(elm.C_ > 0), bool(elm.loo_rmse_ < 0.05)
    ((10,), True, True)
    >>> round(elm.score(data.x, data.t), 2)
    1.0
    """

    def __init__(self, n_hidden: int = 10, activation: str = "sigmoid", scheme="enlarged",
                 solver="loo", C: Optional[float] = None, random_state=None):
        self.n_hidden = n_hidden
        self.activation = activation
        self.scheme = scheme
        self.solver = solver
        self.C = C
        self.random_state = random_state

    def _solver(self):
        if self.solver == "ridge":
            if self.C is None:
                raise ValueError("solver 'ridge' needs C")
            return Ridge(self.C)
        return make_part(self.solver, SOLVERS, "solver")

    def fit(self, x, t) -> "ELMRegressor":
        integer("n_hidden", self.n_hidden)
        check_activation(self.activation)
        x, t = self._inputs(x, t)
        w, b = make_part(self.scheme, SCHEMES, "scheme").draw(int(self.n_hidden), as_rng(self.random_state))
        H = hidden_matrix(self.activation, x, w, b)
        svd = SVD.of(H)
        layer = HiddenLayer(self.activation, w, b, x)
        self.C_ = self._solver().choose_C(svd, t, layer)
        rows = hidden_matrix(self.activation, order_rows(probe_inputs(x), w.size), w, b)
        self.network_ = ordered_network(layer, svd.solve(t, self.C_), rows)
        self.input_weights_, self.biases_ = self.network_.input_weights, self.network_.biases
        self.beta_ = self.network_.output_weights
        self.singular_values_ = svd.s
        self.loo_rmse_ = rmse(loo_residuals(svd, t, self.C_), 0.0)
        return self

    @property
    def beta_norm_(self) -> float:
        """||beta||, the size of the output weights."""
        return float(np.linalg.norm(self.beta_))

    @property
    def log10_cond_(self) -> float:
        """log10 cond(H^T H) of the fitted hidden layer, from the singular values of H."""
        return log10_cond(self.singular_values_, n_hidden=int(self.n_hidden))


#: Defaults of an explicitly configured ELM (``fricgen train --method elm``): 40 sigmoids of
#: enlarged variability with input weights up to 30 (steep enough for the Stribeck drop), C by
#: leave-one-out within the float32 parity bound (``LeaveOneOut``).
DEFAULT_ELM = dict(n_hidden=40, activation="sigmoid", scheme=EnlargedScheme(w_max=30.0), solver="loo")
