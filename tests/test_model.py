import copy
import json

import numpy as np
import pytest

from fricgen import codegen
from fricgen.model import FrictionModel, ModelError


def test_force_is_exactly_odd(default_model):
    v = np.linspace(-0.3, 0.3, 20001)
    assert np.array_equal(default_model.force(-v), -default_model.force(v))
    assert default_model.force(0.0) == 0.0


def test_network_input_saturates_beyond_v_sat(default_model):
    m = default_model
    v = np.array([0.06, 0.07, 0.5, 3.0])
    stribeck = m.force(v) - m.viscous * v
    assert np.allclose(stribeck, stribeck[0], rtol=0, atol=1e-12)
    assert m.network_input(np.array([-5.0]))[0] == pytest.approx(1.0)


def test_model_reproduces_the_benchmark_curve(bench, default_model):
    v = bench.theory.v[1:]
    err = default_model.force(v) - bench.friction(v)
    # least squares of M parameters on N points of noise sd 0.5/sqrt(3) N (uniform +-0.5 N)
    # misses the truth by about sd sqrt(M/N) RMS (0.058 N for 8 neurons; 0.073 N reached): twice it
    bound = 2 * 0.5 / np.sqrt(3) * np.sqrt(default_model.aim.n_hidden / bench.dataset.x.size)
    assert np.sqrt(np.mean(err ** 2)) < bound


def test_save_load_round_trip(tmp_path, default_model):
    path = default_model.save(tmp_path / "m.json")
    back = FrictionModel.load(path)
    v = np.linspace(-0.2, 0.2, 999)
    assert np.array_equal(back.force(v), default_model.force(v))
    assert back.model_hash == default_model.model_hash
    assert back.name == default_model.name


def test_save_refuses_a_read_only_file_unless_forced(tmp_path, default_model):
    path = tmp_path / "m.json"
    path.write_text("kept\n")
    path.chmod(0o444)
    with pytest.raises(PermissionError, match="read-only"):
        default_model.save(path)
    assert path.read_text() == "kept\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.json"]
    default_model.save(path, force=True)
    assert FrictionModel.load(path).model_hash == default_model.model_hash


def _mutations():
    yield "missing aim", lambda d: d.pop("aim"), "aim"
    yield "missing scaling", lambda d: d.pop("scaling"), "scaling"
    yield "missing k_out", lambda d: d["scaling"].pop("k_out"), "k_out"
    yield "missing biases", lambda d: d["aim"].pop("biases"), "biases"
    yield "wrong lengths", lambda d: d["aim"]["biases"].pop(), "lengths"
    yield "nan weight", lambda d: d["aim"]["output_weights"].__setitem__(0, float("nan")), "finite"
    yield "inf viscous", lambda d: d.__setitem__("viscous", float("inf")), "finite"
    yield "string number", lambda d: d.__setitem__("v_sat", "0.06"), "must be a number"
    yield "negative v_sat", lambda d: d.__setitem__("v_sat", -1.0), "must be > 0"
    yield "zero k_in", lambda d: d["scaling"].__setitem__("k_in", 0), "must be > 0"
    yield "bool weight", lambda d: d["aim"]["biases"].__setitem__(0, True), "finite number"
    yield "unknown version", lambda d: d.__setitem__("format_version", 4), "unknown format_version"
    yield "wrong format", lambda d: d.__setitem__("format", "onnx"), "format must be"
    yield "unknown activation", lambda d: d["aim"].__setitem__("activation", "relu"), "activation"
    yield "unknown kind", lambda d: d["aim"].__setitem__("kind", "svm"), "aim.kind"
    yield "asymmetric", lambda d: d.__setitem__("symmetric", False), "symmetric"
    yield "effects not list", lambda d: d.__setitem__("effects", "none"), "effects"
    yield "empty weights", lambda d: [d["aim"].__setitem__(k, []) for k in
                                      ("input_weights", "biases", "output_weights")], "list of 1 to"


@pytest.mark.parametrize("label, mutate, message", list(_mutations()), ids=[m[0] for m in _mutations()])
def test_invalid_model_json_is_named(default_model, label, mutate, message):
    d = copy.deepcopy(default_model.to_dict())
    mutate(d)
    with pytest.raises(ModelError, match=message):
        FrictionModel.from_dict(json.loads(json.dumps(d)))


@pytest.mark.parametrize("name", ["", "1abc", "fm-1", "fm;system(\"rm -rf /\");", "int", "static",
                                  "a" * 64, "fm\n#include <stdio.h>", "fm */ int x; /*", 42, None,
                                  [1], {"a": 1}])
def test_hostile_names_are_refused(default_model, name):
    d = copy.deepcopy(default_model.to_dict())
    d["name"] = name
    message = "name must not be a C keyword" if name in ("int", "static") else "name must be a C identifier"
    with pytest.raises(ModelError, match=message):
        FrictionModel.from_dict(d)


@pytest.mark.parametrize("name", ["_", "_stdint", "_math", "__reserved", "_Upper"])
def test_names_reserved_by_c_are_refused(default_model, name):
    d = copy.deepcopy(default_model.to_dict())
    d["name"] = name
    with pytest.raises(ModelError, match="name must not begin with '_'"):
        FrictionModel.from_dict(d)


def test_models_named_with_the_runtime_prefix_still_load_but_do_not_emit(default_model):
    # model.json files of earlier versions carry the old default name fric_model
    d = copy.deepcopy(default_model.to_dict())
    d["name"] = "fric_model"
    model = FrictionModel.from_dict(d)
    assert model.name == "fric_model"
    with pytest.raises(ModelError, match="name must not begin with 'fric_'"):
        codegen.render(model)


def test_unreadable_and_non_json_files(tmp_path):
    with pytest.raises(ModelError, match="cannot read"):
        FrictionModel.load(tmp_path / "absent.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(ModelError, match="not valid JSON"):
        FrictionModel.load(bad)
    bad.write_text("[1, 2]")
    with pytest.raises(ModelError, match="JSON object"):
        FrictionModel.load(bad)
