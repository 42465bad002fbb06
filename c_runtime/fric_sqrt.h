/* fricgen C runtime: the square root without libm, correctly rounded.
 * C99, no float library call, no dynamic memory, no global state. Part of fricgen; copied by
 * `fricgen emit --with-controller` (the adaptive law c of section 6 needs sqrt(e1^2 + e2^2)), so
 * that the controller links without libm, as the models of `--activation-impl fast` do.
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#ifndef FRIC_SQRT_H
#define FRIC_SQRT_H

#include "fric_version.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief sqrt(x) rounded to the nearest float, without libm.
 *
 * The same bits as an IEEE sqrtf (correctly rounded, as IEEE 754 requires of sqrtf and as
 * glibc's, newlib's and the Cortex-M4F's vsqrt are) for every float x, so the Python twins'
 * np.sqrt(float32) stays their twin; the error is at most half an ulp of the result, and 0
 * against sqrtf. Integers only: the mantissa's root digit by digit (24 steps on a 48-bit
 * integer), rounded by its remainder (a root of a float never lies halfway between two floats).
 * tests/test_control_c.py compares it with sqrtf on every float of [1, 4) (the bits of every
 * other binade pair only shift), on every subnormal and at the ends.
 * @param[in] x any float; subnormal x is exact too.
 * @return sqrt(x) correctly rounded; +-0 -> +-0, +inf -> +inf, NaN -> NaN, x < 0 -> NaN.
 */
float fric_sqrt_f32(float x);

#ifdef __cplusplus
}
#endif

#endif /* FRIC_SQRT_H */
