"""Properties [F1]-[F3] owe to the physics, for any parameters (hypothesis): friction is odd
and opposes the motion, g of [F2] falls from 1 towards 0, [F1] without a Stribeck peak
rises with the speed, and [F3] equals [F1] up to v_sat and holds its Stribeck part beyond."""
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from fricgen.codegen.twin import force_f32
from fricgen.friction import SHAPES, multisource
from test_references import float32_bound, table1_curve

#: Few examples, no deadline (a loaded machine) and no example database written beside the tests.
FAST = settings(max_examples=40, deadline=None, database=None)
shapes = st.sampled_from(sorted(SHAPES))
force = st.floats(0.0, 100.0)
speed = st.floats(1e-4, 1.0)
viscous = st.floats(0.0, 100.0)


@st.composite
def sources(draw, max_sources=3):
    n = draw(st.integers(1, max_sources))
    return [(draw(force), draw(force), draw(speed), draw(viscous)) for _ in range(n)]


def _friction(src, shape):
    return multisource(*zip(*src), shape=shape)


@FAST
@given(src=sources(), shape=shapes, v=st.lists(st.floats(-10.0, 10.0), min_size=1, max_size=20))
def test_friction_is_odd_and_opposes_the_motion(src, shape, v):
    f = _friction(src, shape)
    v = np.array(v)
    assert np.array_equal(f(-v), -f(v))
    assert np.all(f(v) * np.sign(v) >= 0)                         # f_c, f_s, B >= 0


@FAST
@given(shape=shapes, vs=speed, a=st.floats(0.0, 20.0), b=st.floats(0.0, 20.0))
def test_g_falls_from_one_towards_zero(shape, vs, a, b):
    g = SHAPES[shape]
    lo, hi = sorted((a * vs, b * vs))
    assert g(np.array(0.0), vs) == 1.0
    assert 0.0 <= float(g(np.array(hi), vs)) <= float(g(np.array(lo), vs)) <= 1.0
    assert float(g(np.array(1e6 * vs), vs)) < 1e-5


@FAST
@given(src=sources(), shape=shapes, a=st.floats(0.0, 2.0), b=st.floats(0.0, 2.0))
def test_without_a_stribeck_peak_friction_rises_with_speed(src, shape, a, b):
    """f_s <= f_c in every source: (f_s - f_c) g rises as g falls, and B v >= 0 rises."""
    src = [(max(fc, fs), min(fc, fs), vs, B) for fc, fs, vs, B in src]
    f = _friction(src, shape)
    lo, hi = sorted((a, b))
    assert float(f(hi)) >= float(f(lo)) - 1e-12 * (1 + abs(float(f(lo))))


@FAST
@given(src=sources(), shape=shapes, v_sat=st.floats(1e-3, 1.0),
       v=st.lists(st.floats(-5.0, 5.0), min_size=1, max_size=20))
def test_eq3_is_eq1_up_to_v_sat_and_holds_the_stribeck_part_beyond(src, shape, v_sat, v):
    f = _friction(src, shape)
    model = table1_curve(shape, src, k_out=1.0 / max(1.0, sum(s[1] for s in src)), v_sat=v_sat)
    v = np.array(v)
    held = np.clip(v, -v_sat, v_sat)
    scale = 1 + np.abs(f(v)) + np.abs(f(held))
    expected = f(held) + f.viscous * (v - held)                  # [F1] at min(|v|, v_sat)
    assert np.all(np.abs(model.force(v) - expected) <= 1e-12 * scale)


@FAST
@given(src=sources(), shape=shapes, impl=st.sampled_from(["libm", "fast"]),
       v=st.lists(st.floats(-0.12, 0.12), min_size=1, max_size=20))
def test_float32_twin_stays_within_its_rounding_bound(src, shape, impl, v):
    model = table1_curve(shape, src, k_out=1.0 / max(1.0, sum(s[1] for s in src)))
    v = np.array(v, dtype=np.float32).astype(float)            # the twin's own inputs
    assert np.all(np.abs(force_f32(model, v, impl) - model.force(v)) <= float32_bound(model, impl))
