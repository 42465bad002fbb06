"""Reading back what the firmware adapted: fric_adapt_export's text (C) against its writer in
fricgen.control.readback, the adapted model.json it becomes, and `fricgen readback`."""
import shutil
import subprocess
import sys

import numpy as np
import pytest

from fricgen.control.adaptation import adapted
from fricgen.control.c_adapted import CAdaptedController, build_adapted
from fricgen.control.loop import default_axis, simulate
from fricgen.control.readback import MAGIC, MAGIC_1, dump_text, model_from_dump, parse_dump
from fricgen.control.regressor import trained_parameters
from fricgen.errors import DataError, ModelError
from fricgen.model import FrictionModel

pytestmark = pytest.mark.skipif((shutil.which("cc") or shutil.which("gcc")) is None, reason="no C compiler")


@pytest.fixture(scope="module")
def adapted_loop(default_model):
    """A 1.5 s closed loop of the C adaptation (fast, RLS), with its twin beside it."""
    module = build_adapted(default_model, activation_impl="fast")
    twin = adapted(default_model, "rls", dtype="float32", activation_impl="fast")
    c = CAdaptedController(module, adapted(default_model, "rls", dtype="float32", activation_impl="fast"))
    simulate(default_axis(), [twin, c], duration=1.5)
    return module, c, twin


def _export(module, c, model_hash, size=512):
    """fric_adapt_export of the C adaptation state: (its return value, the text)."""
    ffi, lib = module.ffi, module.lib
    buf = ffi.new("char[]", size)
    n = lib.fric_adapt_export(c._a, ffi.new("char[]", model_hash.encode()), buf, size)
    return n, ffi.string(buf).decode()


def test_the_c_dump_is_its_python_writer_byte_for_byte(adapted_loop, default_model):
    module, c, _ = adapted_loop
    n, text = _export(module, c, default_model.model_hash)
    theta, k_hat = np.float32(c.theta_), np.float32(c.adaptive_parameters[1])
    assert text == dump_text(default_model.model_hash, theta, k_hat) and n == len(text)
    assert not np.array_equal(theta, np.float32(trained_parameters(default_model)))   # it adapted
    assert k_hat != 1.0                                          # the controller's k_hat moved too
    model_hash, read, scale = parse_dump(text)
    assert model_hash == default_model.model_hash
    assert read.tobytes() == theta.tobytes() and np.float32(scale) == k_hat       # every bit


def test_the_dump_reads_back_into_the_model_the_twin_adapted(adapted_loop, default_model):
    """The read-back model's force is the friction the twin's loop applies: k_hat times its
    adapted model's (same theta, same k_hat)."""
    module, c, twin = adapted_loop
    back = model_from_dump(default_model, _export(module, c, default_model.model_hash)[1])
    v = np.linspace(-0.1, 0.1, 41)
    k_hat = twin.adaptive_parameters[1]
    assert k_hat == c.adaptive_parameters[1]
    np.testing.assert_allclose(back.force(v), k_hat * twin.adapter.adapted_model.force(v),
                               rtol=1e-12, atol=1e-12)
    assert back.model_hash != default_model.model_hash
    # and it survives model.json
    again = FrictionModel.from_dict(back.to_dict())
    np.testing.assert_array_equal(again.force(v), back.force(v))


def test_a_buffer_too_small_or_null_gives_zero_and_an_empty_string(adapted_loop, default_model):
    module, c, _ = adapted_loop
    n_full, text = _export(module, c, default_model.model_hash)
    assert n_full + 1 == 50 + len(default_model.model_hash) + 9 * len(c.theta_)   # the size the header states
    assert _export(module, c, default_model.model_hash, size=n_full + 1)[0] == n_full
    assert _export(module, c, default_model.model_hash, size=n_full) == (0, "")
    ffi, lib = module.ffi, module.lib
    buf = ffi.new("char[]", 64)
    assert lib.fric_adapt_export(ffi.NULL, ffi.new("char[]", b"abc"), buf, 64) == 0
    assert lib.fric_adapt_export(c._a, ffi.NULL, buf, 64) == 0


@pytest.mark.parametrize("text, words", [
    ("v,f\n0.1,2\n", "not an adaptation dump"),
    (f"{MAGIC}\nmodel abc\n", "expected the lines"),
    (f"{MAGIC}\nmodel abc\ntheta\nscale 3f800000\n", "holds no parameter"),
    (f"{MAGIC}\nmodel abc\ntheta 3f80000g\nscale 3f800000\n", "is not 8 hex digits"),
    (f"{MAGIC}\nmodel abc\ntheta 3f800000 7fc00000\nscale 3f800000\n", "theta[1] is nan"),
    (f"{MAGIC}\nmodel abc\ntheta 3f800000\n", "and 'scale <hex>'"),
    (f"{MAGIC}\nmodel abc\ntheta 3f800000\nscale 00000000\n", "no friction model"),
    (f"{MAGIC}\nmodel abc\ntheta 3f800000\nscale 3f800000 3f800000\n", "must be one number"),
])
def test_malformed_dumps_are_refused_by_name(text, words):
    with pytest.raises(DataError, match=words.replace("[", r"\[").replace("]", r"\]")):
        parse_dump(text)


def test_a_dump_of_another_model_or_size_is_refused(default_model):
    theta = trained_parameters(default_model)
    with pytest.raises(ModelError, match="not from this one"):
        model_from_dump(default_model, dump_text("0" * 16, theta))
    with pytest.raises(ModelError, match=f"holds {theta.size - 1} parameters"):
        model_from_dump(default_model, dump_text(default_model.model_hash, theta[:-1]))


def test_fricgen_readback_writes_a_model_that_eval_reads(default_model, tmp_path):
    model_path = default_model.save(tmp_path / "model.json")
    model = FrictionModel.load(model_path)
    theta = trained_parameters(model)
    theta[-1] *= 1.25                                          # B grew by a quarter
    (tmp_path / "dump.txt").write_text(dump_text(model.model_hash, theta))
    run = [sys.executable, "-m", "fricgen"]
    proc = subprocess.run(run + ["readback", str(tmp_path / "dump.txt"), "--model", str(model_path),
                                 "-o", str(tmp_path / "adapted.json")], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "changed: B " in proc.stderr and "beta_0" not in proc.stderr   # only B moved
    ev = subprocess.run(run + ["eval", str(tmp_path / "adapted.json")], input="0.1\n",
                        capture_output=True, text=True)
    ref = subprocess.run(run + ["eval", str(model_path)], input="0.1\n", capture_output=True, text=True)
    grown = float(ev.stdout) - float(ref.stdout)
    record = FrictionModel.load(tmp_path / "adapted.json").training
    assert record["adapted_from"] == model.model_hash and "metrics" not in record
    # the dump holds float32: every parameter rounded to 6e-8 of itself, B's quarter exactly
    assert grown == pytest.approx(0.25 * model.viscous * 0.1, rel=1e-5)


def test_a_version_1_dump_reads_as_k_hat_1_and_a_scale_scales_the_force(default_model):
    theta = trained_parameters(default_model)
    words = " ".join(f"{int(u):08x}" for u in np.float32(theta).view(np.uint32))
    old = model_from_dump(default_model, f"{MAGIC_1}\nmodel {default_model.model_hash}\ntheta {words}\n")
    v = np.linspace(-0.1, 0.1, 41)
    np.testing.assert_allclose(old.force(v), default_model.force(v), rtol=1e-6, atol=1e-9)
    half = model_from_dump(default_model, dump_text(default_model.model_hash, theta, 0.5))
    np.testing.assert_allclose(half.force(v), 0.5 * old.force(v), rtol=1e-12, atol=1e-12)
