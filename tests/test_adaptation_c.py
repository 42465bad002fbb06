"""The adaptation runtime c_runtime/fric_adapt.c and the regressor `fricgen emit --adapt`
generates: strict build, emit unchanged without --adapt, and the whole adapted closed loop
bit-equal to its float32 twin (fricgen.control.adaptation with dtype="float32").

Bit-equality: the C and the twin perform the same float operations in the same order. With
--activation-impl fast no libm function is involved, so equality is exact by construction on
every platform: the step-for-step tests use it (EXACT). With libm the twin takes expf as
correctly rounded and a libm's expf may differ by 1 ULP (glibc's does for 82 of 100000
regressor calls), so the libm loops are compared within the twin's bound, never bit for bit."""
import re
import shutil
import subprocess

import numpy as np
import pytest

from conftest import with_axis
from fricgen.cli import main
from fricgen.codegen import CONTROLLER_FILES, RUNTIME_FILES, emit
from fricgen.codegen.cbuild import CFLAGS, STRICT_WARNINGS
from fricgen.codegen.render import render
from fricgen.control.adaptation import FLAGS, MAX_PARAMS, SETTLE, FrictionAdapter, adapted
from fricgen.control.c_abi import FLAGS as CTRL_FLAGS
from fricgen.control.c_adapted import CAdaptedController, build_adapted, c_params, render_adapt
from fricgen.control.loop import default_axis, simulate
from fricgen.errors import ModelError
from fricgen.firmware import flag_matrix
from fricgen.fit import StribeckRegressor
from fricgen.model import FrictionModel
from fricgen._io import resource_dir

CC = shutil.which("cc") or shutil.which("gcc")
#: The activation of the step-for-step tests: no libm call, so C and twin agree bit for bit.
EXACT = "fast"
pytestmark = pytest.mark.skipif(CC is None, reason="no C compiler")


@pytest.fixture(scope="module")
def grey_model(bench):
    return FrictionModel.fit(bench.dataset, StribeckRegressor(), name="gb")


@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_adapt_folder_builds_warning_free(default_model, grey_model, tmp_path, impl):
    for model in (default_model, grey_model):
        folder = tmp_path / model.aim.kind
        emit(model, folder, "fm", activation_impl=impl)
        for fname, text in render_adapt(model, "fm", impl).items():
            (folder / fname).write_text(text)
        sources = sorted(str(p) for p in folder.glob("*.c"))
        result = subprocess.run([CC, *CFLAGS, *STRICT_WARNINGS, "-c", *sources],
                                cwd=folder, capture_output=True, text=True)
        assert result.returncode == 0 and result.stderr == "", result.stderr
        # one float-semantics block, and every source of the folder reaches it
        assert list(flag_matrix.fp_blocks(folder)) == [flag_matrix.FLOAT_HEADER]
        assert all(flag_matrix.includes_float_semantics(folder).values())


def test_emit_without_adapt_is_unchanged_and_adapt_only_adds(default_model, tmp_path):
    plain, adapt = tmp_path / "plain", tmp_path / "adapt"
    assert main(["emit", str(_saved(default_model, tmp_path)), "-o", str(plain)]) == 0
    assert main(["emit", str(_saved(default_model, tmp_path)), "-o", str(adapt), "--adapt"]) == 0
    plain_files = {p.name: p.read_bytes() for p in plain.glob("*.[ch]")}
    assert set(plain_files) == {"fm.h", "fm.c", *RUNTIME_FILES}
    added = {p.name for p in adapt.glob("*.[ch]")} - set(plain_files)
    assert added == {"fm_adapt.h", "fm_adapt.c", "fric_adapt.h", "fric_adapt.c", "fric_bytes.h",
                     "fric_bytes.c", *CONTROLLER_FILES} - set(plain_files)
    for fname, data in plain_files.items():      # fm.h differs in the options it records
        if fname != "fm.h":
            assert (adapt / fname).read_bytes() == data, fname
    changed = set((adapt / "fm.h").read_text().splitlines()) ^ set(plain_files["fm.h"].decode().splitlines())
    assert changed == {'#define FM_EMIT_OPTIONS "dtype=float activation_impl=libm with_controller=0 adapt=0"',
                       '#define FM_EMIT_OPTIONS "dtype=float activation_impl=libm with_controller=1 adapt=1"'}
    # the plain folder's C is what render gives without the option; the build files list the rest
    assert {k: v.encode() for k, v in render(default_model, "fm").items()} == plain_files
    assert "    fm_adapt.c\n" in (adapt / "CMakeLists.txt").read_text()


def test_a_re_emit_without_adapt_leaves_no_adaptation_of_the_old_model(default_model, grey_model,
                                                                       tmp_path, capsys):
    # --adapt of one model, then another model under the same name without it: the stale
    # fm_adapt.{c,h} are removed and the build files no longer list them
    folder = tmp_path / "c"
    assert main(["emit", str(_saved(default_model, tmp_path)), "-o", str(folder), "--adapt"]) == 0
    assert (folder / "fm_adapt.c").is_file()
    grey = tmp_path / "grey.json"
    grey_model.save(grey)
    capsys.readouterr()
    assert main(["emit", str(grey), "-o", str(folder), "--name", "fm"]) == 0
    assert "removed fm_adapt.c, fm_adapt.h" in capsys.readouterr().err
    assert not (folder / "fm_adapt.c").exists() and not (folder / "fm_adapt.h").exists()
    for build in ("CMakeLists.txt", "library.json"):
        assert "fm_adapt" not in (folder / build).read_text(), build
    # ... and so are the adaptation's runtime files, which no model left uses: the folder holds
    # what an emit of the grey model into an empty folder writes (a firmware engineer's trial)
    fresh = tmp_path / "fresh"
    assert main(["emit", str(grey), "-o", str(fresh), "--name", "fm"]) == 0
    assert sorted(p.name for p in folder.rglob("*")) == sorted(p.name for p in fresh.rglob("*"))
    assert not (folder / "fric_adapt.c").exists()
    # a file of the same name that fricgen did not write is left alone
    (folder / "fm_adapt.c").write_text("/* mine */\n")
    assert main(["emit", str(grey), "-o", str(folder), "--name", "fm"]) == 0
    assert (folder / "fm_adapt.c").read_text() == "/* mine */\n"


def test_a_runtime_file_another_model_of_the_folder_uses_stays(default_model, grey_model, tmp_path):
    """Two models in one folder, one adapted: emitting the other again removes nothing the
    adapted one uses, and the folder compiles."""
    folder = tmp_path / "c"
    grey = tmp_path / "grey.json"
    grey_model.save(grey)
    assert main(["emit", str(_saved(default_model, tmp_path)), "-o", str(folder), "--adapt",
                 "--name", "fa"]) == 0
    before = sorted(p.name for p in folder.iterdir())
    assert main(["emit", str(grey), "-o", str(folder), "--name", "fb"]) == 0
    after = sorted(p.name for p in folder.iterdir())
    assert set(before) <= set(after) and {"fric_adapt.c", "fric_ctrl.c", "fb.c"} <= set(after)
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc:
        sources = [str(p) for p in folder.glob("*.c")]
        subprocess.run([cc, "-c", "-std=c99", "-O1", "-I", str(folder), *sources],
                       cwd=tmp_path, check=True)


def _saved(model, tmp_path):
    path = tmp_path / "model.json"
    if not path.exists():
        model.save(path)
    return path


def test_adapt_is_refused_for_fixed_point_models(default_model, tmp_path, capsys):
    path = _saved(default_model, tmp_path)
    assert main(["emit", str(path), "-o", str(tmp_path / "q"), "--adapt", "--dtype", "q15"]) == 2
    assert "--adapt is float" in capsys.readouterr().err
    assert not (tmp_path / "q").exists() or not any((tmp_path / "q").iterdir())


def test_an_asymmetric_model_adapts_in_c_as_its_twin(default_model, grey_model):
    """An ELM curve for v > 0, a grey-box one for v < 0 and the axis's offset: the C regressor
    fills each direction's parameters (the other's 0) and the offset's, and the adapted loop is
    bit-equal to the float32 twin."""
    from fricgen.direction import Direction
    negative = Direction(grey_model.aim, grey_model.scaling, 1.2 * grey_model.viscous,
                         0.8 * grey_model.v_sat)
    model = with_axis(FrictionModel.from_directions(default_model.positive, negative, name="asym"), -0.8)
    twin, c, (py, cc) = _parity(model, "fast", "lyapunov", 1.5)
    assert py.finite and cc.finite
    np.testing.assert_array_equal(py.x, cc.x)
    np.testing.assert_array_equal(py.i, cc.i)
    np.testing.assert_array_equal(np.asarray(twin.adapter.theta_), np.float32(c.theta_))
    n_pos = default_model.aim.n_hidden + 1
    moved = np.asarray(twin.adapter.theta_) != twin.adapter._theta0
    assert moved[:n_pos].any() and moved[n_pos:].any()      # both directions adapted
    # read back: each direction's curve with its own adapted parameters, times the k_hat
    from fricgen.control.readback import dump_text, model_from_dump
    k_hat = float(c.adaptive_parameters[1])
    back = model_from_dump(model, dump_text(model.model_hash, np.float32(c.theta_), k_hat))
    v = np.array([-0.2, -0.01, 0.01, 0.2])
    np.testing.assert_allclose(back.force(v), k_hat * twin.adapter.adapted_model.force(v), rtol=1e-6)
    assert back.negative is not None
    assert back.axis_offset == pytest.approx(k_hat * float(c.theta_[-1]), rel=1e-6)


def test_header_capacity_is_the_python_one():
    text = (resource_dir("c_runtime") / "fric_adapt.h").read_text()
    assert int(re.search(r"#define FRIC_ADAPT_MAX_PARAMS (\d+)", text).group(1)) == MAX_PARAMS


def _parity(model, impl, rule, duration):
    module = build_adapted(model, activation_impl=impl)
    twin = adapted(model, rule, dtype="float32", activation_impl=impl)
    c = CAdaptedController(module, adapted(model, rule, dtype="float32", activation_impl=impl))
    runs = simulate(default_axis(), [twin, c], duration=duration)
    return twin, c, runs


@pytest.mark.parametrize("impl, rule, kind", [("fast", "rls", "elm"), ("fast", "lyapunov", "grey"),
                                              ("libm", "lyapunov", "grey")])
def test_c_adapted_loop_is_bit_equal_to_the_twin(default_model, grey_model, impl, rule, kind):
    """Bit for bit with the fast activation; with libm's expf (within 1 ULP of the twin's
    correctly rounded one) within 1e-4 of the current, as the offset test below argues."""
    model = default_model if kind == "elm" else grey_model
    twin, c, (py, cc) = _parity(model, impl, rule, 1.5)
    assert py.finite and cc.finite
    check = np.testing.assert_array_equal if impl == EXACT else (
        lambda a, b: np.testing.assert_allclose(a, b, rtol=1e-3, atol=1e-5))
    check(py.x, cc.x)
    check(py.i, cc.i)
    check(np.asarray(twin.adapter.theta_), np.float32(c.theta_))
    assert not np.array_equal(np.asarray(twin.adapter.theta_), twin.adapter._theta0)  # it adapted


@pytest.mark.parametrize("rule", ["rls", "lyapunov"])
def test_the_offset_adapts_toward_the_plants_load_in_c_as_its_twin(offset_model, rule):
    """The model's axis holds an offset of 1.5 N, the plant's load is 4 N: the C and its twin
    step for step, the offset (theta's last, which does not leak) rises toward the load, and
    the emitted header says the leakage spares it. Step for step within the twin's own bound:
    its activations are correctly rounded, libm's expf is within 1 ULP of that (82 of 100000
    regressor calls differ by 1 ULP in one element on glibc), and 3000 samples of the closed
    loop carry such a step to at most 1e-4 of the current."""
    module = build_adapted(offset_model)
    twin = adapted(offset_model, rule, dtype="float32")
    c = CAdaptedController(module, adapted(offset_model, rule, dtype="float32"))
    py, cc = simulate(default_axis(load=4.0), [twin, c], duration=3.0)
    assert py.finite and cc.finite
    np.testing.assert_allclose(py.i, cc.i, rtol=1e-3, atol=1e-5)
    np.testing.assert_allclose(np.asarray(twin.adapter.theta_), np.float32(c.theta_), rtol=1e-3,
                               atol=1e-5)
    assert 1.7 < float(c.theta_[-1]) < 4.0 * 20.0 / 18.0 * 1.05     # in phi_N / phi units
    n = len(twin.adapter.theta_)
    header = render_adapt(offset_model, "om")["om_adapt.h"]
    assert f"#define OM_ADAPT_N_LEAK {n - 1}" in header and f"#define OM_ADAPT_N_PARAMS {n}" in header


@pytest.mark.parametrize("rule", ["rls", "lyapunov"])
def test_the_estimates_hold_at_rest_and_while_the_axis_catches_up(default_model, rule):
    """m_o_hat and k_hat (and Lyapunov's theta) do not adapt on the velocity error of a stick,
    |v| < v_dead, nor for SETTLE / k1 after it (37 samples at k1 = 80, Ts = 1 ms): the C and
    its twin, step for step."""
    module = build_adapted(default_model, activation_impl=EXACT)
    twin = adapted(default_model, rule, dtype="float32", activation_impl=EXACT).reset()
    c = CAdaptedController(module, adapted(default_model, rule, dtype="float32",
                                           activation_impl=EXACT)).reset()
    a0, theta0 = twin.adaptive_parameters, np.asarray(twin.adapter.theta_).copy()
    held = int(SETTLE / twin.controller.k1 / twin.controller.ts)
    behind = (0.0, 1e-3, 0.05, 1.0)                 # x, xd, xd', xd'': 1 mm behind, e2 0.08 m/s
    for v in [0.0] * 5 + [0.05] * held:             # stuck, then moving again, still behind
        x, xd, xd_dot, xd_ddot = behind
        assert twin.step(x, v, xd, xd_dot, xd_ddot) == c.step(x, v, xd, xd_dot, xd_ddot)
        assert twin.adaptive_parameters == c.adaptive_parameters == a0
        assert twin.controller.flags_ == 0
        assert c.flags_ == twin.flags_ == twin.adapter.flags_     # the update's, in one word
    if rule == "lyapunov":
        np.testing.assert_array_equal(twin.adapter.theta_, theta0)
        np.testing.assert_array_equal(np.float32(c.theta_), theta0)
        assert twin.adapter.flags_ == FLAGS.value("held")
    twin.step(0.0, 0.05, *behind[1:])
    c.step(0.0, 0.05, *behind[1:])
    assert twin.adaptive_parameters == c.adaptive_parameters != a0    # then it adapts
    assert twin.adaptive_parameters[1] > a0[1]


@pytest.mark.parametrize("rule", ["rls", "lyapunov"])
def test_without_the_hold_the_estimates_adapt_through_the_stick(default_model, rule):
    """hold_at_rest=False (fric_adapt_params_t.hold_at_rest = 0): the same stick and catch-up
    move m_o_hat and k_hat from the first step on, and Lyapunov's theta once the axis moves,
    in the C as in its twin, step for step."""
    module = build_adapted(default_model, activation_impl=EXACT)
    twin = adapted(default_model, rule, dtype="float32", activation_impl=EXACT,
                   hold_at_rest=False).reset()
    c = CAdaptedController(module, adapted(default_model, rule, dtype="float32",
                                           activation_impl=EXACT, hold_at_rest=False)).reset()
    a0, theta0 = twin.adaptive_parameters, np.asarray(twin.adapter.theta_).copy()
    behind = (0.0, 1e-3, 0.05, 1.0)
    for v in [0.0] * 5 + [0.05] * 5:
        assert twin.step(v=v, x=behind[0], xd=behind[1], xd_dot=behind[2], xd_ddot=behind[3]) \
            == c.step(behind[0], v, *behind[1:])
        assert twin.adaptive_parameters == c.adaptive_parameters != a0
        np.testing.assert_array_equal(np.asarray(twin.adapter.theta_), np.float32(c.theta_))
    if rule == "lyapunov":
        assert not np.array_equal(np.asarray(twin.adapter.theta_), theta0)
    with pytest.raises(ValueError, match="hold_at_rest must be True or False"):
        adapted(default_model, rule, hold_at_rest=0).adapter.validate()


@pytest.mark.slow
@pytest.mark.parametrize("rule", ["rls", "lyapunov"])
def test_c_adapted_loop_is_bit_equal_over_60_s(default_model, rule):
    twin, c, (py, cc) = _parity(default_model, "fast", rule, 60.0)
    np.testing.assert_array_equal(py.x, cc.x)
    np.testing.assert_array_equal(py.i, cc.i)
    np.testing.assert_array_equal(np.asarray(twin.adapter.theta_), np.float32(c.theta_))


def test_c_init_rejects_bad_parameters(default_model):
    module = build_adapted(default_model)
    ffi, lib = module.ffi, module.lib
    p = ffi.new("fric_adapt_params_t *")
    assert lib.fm_adapt_default_params(p, lib.FRIC_ADAPT_RULE_LYAPUNOV, 1e-3) == 0
    a = ffi.new("fric_adapt_t *")
    assert lib.fric_adapt_init(a, p) == 0
    for field, bad in (("forgetting", 0.0), ("forgetting", 1.5), ("p0", -1.0), ("leak", 1.0), ("n", 0),
                       ("n", MAX_PARAMS + 1), ("v_dead", float("nan")), ("rule", 2),
                       ("e_max", 0.0), ("band", -1.0), ("v_max", float("inf")), ("n_leak", p.n + 1),
                       ("hold_at_rest", 2)):
        q = ffi.new("fric_adapt_params_t *", p[0])
        setattr(q, field, bad)
        assert lib.fric_adapt_init(a, q) == -2, field
    q = ffi.new("fric_adapt_params_t *", p[0])
    q.lo[0] = q.theta0[0] + 1.0
    assert lib.fric_adapt_init(a, q) == -2


def _c_adapter(module, twin):
    """A fric_adapt_t initialised with the parameters of ``twin`` (a float32 FrictionAdapter)."""
    a = module.ffi.new("fric_adapt_t *")
    assert module.lib.fric_adapt_init(a, c_params(module, twin)) == 0
    return a


def test_a_restored_state_gives_the_controller_its_k_hat_back(default_model):
    """The saved state holds the controller's k_hat and m_o_hat: after a restore the next
    controller step starts from them (not k_hat0, m_o_hat0), so the current does not jump at
    boot; a state saved before any controller step, or of format 3, resumes nothing."""
    import struct
    import zlib
    from fricgen.control.backstepping import AdaptiveBackstepping
    from fricgen.control.c_controller import CController
    module = build_adapted(default_model)
    ffi, lib = module.ffi, module.lib
    reg = ffi.addressof(lib, "fm_regressor")
    twin = FrictionAdapter(default_model, "lyapunov", dtype="float32")
    params = CController(module, AdaptiveBackstepping(law="c"), "fm_force").params()

    def fresh():
        a, c = _c_adapter(module, twin), ffi.new("fric_ctrl_t *")
        assert lib.fric_ctrl_init(c, params) == 0
        return a, c

    a, c = fresh()
    current = ffi.new("float *")
    for tk in np.arange(2000) * 1e-3:                       # the built-in reversing move
        xd, vd = 0.01 * np.sin(4 * tk), 0.04 * np.cos(4 * tk)
        lib.fric_adapt_ctrl_step(a, c, reg, xd * 0.98, vd * 0.97, xd, vd, -0.16 * np.sin(4 * tk), current)
    saved_k, saved_m = float(c.k_hat), float(c.m_o_hat)
    assert abs(saved_k - 1.0) > 1e-3 and abs(saved_m - 0.1) > 1e-4   # both have moved
    n = a.p.n
    size = 40 + 4 * n + 4 * n * n
    buf = ffi.new("unsigned char[]", size)
    hash_ = default_model.model_hash.encode()
    b, d = fresh()
    assert lib.fric_adapt_save(b, hash_, buf, size) == size              # before any step
    assert _state(bytes(ffi.buffer(buf, size)))[5] == 0                  # nothing recorded
    assert lib.fric_adapt_save(a, hash_, buf, size) == size
    blob = bytes(ffi.buffer(buf, size))
    assert _state(blob)[5:] == (1, np.float32(saved_k), np.float32(saved_m))
    assert lib.fric_adapt_restore(b, hash_, blob, size) == 0
    assert float(d.k_hat) == 1.0                             # k_hat0 until the next step
    lib.fric_adapt_ctrl_step(b, d, reg, 0.0, 0.0, 0.0, 0.0, 0.0, current)
    assert abs(float(d.k_hat) - saved_k) < 1e-4              # resumed (one step's change aside)
    assert abs(float(d.m_o_hat) - saved_m) < 1e-4
    # format 3: the same without them
    old = bytearray(blob[:size - 16] + blob[size - 4:])
    old[4:6] = struct.pack("<H", 3)
    old[-4:] = struct.pack("<I", zlib.crc32(bytes(old[:-4])))
    e, f = fresh()
    assert lib.fric_adapt_restore(e, default_model.model_hash.encode(), bytes(old), len(old)) == 0
    lib.fric_adapt_ctrl_step(e, f, reg, 0.0, 0.0, 0.0, 0.0, 0.0, current)
    assert abs(float(f.k_hat) - 1.0) < 1e-4
    assert bytes(ffi.buffer(e.theta, 4 * n)) == bytes(ffi.buffer(b.theta, 4 * n))


def test_the_adapted_sample_step_is_the_positional_step_bit_for_bit(default_model):
    module = build_adapted(default_model)
    ffi, lib = module.ffi, module.lib
    reg = ffi.addressof(lib, "fm_regressor")
    twin = FrictionAdapter(default_model, "rls", dtype="float32")
    from fricgen.control.backstepping import AdaptiveBackstepping
    from fricgen.control.c_controller import CController
    ctrl = CController(module, AdaptiveBackstepping(law="c"), "fm_force")
    states = []
    for _ in range(2):
        c = ffi.new("fric_ctrl_t *")
        assert lib.fric_ctrl_init(c, ctrl.params()) == 0
        states.append((_c_adapter(module, twin), c))
    (a1, c1), (a2, c2) = states
    current, sample = ffi.new("float[2]"), ffi.new("fric_ctrl_sample_t *")
    t = np.arange(400) * 1e-3
    for k, tk in enumerate(t):
        row = [0.009 * np.sin(3 * tk), 0.027 * np.cos(3 * tk), 0.01 * np.sin(3 * tk), 0.03 * np.cos(3 * tk),
               -0.09 * np.sin(3 * tk)]
        if k == 200:
            row[1] = np.inf                                       # one input fault
        sample.x, sample.v, sample.xd, sample.xd_dot, sample.xd_ddot = (float(r) for r in row)
        flags = lib.fric_adapt_ctrl_step(a1, c1, reg, *(float(r) for r in row), current)
        assert lib.fric_adapt_ctrl_step_sample(a2, c2, reg, sample, current + 1) == flags
        assert bytes(ffi.buffer(current, 4)) == bytes(ffi.buffer(current + 1, 4))
    assert bytes(ffi.buffer(a1)) == bytes(ffi.buffer(a2)) and bytes(ffi.buffer(c1)) == bytes(ffi.buffer(c2))
    assert list(a1.theta)[:a1.p.n] != list(twin.reset().theta_)   # it adapted
    assert lib.fric_adapt_ctrl_step_sample(a2, c2, reg, ffi.NULL, current) == 1    # FAULT_NULL


@pytest.mark.parametrize("rule", ["rls", "lyapunov"])
def test_c_clamps_an_outlier_and_keeps_the_force_in_its_band_as_the_twin(default_model, rule):
    """A finite outlier (1e20) moves theta one clamped step, bit-equal to the twin; with theta at
    a corner of its box the force stays within the band, bit-equal too."""
    module = build_adapted(default_model, activation_impl=EXACT)
    lib, ffi = module.lib, module.ffi
    reg = ffi.addressof(lib, "fm_regressor")
    twin = FrictionAdapter(default_model, rule, dtype="float32", band=3.0,
                           activation_impl=EXACT).reset()
    a = _c_adapter(module, twin)
    update = lib.fric_adapt_lyapunov if rule == "lyapunov" else lib.fric_adapt_rls
    assert update(a, reg, 1e20, 1.0, 0) == FLAGS.value("out of range") == getattr(twin, rule)(1e20, 1.0)
    flags = update(a, reg, 0.03, 1e20, 0)
    assert flags == getattr(twin, rule)(0.03, 1e20) and flags & FLAGS.value("clamped")
    np.testing.assert_array_equal(np.float32(list(a.theta)[:a.p.n]), twin.theta_)
    corner = np.where(np.arange(twin._hi.size) % 2, twin._hi, twin._lo)
    a.theta[0:corner.size] = corner.tolist()
    twin.theta_ = corner.copy()
    v = np.float32(np.linspace(-0.2, 0.2, 81))
    c_force = np.float32([lib.fric_adapt_force(a, reg, float(u)) for u in v])
    np.testing.assert_array_equal(c_force, np.float32([twin.force(u) for u in v]))
    assert np.max(np.abs(c_force - default_model.force(v))) <= 3.0 + 1e-3


def test_rls_is_held_when_this_step_saturates(default_model):
    """A glitch of v (+0.5 m/s) that saturates the controller moves no parameter, in C and in
    the twin (the update is gated on this step, not the last)."""
    module = build_adapted(default_model, activation_impl=EXACT)
    twin = adapted(default_model, "rls", dtype="float32", activation_impl=EXACT)
    c = CAdaptedController(module, adapted(default_model, "rls", dtype="float32",
                                           activation_impl=EXACT))
    for ctrl in (twin.reset(), c.reset()):
        for k in range(200):
            t = k * 1e-3
            ctrl.step(0.01 * t, 0.01, 0.01 * t, 0.01, 0.0)
        before = np.float32(ctrl.theta_ if ctrl is c else ctrl.adapter.theta_).copy()
        ctrl.step(0.002, 0.5, 0.002, 0.01, 0.0)
        assert ctrl.flags_ & CTRL_FLAGS.value("saturated") and ctrl.flags_ & FLAGS.value("held")
        after = np.float32(ctrl.theta_ if ctrl is c else ctrl.adapter.theta_)
        np.testing.assert_array_equal(after, before)


def test_the_sample_after_a_glitch_is_held_not_an_input_fault(default_model):
    """RLS observes the friction over the last sample: after a NaN (or a huge finite) v, the
    next, clean, sample's update is held, never flagged an input fault (the flag of a refused
    input), in C and in the twin (a firmware engineer's trial)."""
    module = build_adapted(default_model, activation_impl=EXACT)
    twin = adapted(default_model, "rls", dtype="float32", activation_impl=EXACT)
    c = CAdaptedController(module, adapted(default_model, "rls", dtype="float32",
                                           activation_impl=EXACT))
    for glitch in (float("nan"), 3e38):
        for ctrl in (twin.reset(), c.reset()):
            for k in range(50):
                ctrl.step(0.01 * k * 1e-3, 0.01, 0.01 * k * 1e-3, 0.01, 0.0)
            ctrl.step(0.0005, glitch, 0.0005, 0.01, 0.0)
            ctrl.step(0.0005, 0.01, 0.0005, 0.01, 0.0)
            assert ctrl.flags_ & FLAGS.value("input fault") == 0
            assert ctrl.flags_ & FLAGS.value("held")
        assert c.flags_ == twin.flags_ and c.step(0.0, 0.01, 0.0, 0.01, 0.0) == twin.step(0.0, 0.01, 0.0, 0.01, 0.0)


def test_default_params_scale_the_per_sample_gains_with_the_sample_time(default_model):
    """NAME_adapt_default_params(p, rule, ts): at the reference 1 ms each rule's Python defaults
    bit for bit;
    at 0.1 ms a tenth of the gain and leakage per sample and a tenth of 1 - lambda, so that a
    10 kHz loop adapts per second as a 1 kHz one does; a ts not > 0 is refused."""
    module = build_adapted(default_model)
    ffi, lib = module.ffi, module.lib
    lyapunov, rls = lib.FRIC_ADAPT_RULE_LYAPUNOV, lib.FRIC_ADAPT_RULE_RLS
    for rule, enum in (("lyapunov", lyapunov), ("rls", rls)):
        ref = ffi.new("fric_adapt_params_t *")
        assert lib.fm_adapt_default_params(ref, enum, 1e-3) == 0 and ref.rule == enum
        expected = c_params(module, FrictionAdapter(default_model, rule))
        for field in ("gain", "leak", "forgetting", "e_max", "band", "v_max", "p0", "trace_max"):
            assert getattr(ref, field) == getattr(expected, field), (rule, field)
    ref, fast = ffi.new("fric_adapt_params_t *"), ffi.new("fric_adapt_params_t *")
    assert lib.fm_adapt_default_params(ref, lyapunov, 1e-3) == 0
    assert lib.fm_adapt_default_params(fast, lyapunov, 1e-4) == 0
    twin = FrictionAdapter(default_model, ts=1e-4)
    assert fast.gain == pytest.approx(twin.gain(), rel=1e-6)
    assert fast.leak == pytest.approx(twin.leakage(), rel=1e-6)
    # lambda is a float near 1: 1 - lambda = 5e-6 is held to its ULP there, 6e-8 (1.2 %)
    assert 1 - fast.forgetting == pytest.approx(1 - twin.forgetting_factor(), rel=0.015)
    assert fast.e_max == ref.e_max
    for bad in (0.0, -1e-3, float("nan"), float("inf")):
        assert lib.fm_adapt_default_params(fast, lyapunov, bad) == -2
    assert lib.fm_adapt_default_params(fast, 7, 1e-3) == -2
    # a ts so long that the leakage per sample reaches 1 (or lambda 0), which init would refuse
    before = bytes(ffi.buffer(fast))
    for enum in (lyapunov, rls):
        assert lib.fm_adapt_default_params(fast, enum, 1e3) == -2
    assert bytes(ffi.buffer(fast)) == before
    state = ffi.new("fric_adapt_t *")
    for enum in (lyapunov, rls):                # every ts it accepts, init accepts
        for ts in (1e-5, 1e-2, 1.0):
            assert lib.fm_adapt_default_params(fast, enum, ts) == 0
            assert lib.fric_adapt_init(state, fast) == 0, (enum, ts)
    assert lib.fm_adapt_default_params(ffi.NULL, lyapunov, 1e-3) == -1


def _state(blob):
    """(format, n, hash, theta, P, recorded, k_hat, m_o_hat) of a saved state, read from the
    layout of fric_adapt.h with the CRC-32 checked by zlib."""
    import struct
    import zlib
    blob = bytes(blob)
    assert blob[:4] == b"FRAS" and zlib.crc32(blob[:-4]) == struct.unpack("<I", blob[-4:])[0]
    version, n = struct.unpack("<HH", blob[4:8])
    values = np.frombuffer(blob[24:-16], dtype="<f4")
    recorded, = struct.unpack("<I", blob[-16:-12])
    k_hat, m_o_hat = np.frombuffer(blob[-12:-4], dtype="<f4")
    return (version, n, blob[8:24].rstrip(b"\0").decode(), values[:n],
            values[n:].reshape(n, n), recorded, k_hat, m_o_hat)


@pytest.mark.parametrize("rule", ["rls", "lyapunov"])
def test_a_saved_state_restores_bit_for_bit_and_a_foreign_one_is_refused(default_model, rule):
    module = build_adapted(default_model)
    ffi, lib = module.ffi, module.lib
    reg = ffi.addressof(lib, "fm_regressor")
    twin = FrictionAdapter(default_model, rule, dtype="float32")
    a, b = _c_adapter(module, twin), _c_adapter(module, twin)
    update = lib.fric_adapt_lyapunov if rule == "lyapunov" else lib.fric_adapt_rls
    for v in np.linspace(-0.1, 0.1, 40):
        update(a, reg, float(v), 1e-3 if rule == "lyapunov" else 1.1 * float(default_model.force(v)), 0)
    n, model_hash = a.p.n, default_model.model_hash.encode()
    size = 40 + 4 * n + 4 * n * n
    buf = ffi.new("unsigned char[]", size + 8)
    assert lib.fric_adapt_save(a, model_hash, buf, size - 1) == 0           # too small
    assert lib.fric_adapt_save(a, model_hash, buf, size + 8) == size
    blob = bytes(ffi.buffer(buf, size))
    version, count, saved_hash, theta, P, recorded, k_hat, _ = _state(blob)
    assert (version, count, saved_hash, recorded) == (4, n, default_model.model_hash, 0)
    np.testing.assert_array_equal(theta, np.float32(list(a.theta)[:n]))
    np.testing.assert_array_equal(P.ravel(), np.float32(list(a.P)[:n * n]))
    assert not np.array_equal(theta, np.float32(list(b.theta)[:n]))         # it adapted
    assert lib.fric_adapt_restore(b, model_hash, blob, size) == 0
    assert bytes(ffi.buffer(b.theta, 4 * n)) == bytes(ffi.buffer(a.theta, 4 * n))
    assert bytes(ffi.buffer(b.P, 4 * n * n)) == bytes(ffi.buffer(a.P, 4 * n * n))
    c = _c_adapter(module, twin)
    before = bytes(ffi.buffer(c.theta, 4 * n))
    flipped = bytearray(blob)
    flipped[30] ^= 0x01                                                       # one bit of theta
    out_of_box = bytearray(blob)
    out_of_box[24:28] = np.float32(1e30).tobytes()
    import struct
    import zlib
    out_of_box[-4:] = struct.pack("<I", zlib.crc32(bytes(out_of_box[:-4])))
    negative = bytearray(blob)              # a covariance with a diagonal entry of -1e30
    negative[24 + 4 * n:28 + 4 * n] = np.float32(-1e30).tobytes()
    negative[-4:] = struct.pack("<I", zlib.crc32(bytes(negative[:-4])))
    for bad, hash_, status in ((blob, b"0123456789abcdef", -4),                # another model
                               (bytes(negative), model_hash, -6),
                               (blob[:4] + b"\x01\x00" + blob[6:], model_hash, -4),   # version 1
                               (bytes(flipped), model_hash, -5),
                               (bytes(out_of_box), model_hash, -6),
                               (blob[:-1], model_hash, -3)):
        assert lib.fric_adapt_restore(c, hash_, bad, len(bad)) == status
        assert bytes(ffi.buffer(c.theta, 4 * n)) == before                   # untouched


@pytest.mark.parametrize("activation", ["rbf", "sigmoid"])
def test_the_libm_regressor_sets_no_errno_and_equals_its_twin(bench, activation):
    """The generated regressor computes each unit with the model's own clamped exponential: no
    call sets errno (an unclamped expf underflows for most of an rbf ELM's speeds), and phi is
    the float32 twin's within libm's last bits (the twin takes expf as correctly rounded, glibc's
    is within 1 ULP)."""
    from fricgen.control.regressor import Regressor
    from fricgen.fit.elm import ELMRegressor, EnlargedScheme
    model = FrictionModel.fit(bench.dataset, ELMRegressor(
        n_hidden=8, activation=activation, scheme=EnlargedScheme(w_max=30.0), random_state=0), name="fm")
    z = np.outer(np.linspace(0, 1, 101), model.aim.input_weights) + model.aim.biases
    assert np.any(z * z > 104)                  # where an unclamped exp(-z^2) underflows
    module = build_adapted(model)
    ffi, lib = module.ffi, module.lib
    twin = Regressor(model, "float32")
    phi = ffi.new("float[]", MAX_PARAMS)
    for v in np.float32(np.linspace(-2 * model.v_sat, 2 * model.v_sat, 2001)):
        ffi.errno = 0
        lib.fm_regressor(float(v), phi)
        assert ffi.errno == 0, float(v)
        np.testing.assert_allclose(np.float32(list(phi)[:twin.n]), twin(v)[1], rtol=5e-7, atol=1e-30)
