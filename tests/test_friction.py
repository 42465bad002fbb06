import numpy as np
import pytest

from fricgen.friction import SHAPES, MultisourceFriction, multisource, preset


def test_paper3_preset_is_table_1():
    f = preset("paper3")
    assert [(s.fc, s.fs, s.vs, s.B) for s in f.sources] == [
        (4, 8, 0.01, 2.5), (6, 16, 0.005, 50), (5, 20, 0.02, 5)]
    assert f.viscous == pytest.approx(57.5)
    assert f.vs_max == 0.02


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_eq1_matches_a_hand_computation(shape):
    f = preset("paper3", shape)
    v = 0.013
    g = SHAPES[shape]
    expected = sum(fc + (fs - fc) * float(g(np.array(v), vs)) + B * v for fc, fs, vs, B in
                   [(4, 8, 0.01, 2.5), (6, 16, 0.005, 50), (5, 20, 0.02, 5)])
    assert float(f(v)) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_shapes_start_at_one_and_vanish_at_high_speed(shape):
    g = SHAPES[shape]
    assert g(np.array(0.0), 0.01) == 1.0
    assert g(np.array(10.0), 0.01) < 1e-3


def test_friction_is_odd_and_zero_at_standstill():
    f = preset("paper3")
    v = np.linspace(-0.2, 0.2, 1001)
    assert np.array_equal(f(-v), -f(v))
    assert f(0.0) == 0.0
    # the limit from the right is the sum of the static (Stribeck) forces
    assert f.stribeck(0.0) == pytest.approx(8 + 16 + 20)


def test_vectorized_over_any_shape():
    f = preset("paper3")
    v = np.linspace(0, 0.1, 12).reshape(3, 4)
    assert f(v).shape == (3, 4)


def test_bad_parameters_are_named():
    with pytest.raises(ValueError, match="vs must be > 0"):
        multisource([1], [2], [0.0], [1])
    with pytest.raises(ValueError, match="shape must be one of"):
        MultisourceFriction(preset("paper3").sources, shape="cubic")
    with pytest.raises(ValueError, match="equal lengths"):
        multisource([1, 2], [2], [0.1], [1])
    with pytest.raises(ValueError, match="unknown friction preset"):
        preset("paper4")


def test_from_dict_reads_sources_by_name_in_any_key_order():
    """A hand-edited model.json may list a source's keys in any order: each is read by name.
    At v = 0.01 = v_s the exponential source gives 4 + (8 - 4) e^-1 + 2.5 * 0.01 N."""
    d = {"sources": [{"B": 2.5, "vs": 0.01, "fs": 8.0, "fc": 4.0}], "shape": "exponential"}
    f = MultisourceFriction.from_dict(d)
    assert [(s.fc, s.fs, s.vs, s.B) for s in f.sources] == [(4.0, 8.0, 0.01, 2.5)]
    assert float(f(0.01)) == pytest.approx(4.0 + 4.0 * 0.36787944117144233 + 0.025, rel=1e-14)
    assert MultisourceFriction.from_dict(f.to_dict()) == f
