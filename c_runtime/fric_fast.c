/* fricgen C runtime: the fast sigmoid of [F8] and its ELM kernel, [F7]. No libm.
 *
 * sigma(z) = 1 / (1 + e), e = exp(-z) = 2^t with t = -z log2(e). t is split without any
 * float-to-int conversion: adding FRIC_FAST_ROUND (1.5 * 2^23) rounds t to the nearest integer
 * n, which then sits in the low mantissa bits of the sum; f = t - n lies in [-1/2, 1/2] and is
 * exact. 2^f comes from a degree-4 polynomial (Horner), and the factor 2^n is added to its
 * float exponent field: (bits of the sum) << 23 equals n << 23 modulo 2^32. Valid, and exact as
 * described, for |t| <= 125. fric_sigmoid_fast_f32 clamps |z| <= 86 (|t| <= 125); the kernel
 * takes tables pre-multiplied by -log2(e), so t = w x + b directly, and clamps x so that every
 * |t| stays inside (`fricgen emit` checks the tables).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#include "fric_fast.h"

#include <stdint.h>

#if defined(__GNUC__)
#define FRIC_FAST_INLINE static inline __attribute__((always_inline))
#else
#define FRIC_FAST_INLINE static inline
#endif

#define FRIC_FAST_NEG_LOG2E (-1.44269502f) /* float32 rounding of -log2(e) */
#define FRIC_FAST_ROUND 12582912.0f      /* 1.5 * 2^23: t + this rounds t to an integer */
#define FRIC_FAST_Z_MAX 86.0f            /* |z| <= 86 keeps |t| <= 125: e stays a normal float */

/* 2^f on [-1/2, 1/2]: relative minimax of degree 4 with P(0) = 1 (2.8e-6), coefficients rounded
 * to float (fricgen.fast_sigmoid.minimax_exp2 rederives them). P0 = 1 keeps 2^n exact at integer
 * t and sigma(0) = 1/2. */
#define FRIC_FAST_P0 1.0f
#define FRIC_FAST_P1 0.693124175f
#define FRIC_FAST_P2 0.240240991f
#define FRIC_FAST_P3 0.0559064262f
#define FRIC_FAST_P4 0.00958285294f

typedef union {
    float f;
    uint32_t u;
} fric_fast_bits;

/* 2^t. Requires |t| <= 125 (callers guarantee it). */
FRIC_FAST_INLINE float fric_fast_exp2(float t)
{
    fric_fast_bits rounded;
    fric_fast_bits e;
    float f;
    rounded.f = t + FRIC_FAST_ROUND;
    f = t - (rounded.f - FRIC_FAST_ROUND);
    e.f = FRIC_FAST_P0 + (f * (FRIC_FAST_P1 + (f * (FRIC_FAST_P2 + (f * (FRIC_FAST_P3
          + (f * FRIC_FAST_P4)))))));
    e.u += rounded.u << 23;
    return e.f;
}

/* 1 + 2^t. Requires |t| <= 125 (callers guarantee it). */
FRIC_FAST_INLINE float fric_fast_one_plus_exp2(float t)
{
    return 1.0f + fric_fast_exp2(t);
}

/* Whether z is a NaN, read from its bits (exponent all ones, mantissa not zero): the same as
 * z != z for every input, without a float comparison (-Wfloat-equal) and without libm headers. */
FRIC_FAST_INLINE int fric_fast_is_nan(float z)
{
    fric_fast_bits b;
    int nan;
    b.f = z;
    if ((b.u & 0x7fffffffu) > 0x7f800000u) {
        nan = 1;
    } else {
        nan = 0;
    }
    return nan;
}

/* z clamped to [-FRIC_FAST_Z_MAX, FRIC_FAST_Z_MAX] (NaN stays NaN) */
FRIC_FAST_INLINE float fric_fast_clamp_z(float z)
{
    float c;
    if (z < -FRIC_FAST_Z_MAX) {
        c = -FRIC_FAST_Z_MAX;
    } else if (z > FRIC_FAST_Z_MAX) {
        c = FRIC_FAST_Z_MAX;
    } else {
        c = z;
    }
    return c;
}

float fric_sigmoid_fast_f32(float z)
{
    if (fric_fast_is_nan(z) != 0) {
        return z;
    }
    return 1.0f / fric_fast_one_plus_exp2(fric_fast_clamp_z(z) * FRIC_FAST_NEG_LOG2E);
}

float fric_elm_sigmoid_fast_f32(const float *w, const float *b, const float *beta, size_t n, float x)
{
    float acc = 0.0f;
    float xc;
    size_t k;
    if (!(x > 0.0f)) { /* also NaN */
        xc = 0.0f;
    } else if (x > FRIC_FAST_X_MAX) {
        xc = FRIC_FAST_X_MAX;
    } else {
        xc = x;
    }
    for (k = 0; k < n; ++k) {
        acc += beta[k] / fric_fast_one_plus_exp2((w[k] * xc) + b[k]); /* w, b times -log2(e) */
    }
    return acc;
}

float fric_exp_neg_fast_f32(float a)
{
    if (fric_fast_is_nan(a) != 0) {
        return a;
    }
    return fric_fast_exp2(fric_fast_clamp_z(a) * FRIC_FAST_NEG_LOG2E);
}
