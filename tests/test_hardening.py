"""Hardened C: defined behaviour for every input, checked under ASan/UBSan over >= 10^6 inputs
in one compiled program per implementation, and cppcheck clean.

Documented behaviour of NAME_force (float): NaN -> NaN; +-inf -> +-inf; every finite v ->
a finite force unless B |v| overflows float (|v| > FLT_MAX / B, then +-inf); F(-v) = -F(v)
exactly. Fixed point: every input gives a saturated, in-range result; F(-v) = -F(v) except at
the most negative input.
"""
import shutil
import subprocess

import numpy as np
import pytest

from fricgen import codegen
from fricgen.model import FrictionModel, Scaling
from fricgen.networks.stribeck import StribeckCurve

SAN = ["-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer", "-g"]
N_FUZZ = 1_100_000

FLOAT_FUZZ = r"""
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <math.h>
#include "fm.h"
static uint64_t s = 88172645463325252ull;
static uint32_t next(void) { s ^= s << 13; s ^= s >> 7; s ^= s << 17; return (uint32_t)s; }
static float from_bits(uint32_t u) { float f; memcpy(&f, &u, sizeof f); return f; }
int main(void) {
    const float special[] = {0.0f, -0.0f, 1e-45f, -1e-45f, 1e-38f, INFINITY, -INFINITY, NAN,
                             3.4e38f, -3.4e38f, FM_V_SAT, -FM_V_SAT};
    long i, bad = 0;
    for (i = 0; i < %(n)d; ++i) {
        uint32_t u = next();
        float v = i < 12 ? special[i] : (i & 1 ? from_bits(u) : (float)((int32_t)u) * 1e-10f);
        float f = fm_force(v), g = fm_force(-v);
        if (isnan(v) != isnan(f)) bad++;
        else if (!isnan(v)) {
            if (f != -g) bad++;
            if (isinf(v) && !(isinf(f) && (f > 0) == (v > 0))) bad++;
            if (isfinite(v) && fabsf(v) < 1e30f && !isfinite(f)) bad++;
        }
        (void)fm_aim(v);
    }
    printf("%%ld inputs, %%ld violations\n", i, bad);
    return bad != 0;
}
"""

FIXED_FUZZ = r"""
#include <stdint.h>
#include <stdio.h>
#include "fm.h"
static uint64_t s = 88172645463325252ull;
static uint32_t next(void) { s ^= s << 13; s ^= s >> 7; s ^= s << 17; return (uint32_t)s; }
int main(void) {
    long i, bad = 0;
    for (i = 0; i < %(n)d; ++i) {
        const %(ct)s v = i < 65536 ? (%(ct)s)(int32_t)(i - 32768) : (%(ct)s)(int32_t)next();
        const %(ct)s f = fm_force_%(dt)s(v);
        if (v != %(min)s && fm_force_%(dt)s((%(ct)s)-v) != -f) bad++;
        if ((v > 0 && f < 0) || (v < 0 && f > 0) || (v == 0 && f != 0)) bad++;
    }
    printf("%%ld inputs, %%ld violations\n", i, bad);
    return bad != 0;
}
"""


def sanitized_run(folder, main_c):
    (folder / "fuzz_main.c").write_text(main_c)
    exe = folder / "fuzz"
    sources = [str(p) for p in sorted(folder.glob("*.c")) if not p.name.startswith("fric_ctrl")]
    subprocess.run(["cc", "-std=c99", "-O1", "-ffp-contract=off"] + SAN + sources + ["-o", str(exe), "-lm"],
                   check=True, capture_output=True)
    proc = subprocess.run([str(exe)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0 and "runtime error" not in proc.stderr, proc.stdout + proc.stderr[-2000:]
    return proc.stdout


@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_float_force_has_defined_behaviour_for_every_input_under_sanitizers(model10, impl, tmp_path):
    codegen.emit(model10, tmp_path, "fm", activation_impl=impl)
    out = sanitized_run(tmp_path, FLOAT_FUZZ % {"n": N_FUZZ})
    assert out.strip() == f"{N_FUZZ} inputs, 0 violations"


@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_grey_box_force_has_defined_behaviour_for_every_input_under_sanitizers(impl, tmp_path):
    """[F1]'s loop over the sources reads its tables in bounds (ASan checks every global)."""
    curve = StribeckCurve("exponential", 0.4, np.array([0.3, 0.25]), np.array([0.08, 0.3]), 0.02)
    model = FrictionModel(curve, Scaling(1 / 0.06, 1 / 44.0), 57.5, 0.06, name="fm")
    codegen.emit(model, tmp_path, "fm", activation_impl=impl)
    out = sanitized_run(tmp_path, FLOAT_FUZZ % {"n": N_FUZZ})
    assert out.strip() == f"{N_FUZZ} inputs, 0 violations"


@pytest.mark.parametrize("dtype", ["q15", "q31"])
def test_fixed_force_has_defined_behaviour_for_every_input_under_sanitizers(model10, dtype, tmp_path):
    codegen.emit(model10, tmp_path, "fm", dtype=dtype)
    ct, mn = ("int16_t", "INT16_MIN") if dtype == "q15" else ("int32_t", "INT32_MIN")
    out = sanitized_run(tmp_path, FIXED_FUZZ % {"n": N_FUZZ, "ct": ct, "dt": dtype, "min": mn})
    assert out.strip() == f"{N_FUZZ} inputs, 0 violations"


@pytest.mark.parametrize("dtype", ["q15", "q31"])
def test_fixed_point_grey_box_table_is_read_in_bounds_for_every_input_under_sanitizers(dtype, tmp_path):
    """The AIM table of a fixed-point [F1] model: x = 1 (every |v| >= v_sat) is its last
    point, read without its right neighbour (ASan checks every global). v_sat = 0.05 m/s:
    K_in v_sat rounds to exactly 1 in q15 and q31 (with 0.06 m/s it stays 1 LSB below)."""
    curve = StribeckCurve("exponential", 0.4, np.array([0.3, 0.25]), np.array([0.08, 0.3]), 0.02)
    model = FrictionModel(curve, Scaling(1 / 0.05, 1 / 44.0), 57.5, 0.05, name="fm")
    codegen.emit(model, tmp_path, "fm", dtype=dtype)
    ct, mn = ("int16_t", "INT16_MIN") if dtype == "q15" else ("int32_t", "INT32_MIN")
    out = sanitized_run(tmp_path, FIXED_FUZZ % {"n": N_FUZZ, "ct": ct, "dt": dtype, "min": mn})
    assert out.strip() == f"{N_FUZZ} inputs, 0 violations"


@pytest.mark.skipif(shutil.which("cppcheck") is None, reason="cppcheck not installed (apt-get install cppcheck)")
@pytest.mark.parametrize("variant", [dict(activation_impl="libm"), dict(activation_impl="fast"),
                                     dict(dtype="q15"), dict(dtype="q31")])
def test_emitted_c_is_cppcheck_clean(model10, variant, tmp_path):
    codegen.emit(model10, tmp_path, "fm", **variant)
    proc = subprocess.run(["cppcheck", "--error-exitcode=1", "--enable=warning,portability,performance",
                           "--std=c99", "--quiet", "--inline-suppr", str(tmp_path)],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
