"""Conditioning optimization: the particle swarm and the RAND/OPT split (section 5)."""
import numpy as np
import pytest

from fricgen.fit.conditioning import ConditionedELMRegressor, ParticleSwarm, batched_log10_cond
from fricgen.fit.elm import SVD, log10_cond
from fricgen.networks.elm import hidden_matrix


def test_constriction_coefficient_is_clerc_value():
    assert ParticleSwarm(c1=2.05, c2=2.05).chi == pytest.approx(0.72984, abs=1e-5)
    with pytest.raises(ValueError, match="c1 \\+ c2"):
        _ = ParticleSwarm(c1=1.0, c2=1.0).chi


def test_swarm_finds_the_minimum_of_a_shifted_sphere_inside_the_bounds():
    target = np.array([0.3, -0.7, 0.9])
    seen = []

    def f(x):
        seen.append(x.copy())
        return np.sum((x - target) ** 2, axis=1)

    swarm = ParticleSwarm(n_particles=15, iterations=60, random_state=1)
    x, fx, evals = swarm.minimize(f, -np.ones(3), np.ones(3))
    np.testing.assert_allclose(x, target, atol=1e-3)
    assert fx < 1e-6 and evals == 15 * 61
    allx = np.concatenate(seen)
    assert allx.min() >= -1.0 and allx.max() <= 1.0           # clipping to the box


def test_swarm_is_reproducible_by_seed():
    f = lambda x: np.sum(np.cos(5 * x) + x ** 2, axis=1)   # noqa: E731
    a = ParticleSwarm(random_state=7).minimize(f, -np.ones(2), np.ones(2))
    b = ParticleSwarm(random_state=7).minimize(f, -np.ones(2), np.ones(2))
    assert a[1] == b[1] and np.array_equal(a[0], b[0])


def test_batched_objective_equals_direct_cond():
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 1, 50)
    wr, br = rng.uniform(-5, 5, 3), rng.uniform(-5, 5, 3)
    theta = rng.uniform(-5, 5, (4, 4))
    got = batched_log10_cond("sigmoid", x, wr, br, theta)
    for th, g in zip(theta, got):
        H = hidden_matrix("sigmoid", x, np.r_[wr, th[:2]], np.r_[br, th[2:]])
        assert g == pytest.approx(log10_cond(SVD.of(H).s, n_hidden=5))


def test_pso_lowers_cond_versus_the_random_start(bench):
    d = bench.dataset
    est = ConditionedELMRegressor(10, random_state=0).fit(d.x, d.t)
    assert est.log10_cond_ < est.log10_cond_start_ - 1.0       # at least 10x better conditioned
    assert est.n_evaluations_ == 20 * 41
    assert est.network_.n_hidden == 10 and np.all(np.abs(est.input_weights_) <= 10.0)
    e = bench.errors(est.predict)
    assert e["e_ttest_newton"] < 0.5                            # still a friction model


def test_n_opt_zero_is_a_plain_enlarged_elm(bench):
    d = bench.dataset
    est = ConditionedELMRegressor(6, n_opt=0, random_state=3).fit(d.x, d.t)
    assert est.n_evaluations_ == 0 and est.log10_cond_ == pytest.approx(est.log10_cond_start_)
    with pytest.raises(ValueError, match="n_opt"):
        ConditionedELMRegressor(4, n_opt=5).fit(d.x, d.t)
