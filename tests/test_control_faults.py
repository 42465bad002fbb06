"""The contract of fric_ctrl.h under fault injection: NaN, +-inf, 1e20 and denormals in every
controller input at random steps of a closed loop (10 s at 1 kHz here; 60 s in
benchmarks/controller_faults.py). The C and its float32 twin agree bit for bit throughout."""
import shutil

import numpy as np
import pytest

from fricgen.control.backstepping import AdaptiveBackstepping
from fricgen.control.c_abi import FLAGS
from fricgen.control.c_controller import CController, build_controller
from fricgen.control.faults import INPUTS, KINDS, Glitched, random_glitches
from fricgen.control.loop import default_axis, simulate

CC = shutil.which("cc") or shutil.which("gcc")
pytestmark = pytest.mark.skipif(CC is None, reason="no C compiler")

FAULT, SATURATED, PROJECTED = (FLAGS.value(k) for k in ("input fault", "saturated", "projected"))
DURATION, N_GLITCHES, LAST_GLITCH = 10.0, 90, 8.0   # s, count, all glitches end before (s)


@pytest.fixture(scope="module")
def module():
    return build_controller()


@pytest.fixture(scope="module")
def runs(module, default_model):
    """The C controller and its twin with the same glitches, and the twin without glitches."""
    settings = AdaptiveBackstepping(compensation=default_model)
    n_glitched = int(LAST_GLITCH / settings.ts)
    glitches = random_glitches(n_glitched, np.random.default_rng(0), N_GLITCHES, first=500)
    c, twin = Glitched(CController(module, settings), glitches), \
        Glitched(settings.clone(dtype="float32"), glitches)
    clean = Glitched(settings.clone(dtype="float32"), [])
    loops = simulate(default_axis(), [c, twin, clean], duration=DURATION, substeps=2)
    return settings, glitches, (c, twin, clean), loops


def test_every_input_gets_every_kind_of_glitch(runs):
    _, glitches, _, _ = runs
    assert {(g.input, g.kind) for g in glitches} == {(i, k) for i in INPUTS for k in KINDS}


def test_current_stays_finite_within_the_limit_and_estimates_within_their_bounds(runs):
    settings, _, _, (c_run, twin_run, _) = runs
    for run in (c_run, twin_run):
        assert run.finite
        assert np.all(np.abs(run.i) <= settings.i_max)
        assert np.all((settings.a_min[0] <= run.m_o_hat) & (run.m_o_hat <= settings.a_max[0]))
        assert np.all((settings.a_min[1] <= run.k_hat) & (run.k_hat <= settings.a_max[1]))


def test_c_and_twin_agree_bit_for_bit_through_the_glitches(runs):
    _, _, (c, twin, _), (c_run, twin_run, _) = runs
    for name in ("i", "m_o_hat", "k_hat", "x"):
        a, b = getattr(c_run, name).astype(np.float32), getattr(twin_run, name).astype(np.float32)
        assert np.array_equal(a.view(np.uint32), b.view(np.uint32)), name
    assert c.flags_ == twin.flags_
    assert np.array_equal(np.array(c.rows_).view(np.uint32), np.array(twin.rows_).view(np.uint32))


def test_flags_say_what_happened(runs):
    settings, glitches, (c, _, _), (c_run, _, _) = runs
    flags = np.array(c.flags_)
    rows = np.array(c.rows_)
    non_finite = ~np.all(np.isfinite(rows), axis=1)
    fault, saturated = (flags & FAULT) > 0, (flags & SATURATED) > 0
    assert np.array_equal(fault & non_finite, non_finite)      # every non-finite input is a fault
    huge = np.zeros(flags.size, dtype=bool)
    for g in glitches:
        if g.kind == "1e20":
            huge[g.start:g.end] = True
    assert not np.any(fault & ~non_finite & ~huge)             # else only a NaN demand from 1e20
    assert np.all(c_run.i[fault] == 0.0)                       # a fault gives 0 A
    assert np.all(np.abs(c_run.i[saturated]) == np.float32(settings.i_max))
    assert not np.any(fault & saturated)
    frozen = fault | saturated                                 # no adaptation: estimates held
    for name in ("m_o_hat", "k_hat"):
        a = getattr(c_run, name)
        assert np.all(a[1:][frozen[1:]] == a[:-1][frozen[1:]]), name
    assert fault.sum() >= non_finite.sum() > 100 and saturated.any()


def test_tracking_recovers_after_the_last_glitch(runs):
    settings, _, _, (c_run, _, clean_run) = runs
    tail = c_run.t >= LAST_GLITCH + 1.0                         # one second after the last end
    rms = lambda e: float(np.sqrt(np.mean(e[tail] ** 2)))
    assert rms(c_run.e1) <= 2.0 * rms(clean_run.e1)
    assert np.all(np.array(runs[2][0].flags_)[int(LAST_GLITCH / settings.ts):] & FAULT == 0)


# ----------------------------------------------------------------------------- single steps


def c_state(module, settings):
    ffi, lib = module.ffi, module.lib
    c = ffi.new("fric_ctrl_t *")
    assert lib.fric_ctrl_init(c, CController(module, settings).params()) == 0
    return c


def test_null_pointers_return_a_fault_and_write_nothing(module):
    ffi, lib = module.ffi, module.lib
    c = c_state(module, AdaptiveBackstepping())
    before = bytes(ffi.buffer(c))
    current = ffi.new("float *", 123.0)
    null = FLAGS.value("NULL pointer")
    assert lib.fric_ctrl_step(ffi.NULL, 0, 0, 0, 0, 0, 0, current) == null
    assert lib.fric_ctrl_step(c, 0, 0, 1, 0, 0, 0, ffi.NULL) == null
    assert lib.fric_ctrl_step_fn(ffi.NULL, 0, 0, 0, 0, 0, ffi.NULL, current) == null
    assert lib.fric_ctrl_step_fn(c, 0, 0, 1, 0, 0, ffi.NULL, ffi.NULL) == null
    assert current[0] == 123.0 and bytes(ffi.buffer(c)) == before
    lib.fric_ctrl_default_params(ffi.NULL)                      # no crash
    assert lib.fric_ctrl_init(ffi.NULL, ffi.NULL) == -1


@pytest.mark.parametrize("value", [float("nan"), 1e20])
def test_the_reviews_glitch_in_v_no_longer_poisons_the_controller(module, value):
    """One bad velocity at tick 1000 (NaN, or 1e20 that drove k_hat to -inf before the
    projection), then v = 0.01: every later current is finite, and the controller is the same
    as one that skipped tick 1000 (nothing of the glitch is remembered)."""
    settings = AdaptiveBackstepping(compensation=lambda v: 20.0 * np.tanh(v / 0.01))
    hit, skipped = CController(module, settings).reset(), CController(module, settings).reset()
    for k in range(2000):
        if k == 1000:
            i = hit.step(0.0, value, 0.0, 0.0, 0.0)
            assert hit.flags_ & (FAULT | SATURATED) and abs(i) in (0.0, np.float32(settings.i_max))
            continue
        i, i_skipped = hit.step(0.0, 0.01, 0.0, 0.0, 0.0), skipped.step(0.0, 0.01, 0.0, 0.0, 0.0)
        assert np.isfinite(i) and abs(i) <= settings.i_max
        assert hit.adaptive_parameters == skipped.adaptive_parameters and i == i_skipped


def test_estimates_are_projected_onto_their_interval(module):
    """A large velocity error pushes k_hat up at each step (e2 xi1 > 0, law a): it stops at
    k_max, flagged; the twin does the same."""
    settings = AdaptiveBackstepping(compensation=lambda v: 0.0 * v + 50.0, law="a",
                                    gamma=(1.0, 2000.0), a_max=(1.0, 1.5), i_max=1e3)
    c, twin = CController(module, settings).reset(), settings.clone(dtype="float32").reset()
    for _ in range(50):
        i = c.step(0.0, -0.05, 0.0, 0.0, 0.0)
        assert i == twin.step(0.0, -0.05, 0.0, 0.0, 0.0) and c.flags_ == twin.flags_
    assert c.adaptive_parameters[1] == 1.5 and c.flags_ & PROJECTED


def test_saturation_freezes_adaptation(module):
    settings = AdaptiveBackstepping(i_max=1.0)
    c = CController(module, settings).reset()
    a0 = c.adaptive_parameters
    assert c.step(0.0, 0.0, 1.0, 0.0, 0.0) == 1.0 and c.flags_ == SATURATED
    assert c.step(0.0, 0.0, -1.0, 0.0, 0.0) == -1.0 and c.flags_ == SATURATED
    assert c.adaptive_parameters == a0


@pytest.mark.parametrize("changes, message", [
    (dict(a_min=(0.2, 0.0)), "a0 must lie within"),
    (dict(a_max=(1.0, 0.5)), "a0 must lie within"),
    (dict(a_min=(0.01, 2.0), a_max=(1.0, 2.0), a0=(0.1, 2.0)), "a_min must be < a_max"),
    (dict(a_max=(float("inf"), 10.0)), "a_max must be 2 finite numbers"),
])
def test_bad_bounds_are_refused_by_python_and_by_fric_ctrl_init(module, changes, message):
    settings = AdaptiveBackstepping(**changes)
    with pytest.raises(ValueError, match=message):
        settings.reset()
    ffi, lib = module.ffi, module.lib
    p = ffi.new("fric_ctrl_params_t *")
    lib.fric_ctrl_default_params(p)
    a0, lo, hi = settings.a0, settings.a_min, settings.a_max
    p.m_o_hat0, p.k_hat0, p.m_o_min, p.k_min, p.m_o_max, p.k_max = (*a0, *lo, *hi)
    assert lib.fric_ctrl_init(ffi.new("fric_ctrl_t *"), p) == -2


def test_no_compensation_and_an_overflowing_friction_velocity_give_zero_force():
    """Without a model the compensation is 0; with friction_input "vd", a v_d that overflows
    float32 from finite inputs (x_d - x = 6e38) is not passed to the model (as the C does not
    call it there): 0, while a usable v_d gets the model's force."""
    from fricgen.control.backstepping import AdaptiveBackstepping
    assert AdaptiveBackstepping().reset().friction_force(0.1) == 0.0
    model = AdaptiveBackstepping(compensation=lambda v: 5.0, friction_input="vd", dtype="float32").reset()
    with np.errstate(over="ignore"):                    # the overflow is the point
        assert model.compensation_force(-3.0e38, 0.0, 3.0e38, 0.0) == 0.0
    assert model.compensation_force(0.0, 0.0, 0.01, 0.1) == 5.0
