"""The paper's benchmark (section 2): noisy sweeps of a known multisource friction."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ..friction import MultisourceFriction
from ..metrics import rmse
from .training_set import SAT_FACTOR, Dataset, prepare
from .sweep import Sweep


@dataclass(frozen=True)
class Benchmark:
    """The paper's benchmark (section 2) for one seed (``synthesize_benchmark``).

    Parameters
    ----------
    friction : MultisourceFriction
        The true friction, [F1].
    vs_max : float
        The largest Stribeck velocity (m/s); v_sat = 3 vs_max.
    train : Sweep
        N noisy points in [0, v_sat] plus the high-speed points (for B).
    test : Sweep
        Another N noisy points in [0, v_sat].
    theory : Sweep
        Nt equidistant noise-free points in [0, v_sat].
    dataset : Dataset
        The [F9] training set of ``train``.

    Notes
    -----
    ``errors(aim)`` gives E_train, E_test, E_Ttest of [F4]-[F6], normalized and in newtons.

    Examples
    --------
    >>> import fricgen
    >>> bench = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0)
    >>> len(bench.test), len(bench.theory), bench.vs_max
    (200, 500, 0.02)
    """

    friction: MultisourceFriction
    vs_max: float
    train: Sweep          # N noisy points in [0, v_sat] plus the high-speed points
    test: Sweep           # another N noisy points in [0, v_sat]
    theory: Sweep         # Nt equidistant noise-free points in [0, v_sat]
    dataset: Dataset = field(repr=False)

    def errors(self, aim) -> dict:
        """E_train, E_test, E_Ttest of [F4]-[F6], normalized and in newtons, for AIM ``aim``."""
        d = self.dataset
        x_test, t_test = d.targets(self.test.v, self.test.f)
        x_th, t_th = d.targets(self.theory.v, self.theory.f)
        out = {"e_train": rmse(aim(d.x), d.t), "e_test": rmse(aim(x_test), t_test),
               "e_ttest": rmse(aim(x_th), t_th)}
        for key in list(out):
            out[key + "_newton"] = out[key] / d.scaling.k_out
        return out


def synthesize_benchmark(friction: MultisourceFriction, seed=0, vs_max: Optional[float] = None,
                         n_train: int = 200, n_test: int = 200, n_theory: int = 500,
                         noise: float = 0.5, n_high: int = 100, high_factor: float = 10.0) -> Benchmark:
    """Synthesize the paper's benchmark exactly (section 2), plus high-speed data for B.

    Parameters
    ----------
    friction : MultisourceFriction
        The true [F1], e.g. ``preset("paper3")`` (Table 1).
    seed : int, numpy.random.Generator or None
        The noise and velocity draws.
    vs_max : float, optional
        v_smax (m/s); default: the friction's largest Stribeck velocity.
    n_train, n_test : int
        Noisy points uniform in [0, 3 vs_max] for training and test.
    n_theory : int
        Equidistant noise-free points (the theoretical test).
    noise : float
        Half-width of the uniform force noise (N).
    n_high : int
        Noisy points uniform in (3 vs_max, high_factor vs_max] for the regression of B.
    high_factor : float
        Their upper end, in units of vs_max.

    Returns
    -------
    Benchmark
        The sweeps and the [F9] training set, to which ``prepare`` added (0, mean of the four
        slowest) and (3 vs_max, F(3 vs_max)) with the true F, as the paper does.

    Examples
    --------
    >>> import fricgen
    >>> bench = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0, n_high=50)
    >>> len(bench.train), bench.dataset.x.shape
    (250, (202,))
    """
    rng = np.random.default_rng(seed)
    vs_max = friction.vs_max if vs_max is None else vs_max
    v_sat = SAT_FACTOR * vs_max

    def noisy(v):
        return Sweep(v, friction(v) + rng.uniform(-noise, noise, v.size))

    train = noisy(rng.uniform(0.0, v_sat, n_train))
    test = noisy(rng.uniform(0.0, v_sat, n_test))
    high = noisy(rng.uniform(v_sat, high_factor * vs_max, n_high))
    v_th = np.linspace(0.0, v_sat, n_theory)
    theory = Sweep(v_th, friction.stribeck(v_th) + friction.viscous * v_th)  # F(0+) at v = 0
    measured = train.concat(high)
    dataset = prepare(measured, vs_max=vs_max, f_sat=float(friction(v_sat)))
    return Benchmark(friction=friction, vs_max=vs_max, train=measured, test=test, theory=theory,
                     dataset=dataset)
