"""Conditioning optimization (section 5, "Direct minimization of the condition coefficient").

The hidden neurons are split into RAND, drawn with enlarged variability [F16]-[F17], and OPT,
whose weights and biases minimize log10 cond(H^T H) of [F11], computed from the singular
values of H. The objective is multimodal and not smooth (the paper's fig. 21), so OPT is found
by a small seeded particle swarm with Clerc's constriction coefficients, clipped to bounds.
"""
from __future__ import annotations

import time
from typing import Callable, Optional

import numpy as np

from .._validate import integer
from ..networks.elm import hidden_matrix
from .base import Estimator, as_rng
from .elm import SCHEMES, ELMRegressor, EnlargedScheme, FixedScheme, log10_cond, make_part


class ParticleSwarm:
    """Constricted particle swarm (Clerc & Kennedy 2002) minimizing a batched objective.

    ``c1``, ``c2`` are the cognitive and social accelerations; with phi = c1 + c2 > 4 the
    constriction chi = 2 / |2 - phi - sqrt(phi^2 - 4 phi)| (0.7298 for 2.05 + 2.05) multiplies
    the velocity update. Velocities are clipped to the box width, positions to the box (the
    velocity component that hits a wall is zeroed).
    """

    def __init__(self, n_particles: int = 20, iterations: int = 40, c1: float = 2.05,
                 c2: float = 2.05, random_state=None):
        self.n_particles = n_particles
        self.iterations = iterations
        self.c1 = c1
        self.c2 = c2
        self.random_state = random_state

    @property
    def chi(self) -> float:
        phi = self.c1 + self.c2
        if not phi > 4:
            raise ValueError(f"c1 + c2 must be > 4 for constriction, got {phi}")
        return 2.0 / abs(2.0 - phi - np.sqrt(phi * phi - 4.0 * phi))

    def minimize(self, f: Callable[[np.ndarray], np.ndarray], lower, upper,
                 start: Optional[np.ndarray] = None):
        """Minimize f over the box; f maps (P, D) positions to P values. Returns (x, f(x), evals).

        ``start``, if given, is the position of the first particle (the swarm never ends worse).
        """
        integer("n_particles", self.n_particles)
        integer("iterations", self.iterations)
        lower, upper = np.asarray(lower, float), np.asarray(upper, float)
        if lower.shape != upper.shape or not np.all(upper > lower):
            raise ValueError("bounds must have equal shapes with upper > lower")
        chi, rng = self.chi, as_rng(self.random_state)
        P, D = int(self.n_particles), lower.size
        width = upper - lower
        x = lower + rng.uniform(size=(P, D)) * width
        if start is not None:
            x[0] = np.clip(start, lower, upper)
        v = rng.uniform(-1.0, 1.0, (P, D)) * width * 0.1
        fx = f(x)
        evals = P
        pbest, pbest_f = x.copy(), fx.copy()
        g = int(np.argmin(pbest_f))
        for _ in range(int(self.iterations)):
            r1, r2 = rng.uniform(size=(P, D)), rng.uniform(size=(P, D))
            v = chi * (v + self.c1 * r1 * (pbest - x) + self.c2 * r2 * (pbest[g] - x))
            v = np.clip(v, -width, width)
            x = x + v
            hit = (x < lower) | (x > upper)
            x = np.clip(x, lower, upper)
            v[hit] = 0.0
            fx = f(x)
            evals += P
            better = fx < pbest_f
            pbest[better], pbest_f[better] = x[better], fx[better]
            g = int(np.argmin(pbest_f))
        return pbest[g].copy(), float(pbest_f[g]), evals


def batched_log10_cond(activation: str, x, w_rand, b_rand, theta) -> np.ndarray:
    """log10 cond(H^T H) for each row of theta = [w_opt..., b_opt...] (P x 2 n_opt)."""
    x = np.asarray(x, float).reshape(-1, 1)
    H_rand = hidden_matrix(activation, x, w_rand, b_rand)
    n_opt = theta.shape[1] // 2
    H_opt = np.stack([hidden_matrix(activation, x, th[:n_opt], th[n_opt:]) for th in theta])
    H = np.concatenate([np.broadcast_to(H_rand, (theta.shape[0],) + H_rand.shape), H_opt], axis=2)
    s = np.linalg.svd(H, compute_uv=False)
    M = H.shape[2]
    return np.array([log10_cond(si, n_hidden=M) for si in s])


class ConditionedELMRegressor(Estimator):
    """ELM with conditioning optimization (sec. 5): ``n_opt`` of ``n_hidden`` neurons chosen by
    particle swarm to minimize log10 cond(H^T H); the rest drawn by ``scheme``.

    The swarm's weights and biases are bounded to [-w_max, w_max] of the scheme; the output weights
    come from ``solver`` as in ``ELMRegressor``.

    Parameters
    ----------
    n_hidden : int
        Hidden neurons M.
    n_opt : int, optional
        Neurons the swarm places (default: M // 2, the paper's half).
    activation : str
        The hidden units' function.
    scheme : str or scheme object, optional
        How the other neurons are drawn (default: enlarged variability, [F16]-[F17]).
    solver : str or solver object
        "pinv" ([F13], the default here), "ridge" [F15] or "loo".
    C : float, optional
        C of [F15] for ``solver="ridge"``.
    n_particles, iterations : int
        Swarm size and iterations.
    random_state : int, numpy.random.Generator or None
        The one source of randomness.

    Attributes
    ----------
    network_, input_weights_, biases_, beta_, C_, singular_values_, loo_rmse_
        As in ``ELMRegressor`` (beta_ and loo_rmse_ in units of t, normalized force).
    log10_cond_start_ : float
        log10 cond(H^T H) before the swarm (its first particle).
    log10_cond_ : float
        log10 cond(H^T H) of the fitted layer.
    n_evaluations_ : int
        Objective evaluations of the swarm.
    fit_seconds_ : float
        Wall time of ``fit`` (s).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen.fit import ConditionedELMRegressor
    >>> x = np.linspace(0, 1, 40)
    >>> elm = ConditionedELMRegressor(n_particles=5, iterations=5, random_state=0)
    >>> elm = elm.fit(x, 0.5 + 0.5 * np.exp(-(x / 0.2) ** 2))
    >>> bool(elm.log10_cond_ <= elm.log10_cond_start_), elm.n_evaluations_
    (True, 30)
    """

    def __init__(self, n_hidden: int = 10, n_opt: Optional[int] = None, activation: str = "sigmoid",
                 scheme=None, solver="pinv", C: Optional[float] = None, n_particles: int = 20,
                 iterations: int = 40, random_state=None):
        self.n_hidden = n_hidden
        self.n_opt = n_opt
        self.activation = activation
        self.scheme = scheme
        self.solver = solver
        self.C = C
        self.n_particles = n_particles
        self.iterations = iterations
        self.random_state = random_state

    def fit(self, x, t) -> "ConditionedELMRegressor":
        M = integer("n_hidden", self.n_hidden)
        n_opt = M // 2 if self.n_opt is None else int(self.n_opt)
        if not 0 <= n_opt <= M:
            raise ValueError(f"n_opt must be in [0, n_hidden = {M}], got {self.n_opt}")
        start = time.perf_counter()
        rng = as_rng(self.random_state)
        scheme = EnlargedScheme() if self.scheme is None else make_part(self.scheme, SCHEMES, "scheme")
        w, b = scheme.draw(M, rng)
        w_rand, b_rand = w[:M - n_opt], b[:M - n_opt]
        x, t = self._inputs(x, t)
        self.n_evaluations_ = 0
        self.log10_cond_start_ = log10_cond(np.linalg.svd(hidden_matrix(self.activation, x, w, b),
                                                          compute_uv=False), n_hidden=M)
        if n_opt > 0:
            bound = float(getattr(scheme, "w_max", getattr(scheme, "high", 10.0)))
            lower, upper = np.full(2 * n_opt, -bound), np.full(2 * n_opt, bound)
            swarm = ParticleSwarm(self.n_particles, self.iterations, random_state=rng)
            theta, _, self.n_evaluations_ = swarm.minimize(
                lambda th: batched_log10_cond(self.activation, x, w_rand, b_rand, th),
                lower, upper, start=np.concatenate([w[M - n_opt:], b[M - n_opt:]]))
            w = np.concatenate([w_rand, theta[:n_opt]])
            b = np.concatenate([b_rand, theta[n_opt:]])
        elm = ELMRegressor(M, self.activation, FixedScheme(w, b), self.solver, self.C).fit(x, t)
        for key in ("C_", "beta_", "input_weights_", "biases_", "singular_values_", "loo_rmse_",
                    "network_"):
            setattr(self, key, getattr(elm, key))
        self._elm = elm
        self.fit_seconds_ = time.perf_counter() - start
        return self


    @property
    def beta_norm_(self) -> float:
        return self._elm.beta_norm_

    @property
    def log10_cond_(self) -> float:
        return self._elm.log10_cond_
