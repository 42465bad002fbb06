/* fricgen C runtime: ELM hidden-layer kernel with the fast sigmoid, eq. (7)-(8), without libm.
 * C99, float only, no dynamic memory, no global state. Part of fricgen; copied by
 * `fricgen emit --activation-impl fast`. */
#ifndef FRIC_FAST_H
#define FRIC_FAST_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The fast sigmoid of eq. (8): 1 / (1 + e) with e = 2^-t, t = |z| log2(e), evaluated as
 * 2^-floor(t) (exponent arithmetic) times a degree-5 polynomial of 2^-frac(t); no libm call.
 * |fric_sigmoid_fast_f32(z) - 1/(1+exp(-z))| <= 2.2e-7 for every float z (the bound derived in
 * fricgen.fast_sigmoid, enforced by tests/test_fast_sigmoid.py; measured max 1.2e-7). |z| >= 41.6 (t >= 60) is
 * evaluated at t = 60: the result is 1 or 2^-60 / (1 + 2^-60). NaN is evaluated as t = 60 too
 * and gives 1.0f. Finite in, finite out, in [0, 1]. */
float fric_sigmoid_fast_f32(float z);

/* sum_k beta[k] * fric_sigmoid_fast_f32(w[k] * x + b[k]), k = 0, 1, ..., each operation
 * rounded to float in this order; fricgen.fast_sigmoid mirrors it exactly. */
float fric_elm_sigmoid_fast_f32(const float *w, const float *b, const float *beta, size_t n, float x);

#ifdef __cplusplus
}
#endif

#endif /* FRIC_FAST_H */
