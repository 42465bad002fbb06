/* fricgen C runtime: hidden-layer kernels of the Extreme Learning Machine, eq. (7).
 * C99, float only, no dynamic memory, no global state. Part of fricgen; copied by `fricgen emit`. */
#ifndef FRIC_KERNEL_H
#define FRIC_KERNEL_H

/* Float semantics that do not depend on the compiler's flags (the same block opens fric_kernel.h,
 * fric_fast.h and fric_ctrl.c; tests/test_flag_matrix.py checks that the copies agree).
 * Every float operation of the runtime and of the model code that includes this header is
 * rounded as written, which is what makes it bit-equal to its Python twin:
 * - -ffast-math and -ffinite-math-only are refused: they fold fric_fast.c's rounding trick
 *   (exp(-1) came out as 0.5) and drop the NaN checks the contracts rely on.
 * - Contraction of a * b + c into a fused multiply-add (GCC's default in its GNU modes, e.g.
 *   -std=gnu99; clang's default within one expression) is turned off for the rest of the
 *   translation unit. GCC ignores `#pragma STDC FP_CONTRACT` but honours
 *   `#pragma GCC optimize ("fp-contract=off")` for the functions defined after it (GCC 12,
 *   -std=gnu99 -O2 -mfma: 17 vfmadd in fric_fast.o without it, 0 with it, same code size).
 * Other flags that relax IEEE arithmetic one by one (-fassociative-math, -freciprocal-math)
 * define no macro and cannot be detected here: do not build the runtime with them. */
#ifndef FRIC_FP_SEMANTICS
#define FRIC_FP_SEMANTICS
#if defined(__FAST_MATH__) || (defined(__FINITE_MATH_ONLY__) && (__FINITE_MATH_ONLY__ > 0))
#error "fricgen runtime: -ffast-math / -ffinite-math-only change its results; build it without them"
#endif
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize ("fp-contract=off")
#else
#pragma STDC FP_CONTRACT OFF
#endif
#endif /* FRIC_FP_SEMANTICS */

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* sum_k beta[k] * act(w[k] * x + b[k]) for k = 0 .. n-1, accumulated in order k = 0, 1, ...
 * Each product and sum is rounded to float; the Python twin mirrors this order exactly. */
float fric_elm_sigmoid_f32(const float *w, const float *b, const float *beta, size_t n, float x);
float fric_elm_sine_f32(const float *w, const float *b, const float *beta, size_t n, float x);
float fric_elm_rbf_f32(const float *w, const float *b, const float *beta, size_t n, float x);
float fric_elm_multiquadric_f32(const float *w, const float *b, const float *beta, size_t n, float x);

#ifdef __cplusplus
}
#endif

#endif /* FRIC_KERNEL_H */
