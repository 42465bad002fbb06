"""The emitted folder as a product: the runtime's version checked by every model header, the
build recorded (NAME_EMIT_OPTIONS, NAME_CODE_HASH), only the kernels a model calls, and no libm
for --activation-impl fast (with the controller too)."""
import hashlib
import json
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
    assert options["libm"] == "dtype=float activation_impl=libm with_controller=0 adapt=0"
    assert options["fast"] == "dtype=float activation_impl=fast with_controller=0 adapt=0"
    assert options["q15"] == "dtype=q15 v_max=default"
    assert _macro(codegen.render(model10, "fm", dtype="q31", v_max=0.5)["fm.h"],
                  "FM_EMIT_OPTIONS") == "dtype=q31 v_max=0.5"
    # the options, not the code, of the controller: the same NAME.c
    with_ctrl = codegen.render(model10, "fm", with_controller=True)["fm.h"]
    assert _macro(with_ctrl, "FM_CODE_HASH") == codes["libm"]
    assert _macro(with_ctrl, "FM_EMIT_OPTIONS").endswith("with_controller=1 adapt=0")


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
    """Every object of a fast folder (an ELM, a grey-box [F1] model, the controller and the
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


# --- the folder's build files: CMake, Zephyr, PlatformIO ---------------------------------------

CMAKE = shutil.which("cmake")
needs_cmake = pytest.mark.skipif(CMAKE is None or CC is None, reason="cmake or a C compiler missing")
#: A program of two axes: the bits of each model's force at one velocity.
AXES_MAIN = r"""
#include <stdio.h>
#include <string.h>
#include <stdint.h>
#include "fm.h"
#include "axis2.h"
static unsigned long bits(float f) { uint32_t u; memcpy(&u, &f, sizeof u); return (unsigned long)u; }
int main(void)
{
    printf("%08lx %08lx\n", bits(fm_force(0.01f)), bits(axis2_force(-0.02f)));
    return 0;
}
"""


def two_axes(folder, model10, axis2_model):
    """fm (libm, with the controller) and axis2 (fast) emitted into one folder."""
    codegen.emit(model10, folder, "fm", with_controller=True)
    return codegen.emit(axis2_model, folder, "axis2", activation_impl="fast")


def twin_bits(model10, axis2_model):
    import numpy as np
    from fricgen.codegen.twin import force_f32
    fm = force_f32(model10, np.array([0.01], np.float32), "libm").astype(np.float32)
    ax = force_f32(axis2_model, np.array([-0.02], np.float32), "fast").astype(np.float32)
    return fm[0], int(ax.view(np.uint32)[0])


def check_axes_output(out, model10, axis2_model):
    import numpy as np
    fm_twin, axis2_twin = twin_bits(model10, axis2_model)
    fm_bits, axis2_bits = (int(w, 16) for w in out.split())
    assert axis2_bits == axis2_twin                                  # fast: the twin's bits
    fm = np.array([fm_bits], np.uint32).view(np.float32)[0]
    assert abs(float(fm) - float(fm_twin)) <= 1e-5 * abs(float(fm_twin))  # libm's expf: ~1 ULP


def test_a_second_model_joins_the_first_in_the_build_files(model10, axis2_model, tmp_path):
    folder = tmp_path / "axes"
    codegen.emit(model10, folder, "fm")
    first = (folder / "CMakeLists.txt").read_text()
    assert "    fm.c\n" in first and "axis2.c" not in first and "fric_fast.c" not in first
    written = two_axes(folder, model10, axis2_model)
    assert set(codegen.PACKAGE_FILES) <= set(written)
    cmake = (folder / "CMakeLists.txt").read_text()
    sources = sorted(p.name for p in folder.glob("*.c"))
    listed = re.search(r"set\(AXES_SOURCES\n(.*?)\)", cmake, re.S).group(1).split()
    assert listed == sources and {"fm.c", "axis2.c", "fric_fast.c", "fric_sqrt.c"} <= set(sources)
    assert "add_library(axes STATIC" in cmake and "target_link_libraries(axes PUBLIC m)" in cmake
    assert "the friction models axis2, fm" in cmake


def test_a_folder_without_libm_calls_does_not_link_it(model10, tmp_path):
    codegen.emit(model10, tmp_path / "fast", "fm", activation_impl="fast", with_controller=True)
    codegen.emit(model10, tmp_path / "fast", "fq", dtype="q15")
    cmake = (tmp_path / "fast" / "CMakeLists.txt").read_text()
    assert "PUBLIC m)" not in cmake and "No libm" in cmake
    assert "-lm" not in json.loads((tmp_path / "fast" / "library.json").read_text())["build"]["flags"]
    assert "REQUIRES_FULL_LIBC" not in (tmp_path / "fast" / "Kconfig").read_text()


def test_build_files_someone_else_wrote_are_not_overwritten(model10, tmp_path):
    from fricgen.errors import UsageError
    (tmp_path / "CMakeLists.txt").write_text("add_subdirectory(app)\n")
    with pytest.raises(UsageError, match="CMakeLists.txt: was not written by fricgen"):
        codegen.emit(model10, tmp_path, "fm")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["CMakeLists.txt"]
    codegen.emit(model10, tmp_path, "fm", force=True)
    assert "Generated by fricgen" in (tmp_path / "CMakeLists.txt").read_text()
    codegen.emit(model10, tmp_path, "fm", activation_impl="fast")      # fricgen's own: rewritten


def test_the_library_name_is_the_folders_as_a_c_identifier(tmp_path):
    from fricgen.codegen.package import library_name
    assert library_name(tmp_path / "axes") == "axes"
    assert library_name(tmp_path / "my-axes.v2") == "my_axes_v2"
    assert library_name(tmp_path / "2axes") == "fricgen_2axes"


def test_library_json_is_a_platformio_manifest_of_the_folders_sources(model10, axis2_model,
                                                                       tmp_path):
    """name, version (semantic), and a build section: the folder as source and include folder,
    a source filter of exactly the folder's C sources, and the strict float flags; built as
    PlatformIO would (those sources, those flags), the two axes link and run."""
    folder = tmp_path / "axes"
    two_axes(folder, model10, axis2_model)
    manifest = json.loads((folder / "library.json").read_text())
    assert manifest["name"] == "axes" and re.fullmatch(r"\d+\.\d+\.\d+", manifest["version"])
    assert manifest["description"].startswith("Generated by fricgen")
    build = manifest["build"]
    assert build["srcDir"] == "." and build["includeDir"] == "."
    assert build["srcFilter"][0] == "-<*>"
    sources = [re.fullmatch(r"\+<(.+)>", f).group(1) for f in build["srcFilter"][1:]]
    assert sources == sorted(p.name for p in folder.glob("*.c"))
    assert build["flags"] == ["-ffp-contract=off", "-fno-fast-math", "-lm"]   # fm calls expf
    if CC is None:
        return
    (tmp_path / "main.c").write_text(AXES_MAIN)
    proc = subprocess.run([CC, "-std=c99", "-O2", *build["flags"][:-1], f"-I{folder}", "main.c",
                           *(str(folder / s) for s in sources), "-o", "axes_app", "-lm"],
                          cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    out = subprocess.run(["./axes_app"], cwd=tmp_path, capture_output=True, text=True, check=True)
    check_axes_output(out.stdout, model10, axis2_model)


def cmake_build(project, build, *options):
    for cmd in ([CMAKE, "-S", str(project), "-B", str(build), *options],
                [CMAKE, "--build", str(build)]):
        proc = subprocess.run(cmd, capture_output=True, text=True)
        assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]


@needs_cmake
def test_the_folder_builds_as_a_cmake_library_of_two_axes(model10, axis2_model, tmp_path):
    """add_subdirectory of the folder and a main.c linked to its target: configure, build and
    run on the host, the forces those of the twins; also under a project-wide -ffast-math, which
    the target's own flags undo (fric_float.h would otherwise refuse it)."""
    two_axes(tmp_path / "axes", model10, axis2_model)
    (tmp_path / "main.c").write_text(AXES_MAIN)
    (tmp_path / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.15)\nproject(app C)\nadd_subdirectory(axes)\n"
        "add_executable(app main.c)\ntarget_link_libraries(app PRIVATE fricgen::axes)\n")
    for label, options in {"plain": [], "fast-math": ["-DCMAKE_C_FLAGS=-ffast-math"]}.items():
        build = tmp_path / f"build-{label}"
        cmake_build(tmp_path, build, *options)
        assert (build / "axes" / "libaxes.a").is_file()
        out = subprocess.run([str(build / "app")], capture_output=True, text=True, check=True)
        check_axes_output(out.stdout, model10, axis2_model)


#: Zephyr's library functions as plain CMake, to build the module's CMakeLists.txt without the SDK.
ZEPHYR_STUB = """cmake_minimum_required(VERSION 3.15)
project(zephyr_stub C)
set(ZEPHYR_BASE ${CMAKE_CURRENT_SOURCE_DIR})
set(CONFIG_%(kconfig)s y)
add_library(zephyr_interface INTERFACE)
macro(zephyr_library_named name)
  add_library(${name} STATIC)
  target_link_libraries(${name} PUBLIC zephyr_interface)
  set(ZEPHYR_CURRENT_LIBRARY ${name})
endmacro()
macro(zephyr_library_sources)
  target_sources(${ZEPHYR_CURRENT_LIBRARY} PRIVATE ${ARGN})
endmacro()
macro(zephyr_include_directories)
  target_include_directories(zephyr_interface INTERFACE ${ARGN})
endmacro()
macro(zephyr_library_compile_options)
  target_compile_options(${ZEPHYR_CURRENT_LIBRARY} PRIVATE ${ARGN})
endmacro()
add_subdirectory(%(module)s module)
add_executable(app main.c)
target_link_libraries(app PRIVATE %(lib)s m)
"""


def test_the_folder_is_a_zephyr_module(model10, axis2_model, tmp_path):
    """zephyr/module.yml names the folder's CMakeLists.txt and Kconfig; the Kconfig defines the
    symbol the CMakeLists.txt tests."""
    yaml = pytest.importorskip("yaml")
    folder = tmp_path / "axes"
    two_axes(folder, model10, axis2_model)
    module = yaml.safe_load((folder / "zephyr" / "module.yml").read_text())
    assert module["name"] == "axes"
    assert (folder / module["build"]["cmake"] / "CMakeLists.txt").is_file()
    kconfig = (folder / module["build"]["kconfig"]).read_text()
    symbol = re.search(r"^config (\w+)$", kconfig, re.M).group(1)
    assert symbol == "FRICGEN_AXES" and "\tbool " in kconfig
    cmake = (folder / "CMakeLists.txt").read_text()
    assert f"if(CONFIG_{symbol})" in cmake and "zephyr_library_named(axes)" in cmake


@needs_cmake
def test_the_zephyr_branch_builds_with_zephyrs_library_functions_stubbed(model10, axis2_model,
                                                                         tmp_path):
    """Zephyr's build needs its SDK; here its four library functions are plain CMake, so the
    module's own CMakeLists.txt (ZEPHYR_BASE set, CONFIG_FRICGEN_AXES=y) builds the library
    that a host main.c links and runs."""
    two_axes(tmp_path / "axes", model10, axis2_model)
    project = tmp_path / "zephyr_app"
    project.mkdir()
    (project / "main.c").write_text(AXES_MAIN)
    (project / "CMakeLists.txt").write_text(ZEPHYR_STUB % {
        "kconfig": "FRICGEN_AXES", "module": tmp_path / "axes", "lib": "axes"})
    cmake_build(project, project / "build")
    out = subprocess.run([str(project / "build" / "app")], capture_output=True, text=True, check=True)
    check_axes_output(out.stdout, model10, axis2_model)


@pytest.mark.parametrize("dtype", ["float", "q15"])
def test_every_emitted_c_file_states_its_licence_in_its_head_comment(default_model, tmp_path, dtype):
    """LICENSE is MIT: every runtime copy and generated file (the model, its fixed-point form,
    the controller and the adaptation) carries the SPDX and copyright lines in its head
    comment, which a firmware's licence scanner reads."""
    from fricgen.control.c_adapted import render_adapt
    files = codegen.render(default_model, "fm", dtype=dtype, with_controller=dtype == "float")
    if dtype == "float":
        files.update(render_adapt(default_model, "fm"))
    for fname, text in files.items():
        if fname.endswith((".c", ".h")):
            head = text[:text.index("*/")]
            assert "SPDX-License-Identifier: MIT" in head and "Copyright (c)" in head, fname
    assert "MIT License" in (Path(__file__).resolve().parents[1] / "LICENSE").read_text()
