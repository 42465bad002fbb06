"""The grey-box [F1]: variable projection, the honest oracle, the estimator, the default's
choice, gross outliers, and the emitted C against its float32 twin."""
import shutil
from dataclasses import replace
import subprocess

import numpy as np
import pytest

from conftest import assert_builds_strictly
from fricgen import codegen
from fricgen.codegen import parity
from fricgen.codegen.cbuild import build_model
from fricgen.codegen.fast_sigmoid import exp_neg_error_bound, exp_neg_fast_f32
from fricgen.codegen.twin import force_f32
from fricgen.errors import ModelError
from fricgen.firmware import build as fw
from fricgen.data import Sweep, prepare
from fricgen.fit import AutoELMRegressor, DefaultRegressor, OracleRegressor, StribeckRegressor
from fricgen.fit.default import ELM_GAIN_SIGMAS
from fricgen.data.outliers import gross_outliers
from fricgen.fit.stribeck import (AIC_CONTENDERS, AVERAGING_SCALE, akaike_weights, all_subsets,
                                  as_fit, fit_sources)
from fricgen.friction import SHAPES, preset
from fricgen.model import FrictionModel
from fricgen.networks import StribeckCurve

CC = shutil.which("cc") or shutil.which("gcc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler")
EPS32 = float(np.finfo(np.float32).eps)
X = np.linspace(0.0, 1.0, 201)


def curve_data(shape, amplitudes=(0.3, 0.5), stribeck=(0.05, 0.2), offset=0.4, noise=0.0, seed=0):
    truth = StribeckCurve(shape, offset, np.array(amplitudes), np.array(stribeck))
    rng = np.random.default_rng(seed)
    return truth, truth(X) + rng.uniform(-noise, noise, X.size)


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_variable_projection_recovers_eq1_from_exact_data(shape):
    truth, t = curve_data(shape)
    fit = fit_sources(X, t, shape, all_subsets(5, 2))
    np.testing.assert_allclose(fit.curve.stribeck, truth.stribeck, rtol=1e-4)
    np.testing.assert_allclose(fit.curve.amplitudes, truth.amplitudes, rtol=1e-4)
    assert fit.curve.slope == 0.0 and fit.rmse < 1e-8


def test_the_oracle_fits_eq1_alone_with_the_true_shape_and_size(bench):
    d = bench.dataset
    oracle = OracleRegressor("gauss", n_sources=3, grid=5).fit(d.x, d.t)
    net = oracle.network_
    assert net.shape == "gauss" and net.n_sources == 3 and net.slope == 0.0   # no free slope
    assert oracle.n_starts_ == 10                                             # C(5, 3) starts
    # the benchmark's noise is uniform +-0.5 N: [F1] with the true shape fits down to it
    assert bench.errors(oracle.predict)["e_ttest_newton"] < 0.15


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_the_grey_box_chooses_the_shape_that_made_the_data(shape):
    truth, t = curve_data(shape, noise=2e-3, seed=1)
    est = StribeckRegressor(sources=(1, 2, 3)).fit(X, t)
    assert est.shape_ == shape and est.n_sources_ >= 2
    assert np.max(np.abs(est.predict(X) - truth(X))) < 5e-3
    se = est.standard_errors_
    assert se["amplitudes"].shape == se["stribeck"].shape == (est.n_sources_,)
    assert np.all(np.isfinite(se["stribeck"])) and np.all(se["stribeck"] > 0)
    assert est.candidates_[est.best_] == min(est.candidates_.values()) and len(est.candidates_) > 6
    assert est.best_ in est.weights_ and abs(sum(est.weights_.values()) - 1.0) < 1e-12
    assert est.cv_rmse_ > est.train_rmse_ * 0.9


def test_a_warm_copy_repeats_the_procedure_from_the_fit_without_the_multi_start():
    truth, t = curve_data("gauss", noise=0.01, seed=5)
    grey = StribeckRegressor(shapes=("gauss", "exponential"), sources=(1, 2, 3)).fit(X, t)
    warm = grey.warm_copy()
    # the contenders only: the candidates beyond AIC_CONTENDERS are not refitted
    assert warm.n_folds == 0 and set(warm.starts) == set(grey.weights_) < set(grey.fits_)
    warm.fit(X, t)                                        # the same points: the same result
    assert set(warm.fits_) == set(grey.weights_) and warm.weights_.keys() == grey.weights_.keys()
    np.testing.assert_allclose(warm.predict(X), grey.predict(X), atol=1e-6)
    assert warm.cv_residuals_ is None and np.isnan(warm.cv_rmse_)
    fold = np.arange(X.size) % 5 != 0                     # a fold of them: the contenders again
    assert set(grey.warm_copy().fit(X[fold], t[fold]).fits_) <= set(grey.weights_)


def test_akaike_weights_favour_the_smaller_aic_and_drop_the_far_ones():
    w = akaike_weights({"a": 10.0, "b": 10.0 + AVERAGING_SCALE, "c": 10.0 + AIC_CONTENDERS + 0.1})
    assert set(w) == {"a", "b"} and abs(w["a"] + w["b"] - 1.0) < 1e-15
    assert w["a"] / w["b"] == pytest.approx(np.e, rel=1e-12)


def test_the_average_of_close_fits_is_matched_by_one_curve_of_eq1():
    """A one-source and a two-source fit weighted 1/2 each average to a two-source curve: the
    match finds it."""
    lo = StribeckCurve("gauss", 0.4, np.array([0.6]), np.array([0.05]))
    t = lo(X)
    est = StribeckRegressor(shapes=("gauss",), sources=(1, 2))
    est.xs_min_, est.candidates_ = 1e-3, {("gauss", 1, 1.0): 0.0, ("gauss", 2, 1.0): 0.0}
    est.fits_ = {("gauss", 1, 1.0): as_fit(lo, X, t),
                 ("gauss", 2, 1.0): as_fit(StribeckCurve("gauss", 0.4, np.array([0.2, 0.4]),
                                                         np.array([0.05, 0.2])), X, t)}
    est.weights_ = {k: 0.5 for k in est.fits_}
    est.best_ = ("gauss", 1, 1.0)
    average = 0.5 * (lo(X) + est.fits_[("gauss", 2, 1.0)].curve(X))
    match = est._average(X, t, ("gauss",), (1, 2))
    assert match.curve.n_sources == 2 and np.max(np.abs(match.curve(X) - average)) < 1e-6
    np.testing.assert_allclose(match.residuals, t - match.curve(X))
    est.weights_ = {est.best_: 1.0}                    # a single contender is the fit itself
    assert est._average(X, t, ("gauss",), (1, 2)) is est.fits_[est.best_]


def test_the_average_is_stood_for_by_the_nearest_curve_not_by_one_source_fewer():
    """Table 1's three gaussian sources, on a sweep where two and three sources are within the
    noise (their AICc 0.8 apart): the fits are averaged, and the curve kept is the one nearest
    the average, of three sources, as close to the truth as the oracle's. A match of two
    sources also lies within a tenth of the noise of the average, but is twice as far off."""
    law, rng = preset("paper3", "gauss"), np.random.default_rng(5)
    v = np.concatenate([rng.uniform(0.0, 0.06, 200), rng.uniform(0.06, 0.2, 100)])
    data = prepare(Sweep(v, law(v) + rng.uniform(-0.5, 0.5, v.size)), vs_max=0.02)
    grid = np.linspace(0.0, 0.06, 601)[1:]
    grey = StribeckRegressor()
    model = FrictionModel.fit(data, grey)
    assert {k[1] for k in grey.weights_} == {2, 3}
    oracle = FrictionModel.fit(replace(data, x=data.x[data.x > 0], t=data.t[data.x > 0]),
                               OracleRegressor("gauss"))
    errors = [np.sqrt(np.mean((m.force(grid) - law(grid)) ** 2)) for m in (model, oracle)]
    assert grey.n_sources_ == 3 and errors[0] < 1.1 * errors[1]


def test_the_average_is_stood_for_by_no_source_fewer_than_three_points_see():
    """A four-source contender with a narrow negative source at the two slowest points (their
    noise) weighs a third of the average: the curve that stands for the average has no source
    narrower than half the third slowest point's x, and it is the three-source fit."""
    three = StribeckCurve("gauss", 0.4, np.array([0.25, 0.12, 0.3]), np.array([0.08, 0.19, 0.32]))
    four = StribeckCurve("gauss", 0.4, np.array([-0.49, 0.25, 0.12, 0.3]),
                         np.array([0.0035, 0.08, 0.19, 0.32]))
    x = X[1:]
    t = three(x)
    est = StribeckRegressor(shapes=("gauss",), sources=(3, 4))
    est.xs_min_ = 1e-3
    est.fits_ = {("gauss", 3, 1.0): as_fit(three, x, t), ("gauss", 4, 1.0): as_fit(four, x, t)}
    est.candidates_ = {("gauss", 3, 1.0): 0.0, ("gauss", 4, 1.0): 1.4}
    est.weights_ = {("gauss", 3, 1.0): 2 / 3, ("gauss", 4, 1.0): 1 / 3}
    est.best_ = ("gauss", 3, 1.0)
    kept = est._average(x, t, ("gauss",), (3, 4))
    assert kept.curve.n_sources == 3 and kept.curve.stribeck.min() >= 0.5 * np.sort(x)[2]
    np.testing.assert_allclose(kept.curve(x), three(x), atol=1e-9)


def test_sources_that_cancel_with_huge_amplitudes_are_not_chosen(xt):
    x, t = xt
    est = StribeckRegressor(shapes=("gauss",)).fit(x, t)
    assert np.sum(np.abs(est.network_.amplitudes)) <= 10.0


def test_gross_outliers_are_the_spikes_and_bounded_noise_is_kept():
    truth, t = curve_data("gauss", noise=0.01, seed=2)
    assert not gross_outliers(X, t).any()
    spiked = t.copy()
    rows = np.array([0, 3, 50, 120, 200])
    spiked[rows] += 0.5
    found = np.flatnonzero(gross_outliers(X, spiked))
    assert set(found) == {3, 50, 120}            # the ends are the boundary points: never rejected


def test_the_default_chooses_eq1_on_stribeck_data_and_the_elm_elsewhere():
    truth, t = curve_data("exponential", noise=0.01, seed=3)
    stribeck = DefaultRegressor().fit(X, t)
    assert stribeck.choice_ == "stribeck" and stribeck.network_ is stribeck.greybox_.network_
    assert "stribeck" in stribeck.why() and "elm_auto" in stribeck.why()
    step = 1.0 / (1.0 + np.exp(-40.0 * (X - 0.6))) + np.random.default_rng(4).uniform(-0.01, 0.01, X.size)
    elm = DefaultRegressor().fit(X, step)
    assert elm.choice_ == "elm_auto" and elm.cv_rmse_["elm_auto"] < elm.cv_rmse_["stribeck"]
    assert elm.elm_gain_sigmas_ > ELM_GAIN_SIGMAS > stribeck.elm_gain_sigmas_
    assert isinstance(elm.warm_copy(), AutoELMRegressor)
    assert stribeck.warm_copy().starts is not None


def test_elm_auto_must_beat_the_grey_box_by_more_than_the_noise_of_its_cross_validation():
    """A Table 1 sweep (200 points to 3 vs_max, 100 to 10 vs_max, noise +-0.5 N) on which
    elm_auto cross-validates 1 % better, within one standard error of the paired difference:
    the grey-box, 1.7x closer to the truth there, is kept."""
    law, rng = preset("paper3"), np.random.default_rng(218)
    v = np.concatenate([rng.uniform(0.0, 0.06, 200), rng.uniform(0.06, 0.2, 100)])
    data = prepare(Sweep(v, law(v) + rng.uniform(-0.5, 0.5, v.size)), vs_max=0.02)
    model = DefaultRegressor().fit(data.x, data.t)
    assert model.cv_rmse_["elm_auto"] < model.cv_rmse_["stribeck"]
    assert 0.0 < model.elm_gain_sigmas_ <= ELM_GAIN_SIGMAS and model.choice_ == "stribeck"


def test_a_steep_drop_that_the_running_median_suspects_is_kept():
    """Next to v = 0 a narrow Stribeck drop outruns the running median: its points are suspects,
    and the fitted models explain them, so none is rejected."""
    truth = StribeckCurve("exponential", 0.4, np.array([1.0]), np.array([0.01]))
    t = truth(X) + np.random.default_rng(0).uniform(-0.01, 0.01, X.size)
    assert gross_outliers(X, t)[1:3].all()
    est = DefaultRegressor().fit(X, t)
    assert est.n_outliers_ == 0 and est.inliers_.all()
    assert np.max(np.abs(est.predict(X[1:3]) - truth(X[1:3]))) < 0.02


def test_the_default_sets_spikes_aside(xt):
    x, t = xt
    spiked = t.copy()
    spiked[[20, 80, 140]] += np.array([0.5, -0.5, 0.5])
    est = DefaultRegressor().fit(x, spiked)
    assert est.n_outliers_ == 3 and not est.inliers_[[20, 80, 140]].any()
    assert "3 training points rejected" in est.outlier_note()


def test_fast_exp_twin_is_within_its_derived_bound():
    a = np.concatenate([np.linspace(0, 90, 200_001), [0.0, 1e-30, 86.0, 1e30, np.inf]]).astype(np.float32)
    err = np.abs(exp_neg_fast_f32(a).astype(float) - np.exp(-a.astype(float)))
    assert np.max(err) <= exp_neg_error_bound()
    assert np.isnan(exp_neg_fast_f32(np.float32(np.nan)))[0]


@pytest.fixture(scope="module", params=sorted(SHAPES))
def greybox_model(request, bench):
    """Table 1 itself as a grey-box model of [F3] with the benchmark's scaling."""
    d, friction = bench.dataset, preset("paper3", request.param)
    k_in, k_out = d.scaling.k_in, d.scaling.k_out
    sources = friction.sources
    curve = StribeckCurve(request.param, k_out * sum(s.fc for s in sources),
                          np.array([k_out * (s.fs - s.fc) for s in sources]),
                          np.array([k_in * s.vs for s in sources]))
    return FrictionModel(curve, d.scaling, friction.viscous, d.v_sat, name="gb")


@needs_cc
@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_grey_box_c_builds_strictly_and_equals_its_twin(greybox_model, impl, tmp_path):
    files = codegen.emit(greybox_model, tmp_path, "gb", activation_impl=impl)
    assert ("fric_fast.c" in files) == (impl == "fast") == ("fric_kernel.h" not in files)
    # the one libm source a grey-box curve calls, exp(-a), unless its shape is rational
    assert ("fric_exp_neg.c" in files) == (impl == "libm" and greybox_model.aim.shape != "rational")
    text = (tmp_path / "gb.c").read_text()
    assert "static const float gb_inv_stribeck[GB_N_SOURCES]" in text
    assert "expf" not in text                             # through the clamped exponentials
    assert ("fric_exp_neg_f32(" in text) == (impl == "libm" and greybox_model.aim.shape != "rational")
    for src in sorted(p.name for p in tmp_path.glob("*.c")):
        assert_builds_strictly(tmp_path, src, CC)
    lib = build_model(tmp_path, "gb", build_dir=tmp_path / "build")
    v = parity.parity_velocities(greybox_model.v_sat)
    c = parity.c_forces(lib, "gb", v).astype(float)
    twin = force_f32(greybox_model, v, impl).astype(float)
    assert np.mean(c == twin) > 0.99
    a_l1 = np.abs(greybox_model.aim.amplitudes).sum()
    assert np.max(np.abs(c - twin)) <= 4 * EPS32 * (a_l1 + 1) / greybox_model.scaling.k_out
    exact = greybox_model.force(v.astype(float))
    assert np.max(np.abs(c - exact)) <= 1e-5 * np.max(np.abs(exact))
    assert np.isnan(lib.gb_force(float("nan"))) and lib.gb_force(float("inf")) == float("inf")
    assert lib.gb_force(0.0) == 0.0 and lib.gb_force(-0.01) == -lib.gb_force(0.01)


def test_a_trained_grey_box_model_emits_in_q15_within_its_bound(greybox_model):
    """The fitted [F1] as a q15 AIM table (fricgen.codegen.fixed_table): every input within
    the bound NAME.h states."""
    from fricgen.codegen import fixed_table as ft
    files = codegen.render(greybox_model, "gb", dtype="q15")
    spec = ft.TableSpec.of(greybox_model, "q15")
    v_q = np.arange(-2 ** 15, 2 ** 15)
    err = np.abs(ft.force_table_q(spec, v_q) * 2.0 ** -spec.f_f - greybox_model.force(v_q * 2.0 ** -spec.f_v))
    bound = ft.table_error_bound(spec, greybox_model)
    assert err.max() <= bound and f"<= {bound:.3g} N" in files["gb.h"]
    assert f"#define GB_TABLE_SIZE {spec.table.size}" in files["gb.h"] and "float" not in files["gb.c"]


@pytest.mark.skipif(fw.missing_tools() is not None, reason="cross toolchain or QEMU absent")
@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_grey_box_firmware_on_the_emulated_cortex_m4f_equals_its_twin(greybox_model, impl, tmp_path):
    src = tmp_path / "src"
    codegen.emit(greybox_model, src, "gb", activation_impl=impl)
    v = np.linspace(-2 * greybox_model.v_sat, 2 * greybox_model.v_sat, 201).astype(np.float32)
    elf = fw.build_firmware(src, fw.config_float("gb.h", "gb_force", v), "cortex-m4f",
                            tmp_path / "build", strict_model=True)
    out = fw.parse_float_bits(fw.run(elf, "cortex-m4f"))
    twin = force_f32(greybox_model, v, impl)
    if impl == "fast":
        np.testing.assert_array_equal(out, twin)              # no libm: bit for bit
    else:                                                     # newlib's expf: a few ULP
        assert np.max(np.abs(out.astype(float) - twin)) <= 8 * EPS32 * np.max(np.abs(twin))
    exact = greybox_model.force(v.astype(float))
    assert np.max(np.abs(out - exact)) <= 1e-5 * np.max(np.abs(exact))


def test_a_parameter_the_data_do_not_determine_has_an_infinite_standard_error():
    """A Stribeck velocity whose g has no slope at any sample (a zero Jacobian column): pinv
    would give it a standard error of 0; it is undetermined, and the others keep theirs."""
    from fricgen.fit.stribeck import SourcesFit
    from fricgen.networks.stribeck import StribeckCurve
    rng = np.random.default_rng(0)
    J = rng.normal(size=(50, 5))
    curve = StribeckCurve("gauss", 1.0, np.array([0.5, 0.2]), np.array([0.01, 0.1]))
    full = SourcesFit(curve, rng.normal(scale=0.01, size=50), J, 1).standard_errors()
    J[:, 3] = 0.0                        # theta_1 moves nothing
    se = SourcesFit(curve, rng.normal(scale=0.01, size=50), J, 1).standard_errors()
    assert np.isinf(se["stribeck"][0]) and np.isfinite(se["stribeck"][1])
    assert np.isfinite(se["offset"]) and np.all(np.isfinite(se["amplitudes"]))
    assert np.all(np.isfinite(full["stribeck"])) and np.all(full["stribeck"] > 0)


def standstill_spike():
    """Breakaway seen at standstill only: samples at x = 0 and from x = 0.2 up, the x = 0 ones
    0.4 higher. A source with its Stribeck velocity anywhere below ~0.02 fits the spike equally
    well: the data do not determine it."""
    x = np.concatenate([np.zeros(5), np.linspace(0.2, 1.0, 60)])
    truth = StribeckCurve("gauss", 0.4, np.array([0.3]), np.array([0.3]))
    t = truth(x) + np.random.default_rng(0).uniform(-2e-3, 2e-3, x.size)
    t[:5] += 0.4
    return x, t


def test_dropping_an_undetermined_source_refits_the_rest():
    from fricgen.fit.stribeck import drop_undetermined
    x, t = standstill_spike()
    fit = fit_sources(x, t, "gauss", [np.log([0.002, 0.3])])       # 0.002: g = 0 at x >= 0.2
    assert list(fit.undetermined_sources()) == [0]
    kept = drop_undetermined(fit, lambda theta: fit_sources(x, t, "gauss", [theta]))
    assert kept.curve.n_sources == 1 and kept.undetermined_sources().size == 0
    assert kept.curve.stribeck[0] > 0.05                     # where the samples see it


def test_training_drops_the_sources_the_data_do_not_determine():
    """Without the drop, AIC chose 3 sources, one at xs = 0.0067 with an infinite standard error."""
    x, t = standstill_spike()
    est = StribeckRegressor(shapes=("gauss",), sources=(1, 2, 3)).fit(x, t)
    se = est.standard_errors_
    assert np.all(np.isfinite(se["stribeck"])) and np.all(np.isfinite(se["amplitudes"]))
    assert all(f.undetermined_sources().size == 0 for f in est.fits_.values())
    assert all(k[1] == f.curve.n_sources for k, f in est.fits_.items())
    assert est.n_sources_ == est.network_.n_sources


ERRNO_MAIN = r"""
#include <errno.h>
#include <stdio.h>
#include "gb.h"
#include "ge.h"
#include "es.h"
#include "er.h"
int main(void)
{
    float sum = 0.0f;
    int k;
    errno = 0;
    for (k = -2000; k <= 2000; ++k) {
        const float v = (float)k * 1e-3f;
        sum += gb_force(v) + ge_force(v) + es_force(v) + er_force(v);
    }
    printf("%d %d\n", errno, sum == sum);
    return 0;
}
"""


@needs_cc
def test_no_libm_call_of_the_emitted_c_sets_errno(bench, tmp_path):
    """expf's argument is clamped (fric_exp_neg_f32): a Stribeck velocity far below the speeds
    (exp(-u^2) underflowed to 0, errno ERANGE with glibc) and hidden units whose z reaches -300
    (the sigmoid's exp(-z) overflowed) leave errno 0, and the C keeps to its twin."""
    from fricgen.networks import ElmNetwork
    d = bench.dataset
    curves = {"gb": StribeckCurve("gauss", 0.5, np.array([0.3, 0.2]), np.array([0.002, 0.3])),
              "ge": StribeckCurve("exponential", 0.5, np.array([0.3]), np.array([1e-3])),
              "es": ElmNetwork("sigmoid", np.array([-300.0, 5.0]), np.array([0.0, -1.0]),
                               np.array([0.5, 0.5])),
              "er": ElmNetwork("rbf", np.array([300.0, 2.0]), np.array([0.0, 0.0]),
                               np.array([0.5, 0.5]))}
    for name, net in curves.items():
        model = FrictionModel(net, d.scaling, 0.0, d.v_sat, name=name)
        codegen.emit(model, tmp_path, name)
        lib = build_model(tmp_path, name, build_dir=tmp_path / f"build_{name}")
        v = parity.parity_velocities(d.v_sat, 2000)
        c, twin = parity.c_forces(lib, name, v), force_f32(model, v)       # libm: a few ULP
        assert np.max(np.abs(c.astype(float) - twin)) <= 8 * EPS32 * np.max(np.abs(twin)), name
    (tmp_path / "main.c").write_text(ERRNO_MAIN)
    exe = tmp_path / "errno_check"
    subprocess.run([CC, "-std=c99", "-O2", *sorted(str(p) for p in tmp_path.glob("*.c")),
                    "-o", str(exe), "-lm"], check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["0", "1"], out


def test_the_point_at_v_0_is_not_fitted_so_no_narrow_source_follows_it():
    """The [F9] point at x = 0 is the mean of the slowest rows, below F(0) where the Stribeck
    drop has a slope at 0: [F1] extrapolates to it instead of adding a source at XS_MIN."""
    rng = np.random.default_rng(3)
    x = np.concatenate([[0.0], np.sort(rng.uniform(0, 1, 80))])
    curve = lambda u: 0.5 + 0.5 * np.exp(-u / 0.1)          # noqa: E731
    t = curve(x) + rng.uniform(-0.01, 0.01, x.size)
    t[0] = curve(0.0) - 0.15
    grey = StribeckRegressor(n_folds=0).fit(x, t)
    assert grey.n_sources_ == 1 and grey.network_.stribeck[0] > 0.05
    assert abs(grey.predict(np.array([0.0]))[0] - curve(0.0)) < 0.01
