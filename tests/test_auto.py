"""The automatic ELM: leave-one-out algebra, unit placement, float32 bound, default estimator."""
import numpy as np
import pytest

from fricgen.fit.auto import AutoELMRegressor, forward_selection, sigmoid_dictionary
from fricgen.data import synthesize_benchmark
from fricgen.fit import ELMRegressor, default_elm
from fricgen.fit.elm import SVD, float32_error, loo_residuals, parity_limit, prefix_loo_residuals
from fricgen.networks.elm import hidden_matrix
from fricgen.friction import preset
from fricgen.model import FrictionModel
from fricgen.paper.reported import HEADLINE_ELMS


def _brute_force_loo(H, t, C):
    out = np.empty_like(t)
    for i in range(t.size):
        keep = np.arange(t.size) != i
        beta = SVD.of(H[keep]).solve(t[keep], C)
        out[i] = t[i] - H[i] @ beta
    return out


@pytest.mark.parametrize("C", [1e2, 1e6, np.inf])
def test_closed_form_loo_equals_brute_force(C):
    rng = np.random.default_rng(3)
    x = rng.uniform(0, 1, 40)
    t = np.sin(3 * x) + 0.05 * rng.normal(size=40)
    H = hidden_matrix("sigmoid", x, rng.uniform(-8, 8, 6), rng.uniform(-4, 4, 6))
    np.testing.assert_allclose(loo_residuals(SVD.of(H), t, C), _brute_force_loo(H, t, C),
                               rtol=1e-6, atol=1e-9)


def test_prefix_loo_residuals_equal_one_svd_per_prefix(bench):
    """One QR for every prefix, as AutoELMRegressor scores its candidate sizes; a prefix that is
    rank deficient (a repeated column, the 6th) falls back to its own SVD."""
    d = bench.dataset
    w, b = sigmoid_dictionary(0.0, 1.0, 8, (3.0, 24.0))
    D = hidden_matrix("sigmoid", d.x, w, b)
    order = forward_selection(D, d.t, 12)
    cols = D[:, order[:5] + [order[2]] + order[5:]]
    fast = prefix_loo_residuals(cols, d.t)
    assert fast.shape == (d.t.size, cols.shape[1])
    for m in range(1, cols.shape[1] + 1):
        one = loo_residuals(SVD.of(cols[:, :m]), d.t, np.inf)
        np.testing.assert_allclose(fast[:, m - 1], one, rtol=1e-7, atol=1e-9 * np.max(np.abs(d.t)))


def test_loo_of_the_average_is_the_average_of_member_loo(bench):
    """The identity AutoELMRegressor.loo_rmse_ relies on, checked by brute force on 2 members."""
    d = bench.dataset
    x, t = d.x[::4], d.t[::4]
    members = []
    for shift in (0.0, 0.5):
        w, b = sigmoid_dictionary(0.0, 1.0, 6, (4.0, 16.0), shift)
        H = hidden_matrix("sigmoid", x, w, b)
        members.append((H, 1e4))
    closed = np.mean([loo_residuals(SVD.of(H), t, C) for H, C in members], axis=0)
    brute = np.mean([_brute_force_loo(H, t, C) for H, C in members], axis=0)
    np.testing.assert_allclose(closed, brute, rtol=1e-6, atol=1e-9)


def test_forward_selection_is_greedy_least_squares():
    """Each pick is the column whose addition lowers the least-squares residual most."""
    rng = np.random.default_rng(0)
    x = np.linspace(0, 1, 101)
    w, b = sigmoid_dictionary(0.0, 1.0, 11, (5.0, 40.0))
    D = hidden_matrix("sigmoid", x, w, b)
    t = 2.0 * D[:, 3] - 1.0 * D[:, 17] + 0.01 * rng.normal(size=x.size)
    order = forward_selection(D, t, 4)
    assert forward_selection(D, D[:, 7], 1) == [7]
    for m in range(1, 4):
        def rss(cols):
            coef, *_ = np.linalg.lstsq(D[:, cols], t, rcond=None)
            return np.sum((D[:, cols] @ coef - t) ** 2)
        others = [rss(order[:m - 1] + [k]) for k in range(D.shape[1]) if k not in order[:m - 1]]
        assert rss(order[:m]) == pytest.approx(min(others), rel=1e-6)


@pytest.mark.parametrize("force", [lambda v: 5.0 + 10.0 * v, lambda v: 5.0 + 0.0 * v])
def test_exact_data_with_few_rows_fits(force):
    """Exact data on fewer rows than the dictionary has units: the selection stops at the rows
    (it used to pick a unit more, past the leave-one-out residuals it had) and the fit is close."""
    x = np.linspace(0.001, 0.1, 20)
    w, b = sigmoid_dictionary(x.min(), x.max(), 40, (5.0, 40.0))
    assert len(forward_selection(hidden_matrix("sigmoid", x, w, b), force(x), 64)) <= x.size
    fit = AutoELMRegressor().fit(x, force(x))
    np.testing.assert_allclose(fit.predict(x), force(x), atol=1e-3 * np.max(force(x)))


def test_dictionary_centres_cover_the_range_and_steepness_scales():
    w, b = sigmoid_dictionary(0.0, 2.0, 5, (4.0, 8.0))
    assert w[-1] == 0.0 and b[-1] == 0.0                       # the constant unit
    centres = -b[:-1] / w[:-1]
    assert centres.min() == pytest.approx(-0.1) and centres.max() == pytest.approx(2.0)
    assert set(np.round(w[:-1], 9)) == {2.0, 4.0}                # steepness / range


def test_auto_keeps_the_float32_error_within_the_parity_bound(bench):
    est = AutoELMRegressor().fit(bench.dataset.x, bench.dataset.t)
    H = est.network_.hidden(bench.dataset.x)
    assert float32_error(H, est.beta_) <= parity_limit(bench.dataset.t)
    # the average is the union of the members' units: no fewer than one member holds, no more
    # than all of them together, each member within its cap
    assert 1 <= est.member_sizes_.size <= est.n_members
    assert np.all((est.member_sizes_ >= 1) & (est.member_sizes_ <= est.max_hidden))
    assert est.member_sizes_.max() <= est.network_.n_hidden <= est.member_sizes_.sum()
    assert np.isfinite(est.log10_cond_)
    assert 0 < est.loo_rmse_ < 0.02


def test_auto_is_deterministic(bench):
    a = AutoELMRegressor().fit(bench.dataset.x, bench.dataset.t)
    b = AutoELMRegressor().fit(bench.dataset.x, bench.dataset.t)
    np.testing.assert_array_equal(a.beta_, b.beta_)


def test_default_elm_is_the_auto_model_and_round_trips(bench, tmp_path):
    est = default_elm(0)
    assert isinstance(est, AutoELMRegressor)
    model = FrictionModel.fit(bench.dataset, est, name="auto_m")
    loaded = FrictionModel.load(model.save(tmp_path / "m.json"))
    v = np.linspace(-0.1, 0.1, 51)
    np.testing.assert_array_equal(loaded.force(v), model.force(v))


def test_auto_beats_every_paper_elm_on_fixed_seeds():
    """Theoretical error in newtons, 4 fixed seeds: auto at least 2x below the best paper ELM."""
    auto, paper_best = [], []
    for seed in range(4):
        bench = synthesize_benchmark(preset("paper3"), seed=seed)
        d = bench.dataset
        auto.append(bench.errors(AutoELMRegressor().fit(d.x, d.t).predict)["e_ttest_newton"])
        paper_best.append(min(
            bench.errors(ELMRegressor(random_state=seed, **cfg).fit(d.x, d.t).predict)["e_ttest_newton"]
            for cfg in HEADLINE_ELMS.values()))
    assert np.median(auto) < 0.5 * np.median(paper_best)


@pytest.mark.parametrize("kw, message", [
    (dict(n_members=0), "n_members"), (dict(n_centres=1), "n_centres"),
    (dict(steepness=(4.0, -1.0)), "steepness"), (dict(max_beta_l1=0.0), "max_beta_l1"),
    (dict(tolerance_se=-1.0), "tolerance_se"), (dict(resolution=float("nan")), "resolution"),
    (dict(max_neurons=0), "max_neurons"),
])
def test_bad_parameters_are_named(kw, message):
    with pytest.raises(ValueError, match=message):
        AutoELMRegressor(**kw).fit(np.linspace(0, 1, 10), np.zeros(10))


def test_auto_takes_the_smallest_candidate_within_one_standard_error(bench):
    d = bench.dataset
    default = AutoELMRegressor().fit(d.x, d.t)
    best = AutoELMRegressor(tolerance_se=0.0, resolution=0.0).fit(d.x, d.t)
    # the best candidate by PRESS is at least as large, and the default's PRESS (of the
    # pseudo-inverse candidates) lies within one standard error of it
    assert best.n_hidden >= default.n_hidden
    assert default.press_best_ == best.press_best_
    members = default._members(d.x, d.t)
    scale = float(np.max(np.abs(d.t)))
    _, chosen = default._choose(members, d.t.size, scale)
    assert chosen[0] == default.n_hidden
    assert chosen[1] <= default.press_best_ + max(default.press_se_, (default.resolution * scale) ** 2)


@pytest.mark.parametrize("cap", [1, 3, 6])
def test_max_neurons_caps_the_model(bench, cap):
    d = bench.dataset
    est = AutoELMRegressor(max_neurons=cap).fit(d.x, d.t)
    assert 1 <= est.n_hidden <= cap
    assert np.all(np.isfinite(est.predict(d.x)))


def test_resolution_counts_close_candidates_as_equal(bench):
    """Candidates within ``resolution`` (RMS, of max |t|) of the best are equal: a resolution
    of the whole force scale leaves the smallest candidate, one unit."""
    d = bench.dataset
    assert AutoELMRegressor(resolution=1.0).fit(d.x, d.t).n_hidden == 1
    assert AutoELMRegressor(resolution=0.0).fit(d.x, d.t).n_hidden > 1
