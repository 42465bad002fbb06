"""The emitted folder as a product: the runtime's version checked by every model header, the
build recorded (NAME_EMIT_OPTIONS, NAME_CODE_HASH), only the kernels a model calls, and no libm
for --activation-impl fast (with the controller too)."""
import hashlib
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from fricgen import __version__, codegen
from fricgen._io import resource_dir
from fricgen.codegen.context import RUNTIME_VERSION, VERSION_HEADER, numeric_version, runtime_text
from fricgen.firmware.flag_matrix import table1_greybox

CC = shutil.which("cc") or shutil.which("gcc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler")
MAIN = '#include "fm.h"\nfloat axis(float v) { return fm_force(v); }\n'


def compile_c(folder, *sources, flags=("-std=c99", "-O2")):
    """``cc -c`` of ``sources`` in ``folder``: the completed process."""
    return subprocess.run([CC, *flags, "-c", *sources], cwd=folder, capture_output=True, text=True)


def set_runtime_version(folder, part: str, value: int) -> None:
    path = Path(folder) / VERSION_HEADER
    text, n = re.subn(rf"(#define FRIC_RUNTIME_VERSION_{part}) \d+", rf"\g<1> {value}", path.read_text())
    assert n == 1
    path.write_text(text)


def test_the_runtime_version_is_fricgens_in_the_copy_and_in_the_repository():
    assert RUNTIME_VERSION == numeric_version(__version__)
    assert numeric_version("1.12.3.dev4") == (1, 12, 3) and numeric_version("2.0") == (2, 0, 0)
    text = runtime_text(VERSION_HEADER)
    for part, number in zip(("MAJOR", "MINOR", "PATCH"), RUNTIME_VERSION):
        assert f"#define FRIC_RUNTIME_VERSION_{part} {number}\n" in text
    # c_runtime/ itself states it too (it builds as it is, e.g. for the tests that copy it)
    assert (resource_dir("c_runtime") / VERSION_HEADER).read_text() == text


@needs_cc
@pytest.mark.parametrize("part, builds", [("MINOR", False), ("MAJOR", False), ("PATCH", True)])
def test_a_model_against_a_runtime_of_another_version_is_a_compile_error(model10, tmp_path,
                                                                       part, builds):
    """NAME.h #errors when fric_version.h beside it has another major or minor; a patch
    release of the runtime is accepted. The unedited folder builds."""
    codegen.emit(model10, tmp_path, "fm", with_controller=True)
    (tmp_path / "main.c").write_text(MAIN)
    proc = compile_c(tmp_path, "main.c", "fm.c")
    assert proc.returncode == 0, proc.stderr
    index = ("MAJOR", "MINOR", "PATCH").index(part)
    set_runtime_version(tmp_path, part, RUNTIME_VERSION[index] + 1)
    for source in ("main.c", "fm.c"):
        proc = compile_c(tmp_path, source)
        assert (proc.returncode == 0) == builds, proc.stderr
        if not builds:
            assert "fm.h was emitted against the fricgen C runtime" in proc.stderr
            assert "re-emit every model of this folder with one fricgen" in proc.stderr


@needs_cc
def test_the_adapt_header_checks_the_runtime_version_too(default_model, tmp_path):
    from fricgen.control.c_adapted import render_adapt
    files = {**codegen.render(default_model, "fm"), **render_adapt(default_model, "fm")}
    for fname, text in files.items():
        (tmp_path / fname).write_text(text)
    assert compile_c(tmp_path, "fm_adapt.c").returncode == 0
    set_runtime_version(tmp_path, "MINOR", RUNTIME_VERSION[1] + 1)
    proc = compile_c(tmp_path, "fm_adapt.c")
    assert proc.returncode != 0 and "fm_adapt.h was emitted against" in proc.stderr


def _macro(header: str, name: str) -> str:
    return re.search(rf'^#define {name} "([^"]*)"$', header, re.M).group(1)


def test_builds_of_one_model_share_the_model_hash_and_differ_in_code_hash(model10):
    """NAME_MODEL_HASH is the model's; NAME_CODE_HASH the SHA-256 (16 hex digits) of NAME.c,
    the same on every rendering, another for each build (libm, fast, q15, q31);
    NAME_EMIT_OPTIONS says which build it is."""
    builds = {"libm": {}, "fast": {"activation_impl": "fast"}, "q15": {"dtype": "q15"},
              "q31": {"dtype": "q31"}}
    codes, options = {}, {}
    for label, kwargs in builds.items():
        files = codegen.render(model10, "fm", **kwargs)
        header = files["fm.h"]
        assert _macro(header, "FM_MODEL_HASH") == model10.model_hash
        codes[label] = _macro(header, "FM_CODE_HASH")
        assert codes[label] == hashlib.sha256(files["fm.c"].encode()).hexdigest()[:16]
        assert codegen.render(model10, "fm", **kwargs) == files          # reproducible
        options[label] = _macro(header, "FM_EMIT_OPTIONS")
        for major, name in zip(RUNTIME_VERSION, ("MAJOR", "MINOR", "PATCH")):
            assert f"#define FM_FRICGEN_VERSION_{name} {major}\n" in header
    assert len(set(codes.values())) == len(builds)
    assert options["libm"] == "dtype=float activation_impl=libm with_controller=0"
    assert options["fast"] == "dtype=float activation_impl=fast with_controller=0"
    assert options["q15"] == "dtype=q15 v_max=default"
    assert _macro(codegen.render(model10, "fm", dtype="q31", v_max=0.5)["fm.h"],
                  "FM_EMIT_OPTIONS") == "dtype=q31 v_max=0.5"
    # the options, not the code, of the controller: the same NAME.c
    with_ctrl = codegen.render(model10, "fm", with_controller=True)["fm.h"]
    assert _macro(with_ctrl, "FM_CODE_HASH") == codes["libm"]
    assert _macro(with_ctrl, "FM_EMIT_OPTIONS").endswith("with_controller=1")


@pytest.mark.parametrize("activation", ["sigmoid", "sine", "rbf", "multiquadric"])
def test_a_model_gets_only_the_libm_kernel_it_calls(model10, activation):
    from fricgen.model import FrictionModel
    from fricgen.networks import ElmNetwork
    net = model10.aim
    model = FrictionModel(ElmNetwork(activation, net.input_weights, net.biases, net.output_weights),
                          model10.scaling, model10.viscous, model10.v_sat, name="fm")
    sources = sorted(f for f in codegen.render(model, "fm") if f.endswith(".c"))
    assert sources == ["fm.c", f"fric_elm_{activation}.c"]


def libm_symbols():
    """The functions libm exports (glibc's libm.so.6), or None where it cannot be listed."""
    path = subprocess.run([CC, "-print-file-name=libm.so.6"], capture_output=True,
                          text=True).stdout.strip()
    if not Path(path).is_file() or shutil.which("nm") is None:
        return None
    out = subprocess.run(["nm", "-D", "--defined-only", path], capture_output=True, text=True).stdout
    return {line.split()[-1].split("@")[0] for line in out.splitlines() if line.strip()}


def undefined_symbols(objects):
    out = subprocess.run(["nm", "-u", *map(str, objects)], capture_output=True, text=True,
                         check=True).stdout
    return {line.split()[-1] for line in out.splitlines() if line.startswith(" ")}


@needs_cc
@pytest.mark.parametrize("opt", ["-O0", "-O2"])
def test_the_fast_folder_with_the_controller_needs_no_libm(model10, bench, tmp_path, opt):
    """Every object of a fast folder (an ELM, a grey-box eq. (1) model, the controller and the
    adaptation runtime) leaves no libm function undefined; the libm build of the same folder
    does (expf), which shows that the check sees them."""
    libm = libm_symbols()
    if libm is None:
        pytest.skip("no glibc libm.so.6 or nm to list libm's functions")
    from fricgen.control.c_adapted import render_adapt
    undefined = {}
    for impl in ("fast", "libm"):
        folder = tmp_path / impl
        codegen.emit(model10, folder, "fm", activation_impl=impl, with_controller=True)
        codegen.emit(table1_greybox(bench), folder, "gb", activation_impl=impl)
        for fname, text in render_adapt(model10, "fm", impl).items():
            (folder / fname).write_text(text)
        sources = sorted(p.name for p in folder.glob("*.c"))
        proc = compile_c(folder, *sources, flags=("-std=c99", opt))
        assert proc.returncode == 0, proc.stderr
        undefined[impl] = undefined_symbols(sorted(folder.glob("*.o"))) & libm
    assert undefined["fast"] == set()
    assert "expf" in undefined["libm"]
