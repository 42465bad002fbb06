/* fricgen C runtime: the fast sigmoid of eq. (8) and its ELM kernel, eq. (7). No libm. */
#include "fric_fast.h"

#include <stdint.h>

#define FRIC_FAST_LOG2E 1.44269502f /* float32 rounding of log2(e) */
#define FRIC_FAST_T_MAX 60.0f        /* 2^-60 < 1e-18: beyond, sigma is 1 to float precision */

/* 2^-f on [0, 1): near-minimax for relative error (7.5e-8), coefficients rounded to float. */
#define FRIC_FAST_P0 0.999999940f
#define FRIC_FAST_P1 -0.693142235f
#define FRIC_FAST_P2 0.240172192f
#define FRIC_FAST_P3 -0.0552797206f
#define FRIC_FAST_P4 0.00918861106f
#define FRIC_FAST_P5 -0.000938788173f

typedef union {
    float f;
    uint32_t u;
} fric_fast_bits;

static float fric_sigmoid_fast_inline(float z)
{
    const float a = z < 0.0f ? -z : z;
    float t = a * FRIC_FAST_LOG2E;
    int32_t n;
    float f;
    float p;
    fric_fast_bits e;
    if (!(t < FRIC_FAST_T_MAX)) { /* also NaN: keeps the conversion below defined */
        t = FRIC_FAST_T_MAX;
    }
    n = (int32_t)t; /* floor, t >= 0 */
    f = t - (float)n;
    p = FRIC_FAST_P0 + f * (FRIC_FAST_P1 + f * (FRIC_FAST_P2 + f * (FRIC_FAST_P3
        + f * (FRIC_FAST_P4 + f * FRIC_FAST_P5))));
    e.f = p; /* p in (0.49, 1): a normal float; minus n <= 60 octaves stays normal */
    e.u -= (uint32_t)n << 23;
    return (z < 0.0f ? e.f : 1.0f) / (1.0f + e.f);
}

float fric_sigmoid_fast_f32(float z)
{
    return fric_sigmoid_fast_inline(z);
}

float fric_elm_sigmoid_fast_f32(const float *w, const float *b, const float *beta, size_t n, float x)
{
    float acc = 0.0f;
    size_t k;
    for (k = 0; k < n; ++k) {
        acc += beta[k] * fric_sigmoid_fast_inline(w[k] * x + b[k]);
    }
    return acc;
}
