"""One estimator contract (scikit-learn's) for every fricgen regressor, and the JSON of every
network kind."""
import numpy as np
import pytest

from fricgen.errors import ModelError
from fricgen.fit import (AnfisRegressor, AutoELMRegressor, ConditionedELMRegressor,
                         DefaultRegressor, ELMRegressor, NotFittedError, OracleRegressor,
                         StribeckRegressor)
from fricgen.fit.elm import EnlargedScheme
from fricgen.model import FrictionModel
from fricgen.networks import KINDS, network_from_dict

#: One small configuration of every estimator (fast enough to fit many times).
ESTIMATORS = {
    "elm": lambda: ELMRegressor(n_hidden=12, scheme=EnlargedScheme(w_max=20.0), random_state=1),
    "auto": lambda: AutoELMRegressor(n_members=2),
    "anfis": lambda: AnfisRegressor(n_mfs=4, epochs=10),
    "conditioned": lambda: ConditionedELMRegressor(n_hidden=6, iterations=3, random_state=1),
    "oracle": lambda: OracleRegressor(grid=4),
    "stribeck": lambda: StribeckRegressor(shapes=("gauss",), sources=(2, 3), grid=4),
    "default": lambda: DefaultRegressor(n_repeats=1),
}


@pytest.mark.parametrize("kind", ESTIMATORS)
def test_params_are_stored_unchanged_and_settable(kind):
    est = ESTIMATORS[kind]()
    params = est.get_params()
    assert params and all(getattr(est, k) is v for k, v in params.items())
    fresh = type(est)(**params)
    assert fresh.get_params() == params
    name = sorted(params)[0]
    assert est.set_params(**{name: params[name]}) is est
    with pytest.raises(ValueError, match="no parameter 'nope'"):
        est.set_params(nope=1)
    assert "(" in repr(est) and type(est).__name__ in repr(est)


@pytest.mark.parametrize("kind", ESTIMATORS)
def test_predict_is_shaped_like_its_input_and_refuses_before_fit(kind, xt):
    x, t = xt
    est = ESTIMATORS[kind]()
    with pytest.raises(NotFittedError, match="not fitted"):
        est.predict(x)
    assert est.fit(x, t) is est
    assert est.predict(0.3).shape == ()
    assert est.predict(x).shape == x.shape
    assert est.predict(x[:, None]).shape == x.shape               # scikit-learn's (n, 1) column
    grid = np.linspace(0, 1, 12).reshape(3, 4)
    np.testing.assert_array_equal(est.predict(grid), est.predict(grid.ravel()).reshape(3, 4))


@pytest.mark.parametrize("kind", ESTIMATORS)
def test_score_is_r2_and_fits_are_repeatable(kind, xt, bench):
    x, t = xt
    a = ESTIMATORS[kind]().fit(x, t)
    y = a.predict(x)
    r2 = 1 - np.sum((t - y) ** 2) / np.sum((t - t.mean()) ** 2)
    assert a.score(x, t) == pytest.approx(r2, rel=1e-12)
    # the training residual is the noise, sd 0.5/sqrt(3) N (uniform +-0.5 N), times
    # sqrt(1 - p/N) for p parameters: above 1.6 sd the model misses the curve by more than
    # 1.25 sd (0.36 N; 1.48 sd reached by the smallest, 6-neuron conditioned ELM), below 0.9 sd
    # it follows the noise (p/N > 0.2; 0.99 sd reached)
    residual_newton = np.sqrt(np.mean((t - y) ** 2)) / bench.dataset.scaling.k_out
    assert 0.9 <= residual_newton / (0.5 / np.sqrt(3)) <= 1.6
    b = ESTIMATORS[kind]().fit(x, t)
    np.testing.assert_array_equal(a.predict(x), b.predict(x))      # same seed, same model


@pytest.mark.parametrize("kind", ESTIMATORS)
def test_every_fitted_network_round_trips_through_model_json(kind, bench, tmp_path):
    model = FrictionModel.fit(bench.dataset, ESTIMATORS[kind](), name="m")
    path = model.save(tmp_path / "m.json")
    back = FrictionModel.load(path)
    v = np.linspace(-0.1, 0.1, 101)
    np.testing.assert_array_equal(back.force(v), model.force(v))
    assert back.model_hash == model.model_hash


def test_conditioned_elm_takes_the_standard_scheme_by_name(xt):
    x, t = xt
    est = ConditionedELMRegressor(n_hidden=6, scheme="standard", iterations=3, random_state=0).fit(x, t)
    assert np.all(np.abs(est.input_weights_) <= 1.0)            # OPT bounded by the scheme's box
    assert est.score(x, t) > 0.9


@pytest.mark.parametrize("kind, field, value, message", [
    ("elm", "activation", "tanh", "aim.activation must be one of"),
    ("anfis", "widths", [0.1, -0.1, 0.1, 0.1], "aim.widths must all be > 0"),
    ("stribeck", "stribeck", [0.1, 0.0], "aim.stribeck must all be > 0"),
    ("stribeck", "shape", "cubic", "aim.shape must be one of"),
    ("stribeck", "offset", "1", "aim.offset must be a number"),
])
def test_each_network_kind_validates_its_own_json(kind, field, value, message, bench):
    est = {"elm": ESTIMATORS["elm"], "anfis": ESTIMATORS["anfis"], "stribeck": ESTIMATORS["oracle"]}[kind]()
    d = est.fit(bench.dataset.x, bench.dataset.t).network_.to_dict()
    assert d["kind"] == kind and KINDS[kind].from_dict(d).to_dict() == d
    with pytest.raises(ModelError, match=message):
        network_from_dict({**d, field: value})


def test_scikit_learn_clone_and_cross_val_score_work(xt):
    sklearn = pytest.importorskip("sklearn")
    from sklearn.base import clone
    from sklearn.model_selection import KFold, cross_val_score
    x, t = xt
    for kind, make in ESTIMATORS.items():
        est = make()
        twin = clone(est)
        assert twin is not est and twin.get_params().keys() == est.get_params().keys()
        scores = cross_val_score(twin, x[:, None], t, cv=KFold(3, shuffle=True, random_state=0))
        assert scores.shape == (3,) and np.all(scores > 0.95), (kind, scores, sklearn.__version__)
