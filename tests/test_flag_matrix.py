"""Meaning that does not depend on flags: the runtime refuses -ffast-math, and the runtime with
emitted models (an ELM and a grey-box [F1] model, both --activation-impl fast: no libm) and
the controller on glitched inputs give the twins' bits under every compiler x -std x -O on this
machine (gcc, clang, arm-none-eabi-gcc under QEMU when installed), with no fused multiply-add."""
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from fricgen import codegen
from fricgen._io import resource_dir
from fricgen.codegen.cbuild import STRICT_WARNINGS
from fricgen.control.backstepping import AdaptiveBackstepping
from fricgen.control.faults import Glitched, random_glitches
from fricgen.control.loop import default_axis, simulate
from fricgen.firmware import flag_matrix as fm

CC = shutil.which("cc") or shutil.which("gcc")
pytestmark = pytest.mark.skipif(CC is None, reason="no C compiler")


def runtime_folder(tmp_path):
    return shutil.copytree(resource_dir("c_runtime"), tmp_path / "runtime")


@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_the_emitted_folder_holds_one_float_block_and_every_source_includes_it(tmp_path, impl,
                                                                               bench, model10):
    """One header fixes the float semantics (fric_float.h); every .c of a folder with an ELM, a
    grey-box [F1] model and the controller reaches it, directly or through a header."""
    for name, model in {"fm": model10, "gb": fm.table1_greybox(bench)}.items():
        codegen.emit(model, tmp_path, name, activation_impl=impl, with_controller=True)
    assert list(fm.fp_blocks(tmp_path)) == [fm.FLOAT_HEADER]
    reached = fm.includes_float_semantics(tmp_path)
    assert {"fm.c", "gb.c", "fric_ctrl.c"} < set(reached) and all(reached.values()), reached


def test_the_include_check_sees_a_source_without_the_header(tmp_path):
    (tmp_path / "a.h").write_text('#include "fric_float.h"\n')
    (tmp_path / "via.c").write_text('#include "a.h"\n')
    (tmp_path / "none.c").write_text('#include "b.h"\n#include <math.h>\n')
    (tmp_path / "b.h").write_text('#include "none.c"\n')      # a cycle ends
    assert fm.includes_float_semantics(tmp_path) == {"none.c": False, "via.c": True}


ARM_NEWLIB = Path("/usr/lib/arm-none-eabi/include")


@pytest.mark.skipif(shutil.which("clang") is None or not ARM_NEWLIB.is_dir(),
                    reason="no clang or no newlib headers")
def test_clang_builds_the_runtime_for_the_cortex_m4f_without_a_warning(tmp_path):
    """The x86-only float pragmas stay away from Arm, where clang ignores them with a warning
    (an error under -Werror)."""
    folder = runtime_folder(tmp_path)
    sources = sorted(p.name for p in folder.glob("*.c"))
    proc = subprocess.run(["clang", "--target=thumbv7em-none-eabihf", "-mcpu=cortex-m4",
                           "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard", "-std=c99", "-O2", "-isystem",
                           str(ARM_NEWLIB), *STRICT_WARNINGS, "-c", *sources],
                          cwd=folder, capture_output=True, text=True)
    assert proc.returncode == 0 and "fric_adapt.c" in sources, proc.stderr[:2000]


@pytest.mark.parametrize("flag", ["-ffast-math", "-ffinite-math-only"])
@pytest.mark.parametrize("source", ["fric_elm_sigmoid.c", "fric_exp_neg.c", "fric_fast.c", "fric_ctrl.c",
                                    "fric_sqrt.c"])
def test_fast_math_is_a_compile_error(tmp_path, flag, source):
    folder = runtime_folder(tmp_path)
    proc = subprocess.run([CC, "-std=c99", "-O2", flag, "-c", source, "-o", "/dev/null"],
                          cwd=folder, capture_output=True, text=True)
    assert proc.returncode != 0 and "-ffast-math" in proc.stderr


@pytest.fixture(scope="module")
def matrix(tmp_path_factory, bench, model10):
    tmp = tmp_path_factory.mktemp("flag_matrix")
    models = {"fm": model10, "gb": fm.table1_greybox(bench)}
    for name, model in models.items():
        codegen.emit(model, tmp / "src", name, activation_impl="fast", with_controller=True)
    settings = AdaptiveBackstepping(compensation=model10)
    glitched = Glitched(settings.clone(dtype="float32"),
                        random_glitches(1000, np.random.default_rng(3), 30, first=100))
    simulate(default_axis(), [glitched], duration=1.0, substeps=2)
    v = np.concatenate([np.linspace(-2 * model10.v_sat, 2 * model10.v_sat, 201),
                        [0.0, -0.0, 1e3, -1e3, np.nan, np.inf]]).astype(np.float32)
    flag_sets = fm.available_flag_sets()
    rows = fm.run_matrix(tmp / "src", list(models), flag_sets, tmp / "out", v, glitched.rows_,
                         settings)
    return rows, fm.twin_lines(models, "fast", v, glitched.rows_, settings)


def test_every_build_equals_the_twins_bit_for_bit(matrix):
    rows, twin = matrix
    print("\n".join(f"{r.flags.label}: fma {r.fma}, "
                    f"{fm.first_difference(r.lines, twin) or 'bit-equal'}" for r in rows))
    assert {r.flags.std for r in rows} == {"c99", "gnu99"} and len(rows) >= 6
    assert any(line.startswith("c ") and int(line.split()[2], 16) & 2 for line in twin)  # faults
    for r in rows:
        assert fm.first_difference(r.lines, twin) is None, r.flags.label


@pytest.mark.parametrize("extra", fm.RELAXING_FLAGS)
def test_a_flag_that_relaxes_ieee_arithmetic_gives_the_twins_bits_or_a_compile_error(
        tmp_path, extra, model10, bench):
    """-funsafe-math-optimizations, -fassociative-math, -freciprocal-math and -ffp-contract=fast
    under gcc and clang (-std=gnu99 -O2, FMA available): every build of the runtime with both
    models and the controller either refuses to compile, naming the flag, or equals the twins'
    bits with no fused multiply-add. Clang's -ffp-contract=fast overrides its contract pragma;
    on x86 the constrained operations of ``STDC FENV_ACCESS ON`` hold against it."""
    models = {"fm": model10, "gb": fm.table1_greybox(bench)}
    for name, model in models.items():
        codegen.emit(model, tmp_path / "src", name, activation_impl="fast", with_controller=True)
    v = np.linspace(-2 * model10.v_sat, 2 * model10.v_sat, 101).astype(np.float32)
    rows = np.zeros((1, 6), dtype=np.float32)
    settings = AdaptiveBackstepping()
    twin = fm.twin_lines(models, "fast", v, rows, settings)
    # -Wno-error: gcc warns that it disables -fassociative-math alone, which the strict
    # warnings would turn into the compile error that hid what the flag still changed
    sets = [fm.FlagSet(c, "gnu99", "-O2", f"{extra} -Wno-error") for c in fm.HOST_COMPILERS
            if shutil.which(c)]
    assert sets
    for k, flags in enumerate(sets):
        try:
            row, = fm.run_matrix(tmp_path / "src", list(models), [flags], tmp_path / f"out{k}", v,
                                 rows, settings)
        except fm.fw.FirmwareError as exc:
            assert "change its results" in str(exc), str(exc)[:500]
            continue
        assert fm.first_difference(row.lines, twin) is None and row.fma == 0, flags.label


def test_no_build_contains_a_fused_multiply_add(matrix):
    rows, _ = matrix
    assert all(r.fma == 0 for r in rows), {r.flags.label: r.fma for r in rows if r.fma}


def test_the_fma_counter_sees_contraction(tmp_path):
    """The count above is not vacuous: a * b + c under -std=gnu99 -O2 (with FMA available)."""
    src = tmp_path / "mad.c"
    src.write_text("float mad(float a, float b, float c) { return a * b + c; }\n")
    flags = fm.host_fma_flags()
    if not flags:
        pytest.skip("the host has no FMA instruction")
    subprocess.run(["gcc", "-std=gnu99", "-O2", *flags, "-c", str(src), "-o", str(tmp_path / "m.o")],
                   check=True)
    assert fm.fma_count([tmp_path / "m.o"], "objdump") == 1


def test_without_the_block_gnu99_contracts_and_the_bits_differ(tmp_path, model10):
    """What the block buys: the same runtime without it, under gcc -std=gnu99 -O2."""
    if not fm.host_fma_flags() or shutil.which("gcc") is None:
        pytest.skip("the host has no FMA instruction (or no gcc)")
    codegen.emit(model10, tmp_path / "src", "fm", activation_impl="fast", with_controller=True)
    assert fm.strip_fp_blocks(tmp_path / "src") == [fm.FLOAT_HEADER]
    v = np.linspace(-2 * model10.v_sat, 2 * model10.v_sat, 201).astype(np.float32)
    rows = np.zeros((1, 6), dtype=np.float32)
    settings = AdaptiveBackstepping()
    row, = fm.run_matrix(tmp_path / "src", ["fm"], [fm.FlagSet("gcc", "gnu99", "-O2")],
                         tmp_path / "out", v, rows, settings)
    assert row.fma > 0
    assert fm.first_difference(row.lines, fm.twin_lines({"fm": model10}, "fast", v, rows, settings))
