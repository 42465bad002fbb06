"""Online adaptation of the friction model's output parameters (fricgen.control.adaptation):
the regressor reproduces the model, and each safety mechanism is provoked once."""
import numpy as np
import pytest

from fricgen.control.adaptation import (FLAGS, LEAK_TIME, MAX_PARAMS, RATE_TIME, FrictionAdapter,
                                        adapted, parameter_scale)
from fricgen.control.c_abi import FLAGS as CTRL_FLAGS
from fricgen.control.regressor import (Regressor, adapts_offset, parameter_names, trained_parameters,
                                      with_parameters)
from fricgen.errors import ModelError
from fricgen.fit import StribeckRegressor
from fricgen.model import FrictionModel

V = np.array([-0.3, -0.05, -0.004, 0.0, 0.001, 0.01, 0.03, 0.2])


@pytest.fixture(scope="module")
def grey_model(bench):
    return FrictionModel.fit(bench.dataset, StribeckRegressor(), name="gb")


@pytest.fixture(scope="module", params=["elm", "grey", "elm+offset"])
def model(request, default_model, grey_model, offset_model):
    return {"elm": default_model, "grey": grey_model, "elm+offset": offset_model}[request.param]



def test_the_controllers_and_the_adaptations_flags_are_one_family():
    """A bit means one thing in both flags words (fric_adapt_ctrl_step returns their OR): the
    values both define have one meaning, and every flag is one bit of its own."""
    ctrl = {m.value: m.key for m in CTRL_FLAGS.members if m.value}
    adapt = {m.value: m.key for m in FLAGS.members if m.value}
    assert {v: ctrl[v] for v in ctrl.keys() & adapt.keys()} == {v: adapt[v] for v in ctrl.keys() & adapt.keys()}
    assert ctrl.keys() & adapt.keys() == {1, 2, 8}
    values = sorted(ctrl.keys() | adapt.keys())
    assert all(v & (v - 1) == 0 for v in values) and len(set(values)) == len(values)
    keys = {**ctrl, **adapt}
    assert len(set(keys.values())) == len(keys)           # no meaning under two bits

def test_regressor_at_the_trained_parameters_is_the_model(model):
    reg = Regressor(model)
    forces = [f0 + phi @ reg.theta0 for f0, phi in map(reg, V)]
    # float64 sums in another order than [F3]: a few ULP of forces below 100 N
    np.testing.assert_allclose(forces, model.force_with_offset(V), rtol=0, atol=1e-12)
    assert len(parameter_names(model)) == reg.n


def test_float32_regressor_is_within_float_rounding_of_the_model(model):
    reg = Regressor(model, "float32")
    forces = [float(f0 + sum(np.float32(t) * p for t, p in zip(reg.theta0, phi))) for f0, phi in map(reg, V)]
    # float32 rounding of n ~ 10 terms of ~50 N: 1e-4 N
    np.testing.assert_allclose(forces, model.force_with_offset(V), rtol=0, atol=1e-4)


def test_with_parameters_round_trips_and_changes_the_force(model):
    theta = trained_parameters(model)
    assert with_parameters(model, theta).model_hash == model.model_hash
    changed = with_parameters(model, theta * 1.1)
    assert changed.force_with_offset(0.1) == pytest.approx(model.force_with_offset(0.1) * 1.1, rel=1e-9)
    assert changed.axis_offset == pytest.approx(1.1 * model.axis_offset, rel=1e-12)   # training.axis


@pytest.fixture(scope="module")
def asymmetric_model(default_model, grey_model):
    """An ELM curve for v > 0 and a grey-box one (another scaling, B and v_sat) for v < 0."""
    from fricgen.direction import Direction
    g = grey_model
    negative = Direction(g.aim, g.scaling, 1.2 * g.viscous, 0.8 * g.v_sat)
    return FrictionModel.from_directions(default_model.positive, negative, name="asym")


def test_an_asymmetric_model_adapts_each_direction_apart(asymmetric_model, default_model, grey_model):
    m = asymmetric_model
    reg = Regressor(m)
    n_pos = trained_parameters(default_model).size
    assert reg.n == n_pos + trained_parameters(grey_model).size
    assert parameter_names(m)[:2] == ("beta_0+", "beta_1+") and parameter_names(m)[-1] == "B-"
    forces = [f0 + phi @ reg.theta0 for f0, phi in map(reg, V)]
    np.testing.assert_allclose(forces, m.force(V), rtol=0, atol=1e-12)
    for v in V:                            # each direction's features only: the other's are 0
        phi = reg(v)[1]
        assert not np.any(phi[n_pos:] if v > 0 else phi[:n_pos] if v < 0 else phi)
    theta = trained_parameters(m).copy()
    theta[n_pos:] *= 1.1                   # the negative curve's parameters only
    changed = with_parameters(m, theta)
    np.testing.assert_allclose(changed.force(V[V > 0]), m.force(V[V > 0]), rtol=1e-12)
    np.testing.assert_allclose(changed.force(V[V < 0]), 1.1 * m.force(V[V < 0]), rtol=1e-9)
    assert with_parameters(m, trained_parameters(m)).model_hash == m.model_hash
    low, high = FrictionAdapter(m).bounds()
    assert np.all(low < reg.theta0) and np.all(reg.theta0 < high)


def _adapter(model, **kw):
    return FrictionAdapter(model, **kw).reset()


def test_rls_learns_a_scaled_friction(model):
    a = _adapter(model, rule="rls")
    rng = np.random.default_rng(0)
    for v in rng.uniform(-0.2, 0.2, 4000):
        a.rls(v, 1.2 * model.force_with_offset(v))
    test = np.linspace(-0.2, 0.2, 41)
    test = test[np.abs(test) > 0.01]
    err_adapted = max(abs(a.force(v) - 1.2 * model.force_with_offset(v)) for v in test)
    err_fixed = max(abs(model.force_with_offset(v) - 1.2 * model.force_with_offset(v)) for v in test)
    assert err_adapted < 0.1 * err_fixed


def test_projection_keeps_parameters_in_the_box(model):
    a = _adapter(model, box=0.2, e_max=1e6)
    lo, hi = a.bounds()
    flags = [a.rls(v, 1e4 * np.sign(v)) for v in np.tile([0.02, -0.1, 0.15], 50)]
    assert any(f & FLAGS.value("projected") for f in flags)
    assert np.all(a.theta_ >= lo) and np.all(a.theta_ <= hi)
    assert np.any(a.theta_ == hi) or np.any(a.theta_ == lo)


def test_dead_zone_in_velocity_and_in_error(model):
    a = _adapter(model, v_dead=0.005, e_dead=0.5)
    assert a.rls(0.004, 100.0) == FLAGS.value("dead zone")          # sticking speed
    assert a.rls(0.05, float(model.force_with_offset(0.05)) + 0.4) == FLAGS.value("dead zone")  # small error
    np.testing.assert_array_equal(a.theta_, a._theta0)
    assert a.rls(0.05, float(model.force_with_offset(0.05)) + 5.0) & FLAGS.value("dead zone") == 0
    assert not np.array_equal(a.theta_, a._theta0)
    b = _adapter(model, rule="lyapunov", v_dead=0.005, e_dead=1e-4)
    assert b.lyapunov(0.05, 5e-5) == FLAGS.value("dead zone")
    assert b.lyapunov(0.001, 1.0) == FLAGS.value("dead zone")
    np.testing.assert_array_equal(b.theta_, b._theta0)


def test_frozen_while_saturated_or_an_input_is_not_finite(model):
    for rule, update in (("rls", "rls"), ("lyapunov", "lyapunov")):
        a = _adapter(model, rule=rule)
        step = getattr(a, update)
        P = a.P_.copy()
        assert step(0.1, 50.0, hold=True) == FLAGS.value("held")
        for bad in (np.nan, np.inf):
            assert step(bad, 50.0) == FLAGS.value("input fault")
            assert step(0.1, bad) == FLAGS.value("input fault")
        np.testing.assert_array_equal(a.theta_, a._theta0)
        np.testing.assert_array_equal(a.P_, P)


def test_covariance_stays_bounded_without_excitation(model):
    """One velocity only (poor excitation) with fast forgetting: P would grow as lambda^-k in the
    unexcited directions; the trace clamp holds it. At rest (dead zone) P does not change."""
    a = _adapter(model, forgetting=0.99, p0=1e-3, trace_max=0.05)
    flags = [a.rls(0.1, float(model.force_with_offset(0.1)) + 1.0) for _ in range(3000)]
    assert any(f & FLAGS.value("trace clamped") for f in flags)
    assert flags[-1] & FLAGS.value("trace clamped")            # scaled down to the bound, not below
    assert np.sum(np.diag(a.P_) / a._scale2) == pytest.approx(0.05, rel=1e-9)
    assert np.all(np.isfinite(a.P_))
    P = a.P_.copy()
    for _ in range(60000):                          # 60 s at rest at 1 kHz
        a.rls(0.0, 3.0)
    np.testing.assert_array_equal(a.P_, P)


def test_leakage_pulls_toward_the_trained_values(model):
    a = _adapter(model, leak=0.01)
    a.theta_ = a._theta0 + 0.05 * (a._hi - a._theta0)
    before = np.abs(a.theta_ - a._theta0)
    v = 0.1
    a.rls(v, a.force(v))                            # no prediction error: only the leakage acts
    after = np.abs(a.theta_ - a._theta0)
    n_leak = len(after) - adapts_offset(model)      # the axis's offset does not leak
    assert after[:n_leak].sum() == pytest.approx(0.99 * before[:n_leak].sum(), rel=1e-6)
    np.testing.assert_allclose(after[n_leak:], before[n_leak:], rtol=1e-12)


def test_reset_returns_to_the_trained_values(model):
    a = _adapter(model)
    for v in (0.05, -0.1, 0.2):
        a.rls(v, 2 * model.force_with_offset(v))
    assert not np.array_equal(a.theta_, a._theta0)
    a.restart()
    np.testing.assert_array_equal(a.theta_, a._theta0)
    np.testing.assert_array_equal(a.P_, np.diag(a.p0 * a._scale2))


@pytest.mark.parametrize("name, value", [("rule", "x"), ("forgetting", 0.0), ("forgetting", 1.5),
                                         ("p0", -1.0), ("leak", 1.0), ("v_dead", -1.0),
                                         ("trace_max", 1e-9), ("box", 0.0),
                                             ("band", 0.0), ("e_max", -1.0)])
def test_bad_settings_name_the_parameter(default_model, name, value):
    with pytest.raises(ValueError, match=name):
        FrictionAdapter(default_model, **{name: value}).validate()


def test_the_fit_report_states_what_an_update_costs_and_where_adaptation_stops():
    from fricgen.codegen.cost import adapt_instructions
    from fricgen.training.report import adapt_cost
    sizes = np.arange(1, MAX_PARAMS)
    lyapunov, rls = adapt_instructions(sizes), adapt_instructions(sizes, "rls")
    assert np.all(np.diff(lyapunov) > 0) and np.all(rls > lyapunov)     # O(M) and O(M^2) updates
    assert adapt_instructions(10) <= 2000 < adapt_instructions(10, "rls")   # the target at M = 10
    line = adapt_cost(10)
    assert f"about {adapt_instructions(10):.0f} instructions per update" in line and "RLS" in line
    assert "about" in adapt_cost(MAX_PARAMS - 2)                # M units, B and the axis's offset
    assert f"--max-neurons {MAX_PARAMS - 2}" in adapt_cost(MAX_PARAMS - 1)
    assert "about" not in adapt_cost(MAX_PARAMS - 1)


def _expected_update(a, rule, v, e):
    """theta after one update from theta0, from the module doc's laws computed directly: the
    error clamped to +-e_max, then the leakage toward theta0."""
    f0, phi = Regressor(a.model)(v)
    scale2 = parameter_scale(a.model) ** 2
    step = float(np.clip(e, -a.input_limit(), a.input_limit()))
    theta0 = trained_parameters(a.model)
    if rule == "lyapunov":
        updated = theta0 + a.gain() * scale2 * step * phi
    else:
        P = a.p0 * np.diag(scale2)
        updated = theta0 + P @ phi / (a.forgetting_factor() + phi @ P @ phi) * step
    leaks = np.where(np.arange(theta0.size) < theta0.size - adapts_offset(a.model), a.leakage(), 0.0)
    return updated - leaks * (updated - theta0)


@pytest.mark.parametrize("rule", ["rls", "lyapunov"])
@pytest.mark.parametrize("size", ["small", "outlier"])
def test_one_update_is_the_law_with_its_clamp_and_leakage(model, rule, size):
    a = _adapter(model, rule=rule, leak=0.01)
    v = 0.03
    e = (0.3 if size == "small" else 1e20) * a.input_limit()
    if rule == "lyapunov":
        flags = a.lyapunov(v, e)
    else:
        flags = a.rls(v, float(model.force_with_offset(v)) + e)
    np.testing.assert_allclose(a.theta_, _expected_update(a, rule, v, e), rtol=1e-9, atol=1e-12)
    assert bool(flags & FLAGS.value("clamped")) == (size == "outlier")


def test_defaults_leak_for_lyapunov_and_clamp_one_step_to_the_rate(model):
    """Lyapunov's default leakage is Ts / LEAK_TIME and its e_max moves the force by at most
    band Ts / RATE_TIME per update through the friction's parameters, however large e2, and at
    most as much again through the axis's offset; RLS leaks nothing by default."""
    a = _adapter(model)
    assert a.leakage() == pytest.approx(a.ts / LEAK_TIME) and _adapter(model, rule="rls").leakage() == 0
    a.lyapunov(0.03, 1e20)
    budget = a.force_band() * a.ts / RATE_TIME
    offset = a.theta_[-1] - a._theta0[-1] if adapts_offset(model) else 0.0
    assert abs(offset) <= budget * (1 + 1e-9)
    v = np.linspace(-2 * model.v_sat, 2 * model.v_sat, 401)
    moved = np.abs([a.force(u) - model.force_with_offset(u) - offset for u in v])
    assert 0 < moved.max() <= budget * (1 + 1e-9)


def test_the_adapted_force_stays_in_its_band_whatever_the_parameters(model):
    a = _adapter(model, band=2.0)
    v = np.linspace(-3 * model.v_sat, 3 * model.v_sat, 601)
    reg = Regressor(model)
    for corner in (a._hi, a._lo, np.where(np.arange(a._hi.size) % 2, a._hi, a._lo)):
        a.theta_ = corner.copy()
        unsaturated = np.array([phi @ (corner - a._theta0) for _, phi in map(reg, v)])
        assert np.max(np.abs(unsaturated)) > 2.0                 # the box alone lets it out
        gap = np.abs([a.force(u) - model.force_with_offset(u) for u in v])
        assert gap.max() <= 2.0 + 1e-9


@pytest.mark.parametrize("rule", ["rls", "lyapunov"])
def test_a_speed_beyond_v_max_changes_nothing(model, rule):
    """The viscous feature is v itself: one glitch of v = 1e20 would move B to its box."""
    a = _adapter(model, rule=rule)
    update = getattr(a, rule)
    assert a.speed_limit() == pytest.approx(10 * model.v_sat)
    assert update(1e20, 1e-3) == FLAGS.value("out of range")
    assert update(-1.01 * a.speed_limit(), 1e-3) == FLAGS.value("out of range")
    np.testing.assert_array_equal(a.theta_, a._theta0)
    assert update(0.99 * a.speed_limit(), 1e-2) & FLAGS.value("out of range") == 0


def test_an_error_at_its_clamp_or_an_update_onto_the_box_edge_is_no_event(model):
    """CLAMPED means an error beyond +-e_max and PROJECTED an update beyond the box: exactly at
    the limit neither flag is raised (the flags count the events the campaign counts)."""
    a = _adapter(model, rule="lyapunov", leak=0.0)
    limit = a._e_max
    assert a._clamp(limit) == (limit, 0) and a._clamp(-limit) == (-limit, 0)
    assert a._clamp(np.nextafter(-limit, -np.inf))[1] == FLAGS.value("clamped")
    assert a._finish(a._lo.copy(), 0, 0.0) == 0 and np.array_equal(a.theta_, a._lo)
    assert a._finish(a._lo - 1.0, 0, 0.0) == FLAGS.value("projected")
