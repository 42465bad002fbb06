"""ANFIS baseline (section 3): genfis1 initialization, hybrid learning, model.json round trip."""
import json

import numpy as np
import pytest

from fricgen.fit.anfis import AnfisRegressor, genfis1
from fricgen.networks.anfis import AnfisNetwork
from fricgen.model import FrictionModel, ModelError


def test_genfis1_bell_initialization_matches_matlab():
    net = genfis1(np.array([0.0, 0.3, 1.0]), 4, "bell")
    np.testing.assert_allclose(net.centers, [0.0, 1 / 3, 2 / 3, 1.0])
    np.testing.assert_allclose(net.widths, np.full(4, 1.0 / 6.0))   # (max - min) / (2 (n - 1))
    np.testing.assert_allclose(net.exponents, np.full(4, 2.0))
    np.testing.assert_array_equal(net.slopes, 0.0)
    np.testing.assert_array_equal(net.intercepts, 0.0)
    # neighbouring bells cross at membership 0.5 half-way between centres
    assert net.memberships([1 / 6])[0, 0] == pytest.approx(0.5)


def test_genfis1_gauss_sigma_gives_half_membership_at_a():
    net = genfis1(np.linspace(-1.0, 3.0, 9), 3, "gauss")
    a = 4.0 / 4.0
    np.testing.assert_allclose(net.widths, a / np.sqrt(2 * np.log(2)))
    assert net.memberships([-1.0 + a])[0, 0] == pytest.approx(0.5)
    assert net.exponents is None


@pytest.mark.parametrize("mf", ["bell", "gauss"])
def test_hybrid_learning_lowers_training_error(bench, mf):
    d = bench.dataset
    one_pass = AnfisRegressor(4, mf, epochs=1).fit(d.x, d.t)        # LS consequents only
    trained = AnfisRegressor(4, mf, epochs=60).fit(d.x, d.t)
    e1 = np.sqrt(np.mean((one_pass.predict(d.x) - d.t) ** 2))
    e2 = np.sqrt(np.mean((trained.predict(d.x) - d.t) ** 2))
    assert e2 < 0.9 * e1
    assert e2 == pytest.approx(trained.train_rmse_.min())          # best epoch is kept
    assert trained.n_parameters_ == (20 if mf == "bell" else 16)


def test_step_size_rule_grows_after_four_decreases_and_shrinks_on_oscillation():
    reg = AnfisRegressor(step_increase=1.1, step_decrease=0.9)
    assert reg._adapt_step(1.0, [5, 4, 3, 2, 1]) == pytest.approx(1.1)
    assert reg._adapt_step(1.0, [5, 4, 5, 4, 5]) == pytest.approx(0.9)
    assert reg._adapt_step(1.0, [5, 4, 3, 4, 3]) == 1.0


def test_anfis_model_json_round_trip(bench, tmp_path):
    d = bench.dataset
    est = AnfisRegressor(4, "bell", epochs=10)
    model = FrictionModel.fit(d, est, name="fz")
    path = model.save(tmp_path / "model.json")
    loaded = FrictionModel.load(path)
    assert isinstance(loaded.aim, AnfisNetwork)
    v = np.linspace(-0.1, 0.1, 41)
    np.testing.assert_array_equal(loaded.force(v), model.force(v))


@pytest.mark.parametrize("patch, message", [
    ({"mf": "tri"}, "aim.mf"),
    ({"widths": [0.1, -0.2, 0.1, 0.1]}, "aim.widths"),
    ({"exponents": [2, 2]}, "lengths"),
    ({"slopes": [0, "x", 0, 0]}, "aim.slopes[1]"),
])
def test_anfis_reader_rejects_bad_fields(bench, patch, message):
    model = FrictionModel.fit(bench.dataset, AnfisRegressor(4, epochs=2), name="fz")
    d = json.loads(json.dumps(model.to_dict()))
    d["aim"].update(patch)
    with pytest.raises(ModelError, match=message.replace("[", r"\[").replace("]", r"\]")):
        FrictionModel.from_dict(d)


def test_network_rejects_nonpositive_width():
    with pytest.raises(ValueError, match="widths"):
        AnfisNetwork("gauss", [0.0], [0.0], None, [0.0], [0.0])
