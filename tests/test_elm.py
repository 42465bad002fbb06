import numpy as np
import pytest

from fricgen.networks.elm import ACTIVATIONS, ElmNetwork, hidden_matrix
from fricgen.codegen.parity import parity_velocities
from fricgen.codegen.twin import force_f32
from fricgen.fit.elm import (TWIN_MARGIN, ELMRegressor, EnlargedScheme, HiddenLayer, LeaveOneOut, SVD,
                             StandardScheme, accumulation_order, float32_error, float32_twin_error,
                             log10_cond, loo_residuals, order_rows, ordered_network, parity_limit,
                             probe_inputs)
from fricgen.model import FrictionModel


def _sigmoid(z):
    return 1 / (1 + np.exp(-z))


def test_pinv_solution_is_eq_13(xt):
    x, t = xt
    elm = ELMRegressor(n_hidden=8, scheme="standard", solver="pinv", random_state=1).fit(x, t)
    H = hidden_matrix("sigmoid", x, elm.input_weights_, elm.biases_)
    assert np.allclose(elm.beta_, np.linalg.pinv(H) @ t, rtol=1e-6, atol=1e-6 * np.abs(elm.beta_).max())
    assert np.isinf(elm.C_)


def test_ridge_solution_is_eq_15(xt):
    x, t = xt
    C = 1e3
    elm = ELMRegressor(n_hidden=12, solver="ridge", C=C, random_state=2).fit(x, t)
    H = hidden_matrix("sigmoid", x, elm.input_weights_, elm.biases_)
    A = np.eye(12) / C + H.T @ H
    expected = np.linalg.solve(A, H.T @ t)
    # The normal-equations reference is itself only accurate to ~cond(A) eps relative (backward
    # stable solve of [F15]); allow ten times that, on the scale of the solution.
    tolerance = 10 * np.linalg.cond(A) * np.finfo(float).eps * np.linalg.norm(expected)
    assert np.linalg.norm(elm.beta_ - expected) <= tolerance
    # and the solution satisfies [F15] itself to the same relative accuracy
    assert np.linalg.norm(A @ elm.beta_ - H.T @ t) <= 10 * np.finfo(float).eps * np.linalg.norm(A, 2) \
        * np.linalg.norm(elm.beta_) * np.sqrt(12)


@pytest.mark.parametrize("C", [1e-1, 1e2, 1e6])
def test_closed_form_loo_equals_brute_force(xt, C):
    x, t = xt
    rng = np.random.default_rng(3)
    w, b = EnlargedScheme().draw(10, rng)
    H = hidden_matrix("sigmoid", x, w, b)
    fast = loo_residuals(SVD.of(H), t, C)
    brute = np.empty_like(t)
    for i in range(t.size):
        keep = np.arange(t.size) != i
        beta = np.linalg.solve(np.eye(10) / C + H[keep].T @ H[keep], H[keep].T @ t[keep])
        brute[i] = t[i] - H[i] @ beta
    assert np.allclose(fast, brute, rtol=1e-6, atol=1e-9)


def test_loo_solver_minimizes_press_within_the_beta_bound(xt):
    x, t = xt
    solver = LeaveOneOut(max_beta_l1=50.0)
    elm = ELMRegressor(n_hidden=30, solver=solver, random_state=4).fit(x, t)
    assert np.abs(elm.beta_).sum() <= 50.0
    svd = SVD.of(hidden_matrix("sigmoid", x, elm.input_weights_, elm.biases_))
    press = {C: np.mean(loo_residuals(svd, t, C) ** 2) for C in solver.C_grid
             if np.abs(svd.solve(t, C)).sum() <= 50.0}
    best = min(press, key=press.get)
    # the grid's best, or the bound's edge between it and the next (ineligible) grid value
    assert best <= elm.C_ < best * solver.C_grid[1] / solver.C_grid[0]
    assert np.mean(loo_residuals(svd, t, elm.C_) ** 2) <= press[best]


def _parity_fit(bench, parity):
    est = ELMRegressor(n_hidden=40, scheme=EnlargedScheme(w_max=30.0),
                       solver=LeaveOneOut(parity=parity), random_state=0)
    return est, FrictionModel.fit(bench.dataset, est)


@pytest.mark.parametrize("parity", [1e-5, 1e-6])
def test_default_loo_solver_keeps_the_float32_twin_within_parity(bench, parity):
    """The parity bound (the float32 network on the probes, times the margin): the float32 twin
    of the fitted model stays within ``parity`` of max |F| on [-2 v_sat, 2 v_sat]; where the bound
    does not bind, C is the one leave-one-out prefers."""
    d = bench.dataset
    est, model = _parity_fit(bench, parity)
    probes = probe_inputs(d.x)
    assert TWIN_MARGIN * float32_twin_error(est.network_, probes) <= parity_limit(d.t, parity)
    v = parity_velocities(model.v_sat)
    v = v[np.abs(v) <= 2 * model.v_sat]
    exact = model.force(v.astype(float))
    assert np.max(np.abs(force_f32(model, v) - exact)) <= parity * np.max(np.abs(exact))
    layer = HiddenLayer("sigmoid", est.input_weights_, est.biases_, d.x)
    svd = SVD.of(model.aim.hidden(d.x))
    grid = LeaveOneOut().C_grid
    above = min(C for C in grid if C > est.C_)
    rows = hidden_matrix("sigmoid", order_rows(probes, 40), est.input_weights_, est.biases_)
    net_above = ordered_network(layer, svd.solve(d.t, above), rows)
    if TWIN_MARGIN * float32_twin_error(net_above, probes) <= parity_limit(d.t, parity):
        # the bound does not bind: C is the grid's unconstrained PRESS minimum
        assert est.C_ == min(grid, key=lambda C: np.mean(loo_residuals(svd, d.t, C) ** 2))


def test_the_parity_bound_holds_between_the_probes_where_it_binds(bench):
    """With parity 1e-6 the bound binds (the next C of the grid breaks it, and leave-one-out
    prefers a larger C); the float32 network is then within the parity on 2e5 inputs, 50 times
    as many as the probes, and the order of the running sum is what lets it get there: the same
    weights summed in the drawn order are further off than the ordered ones."""
    d, parity = bench.dataset, 1e-6
    est, model = _parity_fit(bench, parity)
    svd = SVD.of(model.aim.hidden(d.x))
    press = {C: np.mean(loo_residuals(svd, d.t, C) ** 2) for C in LeaveOneOut().C_grid}
    assert min(press, key=press.get) > est.C_                  # active: leave-one-out wants more
    net, limit = est.network_, parity_limit(d.t, parity)
    dense = np.linspace(0.0, 1.0, 200_001).astype(np.float32)
    assert float32_twin_error(net, dense) <= limit
    probes = probe_inputs(d.x)
    rng = np.random.default_rng(0)
    shuffled = [rng.permutation(net.n_hidden) for _ in range(5)]
    others = [float32_twin_error(ElmNetwork(net.activation, net.input_weights[o], net.biases[o],
                                       net.output_weights[o]), probes) for o in shuffled]
    assert float32_twin_error(net, probes) < np.median(others)


def test_accumulation_order_keeps_the_running_sums_small():
    terms = np.array([[100.0, 50.0, -100.0, -50.0, 1.0],
                      [90.0, 45.0, -95.0, -40.0, 1.0]])
    order = accumulation_order(terms)
    assert sorted(order) == list(range(5))
    acc = np.zeros(2)
    for step, k in enumerate(order):     # each step takes the term that keeps max |partial sum| least
        left = order[step:]
        assert np.max(np.abs(acc + terms[:, k])) == min(np.max(np.abs(acc + terms[:, j])) for j in left)
        acc += terms[:, k]
    assert np.max(np.abs(np.cumsum(terms[:, order], axis=1))) < np.max(np.abs(np.cumsum(terms, axis=1)))


def test_loo_solver_parameters_are_checked():
    with pytest.raises(ValueError, match="parity"):
        LeaveOneOut(parity=0.0)
    with pytest.raises(ValueError, match="max_beta_l1"):
        LeaveOneOut(max_beta_l1=-1.0)


def test_cond_from_singular_values_matches_numpy_when_well_conditioned():
    H = np.random.default_rng(5).normal(size=(50, 4))
    assert log10_cond(np.linalg.svd(H, compute_uv=False)) == pytest.approx(
        np.log10(np.linalg.cond(H.T @ H)), rel=1e-9)
    C = 10.0
    assert log10_cond(np.linalg.svd(H, compute_uv=False), C) == pytest.approx(
        np.log10(np.linalg.cond(np.eye(4) / C + H.T @ H)), rel=1e-9)


def test_cond_goes_beyond_where_numpy_saturates(xt):
    x, t = xt
    elm = ELMRegressor(n_hidden=30, scheme="standard", solver="pinv", random_state=0).fit(x, t)
    # standard ELM with 30 neurons: cond(H^T H) far beyond 1e16 (numpy's cond of H^T H saturates)
    assert elm.log10_cond_ > 20
    assert log10_cond(np.array([1.0, 0.5]), n_hidden=3) == np.inf


def test_enlarged_scheme_satisfies_eq_16():
    s = EnlargedScheme(w_max=10.0, r1=0.1, r2=0.9)
    w, b = s.draw(5000, np.random.default_rng(6))
    assert np.all(np.abs(w) <= 10.0)
    h0, h1 = _sigmoid(b), _sigmoid(w + b)
    up = w > 0
    assert np.all(h0[up] <= 0.1 + 1e-12) and np.all(h1[up] >= 0.9 - 1e-12)
    assert np.all(h1[~up] <= 0.1 + 1e-12) and np.all(h0[~up] >= 0.9 - 1e-12)
    assert 0.4 < up.mean() < 0.6


def test_standard_scheme_draws_in_unit_box():
    w, b = StandardScheme().draw(1000, np.random.default_rng(7))
    assert np.all(np.abs(w) <= 1) and np.all(np.abs(b) <= 1)


def test_same_seed_same_bits_other_seed_other_model(xt):
    x, t = xt
    a = ELMRegressor(random_state=11).fit(x, t)
    b = ELMRegressor(random_state=11).fit(x, t)
    c = ELMRegressor(random_state=12).fit(x, t)
    assert np.array_equal(a.beta_, b.beta_) and np.array_equal(a.biases_, b.biases_)
    assert not np.array_equal(a.beta_, c.beta_)


@pytest.mark.parametrize("activation", sorted(ACTIVATIONS))
def test_every_activation_fits_far_better_than_a_constant(xt, activation):
    x, t = xt
    elm = ELMRegressor(n_hidden=20, activation=activation, scheme="standard", solver="loo",
                       random_state=0).fit(x, t)
    resid = np.sqrt(np.mean((elm.predict(x) - t) ** 2))
    assert resid < 0.5 * np.std(t)


def test_default_model_is_accurate_and_float32_friendly(bench, default_model):
    e = bench.errors(default_model.aim)
    # noise is uniform +-0.5 N (std 0.29 N); the noise-free curve must be matched far better
    assert e["e_ttest_newton"] < 0.2
    assert np.abs(default_model.aim.output_weights).sum() <= 100


@pytest.mark.parametrize("kwargs, message", [
    (dict(n_hidden=0), "n_hidden must be a positive integer"),
    (dict(activation="relu"), "activation must be one of"),
    (dict(solver="ridge"), "solver 'ridge' needs C"),
    (dict(solver="lasso"), "solver must be one of"),
    (dict(scheme="wide"), "scheme must be one of"),
])
def test_bad_parameters_are_named(xt, kwargs, message):
    with pytest.raises(ValueError, match=message):
        ELMRegressor(**kwargs).fit(*xt)


def test_bad_scheme_parameters_are_named():
    with pytest.raises(ValueError, match="need 0 < r1 < r2 < 1"):
        EnlargedScheme(r1=0.9, r2=0.1)
    with pytest.raises(ValueError, match="w_max=2 too small"):
        EnlargedScheme(w_max=2)
