/* fricgen C runtime: hidden-layer kernels of the Extreme Learning Machine, eq. (7).
 * C99, float only, no dynamic memory, no global state. Part of fricgen; copied by `fricgen emit`. */
#ifndef FRIC_KERNEL_H
#define FRIC_KERNEL_H

#include "fric_float.h" /* float semantics independent of the compiler's flags */

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Arguments of expf are clamped to [-FRIC_EXP_ARG_MAX, FRIC_EXP_ARG_MAX]: there expf neither
 * overflows nor underflows (its result stays a normal float: exp(-87) = 1.6e-38 > FLT_MIN,
 * exp(87) = 6.1e37 < FLT_MAX), so no call sets errno (glibc sets ERANGE on both). */
#define FRIC_EXP_ARG_MAX 87.0f

/* exp(-a) through libm's expf, a clamped to [-FRIC_EXP_ARG_MAX, FRIC_EXP_ARG_MAX]; NaN returns
 * NaN. For the Stribeck shapes of eq. (2) and the sigmoid and rbf kernels below. */
float fric_exp_neg_f32(float a);

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
