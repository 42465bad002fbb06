/* fricgen C runtime: hidden-layer kernels of the Extreme Learning Machine, [F7], through libm.
 * C99, float only, no dynamic memory, no global state. Part of fricgen; copied by `fricgen emit`.
 * One header, one source per kernel: fric_elm_sigmoid.c, fric_elm_sine.c, fric_elm_rbf.c,
 * fric_elm_multiquadric.c, and fric_exp_neg.c (exp(-a), also for the grey-box shapes of [F2]);
 * `fricgen emit` copies the sources its model calls, so a link without --gc-sections pulls in
 * only the libm functions the model needs (sinf, sqrtf and expf each add kilobytes).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#ifndef FRIC_KERNEL_H
#define FRIC_KERNEL_H

#include "fric_float.h"   /* float semantics independent of the compiler's flags */
#include "fric_version.h" /* FRIC_RUNTIME_VERSION_MAJOR, _MINOR, _PATCH */

#include <math.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Arguments of expf are clamped to [-FRIC_EXP_ARG_MAX, FRIC_EXP_ARG_MAX]: there expf neither
 * overflows nor underflows (its result stays a normal float: exp(-87) = 1.6e-38 > FLT_MIN,
 * exp(87) = 6.1e37 < FLT_MAX), so no call sets errno (glibc sets ERANGE on both). */
#define FRIC_EXP_ARG_MAX 87.0f

/**
 * @brief exp(-a) through libm's expf, a clamped to [-FRIC_EXP_ARG_MAX, FRIC_EXP_ARG_MAX].
 *
 * The one definition: the sigmoid and rbf kernels inline it, fric_exp_neg_f32 calls it.
 * @param[in] a the argument, clamped to [-FRIC_EXP_ARG_MAX, FRIC_EXP_ARG_MAX].
 * @return exp(-a) of the clamped a; NaN returns NaN.
 */
static inline float fric_exp_neg_inline_f32(float a)
{
    const float c = (a > FRIC_EXP_ARG_MAX) ? FRIC_EXP_ARG_MAX
                  : ((a < -FRIC_EXP_ARG_MAX) ? -FRIC_EXP_ARG_MAX : a); /* NaN stays NaN */
    return expf(-c);
}

/**
 * @brief exp(-a) as fric_exp_neg_inline_f32 (fric_exp_neg.c), for the Stribeck shapes of [F2]
 *        in the generated code.
 * @param[in] a the argument, clamped to [-FRIC_EXP_ARG_MAX, FRIC_EXP_ARG_MAX].
 * @return exp(-a) of the clamped a; NaN returns NaN.
 */
float fric_exp_neg_f32(float a);

/* The four kernels below: sum_k beta[k] * act(w[k] * x + b[k]) for k = 0 .. n-1, accumulated in
 * order k = 0, 1, ... Each product and sum is rounded to float; the Python twin mirrors this
 * order exactly. Each is defined in its own source, fric_elm_<act>.c, through FRIC_ELM_KERNEL. */

/**
 * @brief The sigmoid kernel, [F7]-[F8]: sum_k beta[k] / (1 + exp(-z_k)), z_k = w[k] * x + b[k],
 *        k = 0 .. n-1 in order (fric_elm_sigmoid.c); the exponential's argument clamped
 *        (z < -87 gives 1.6e-38).
 * @param[in] w, b, beta the input weights, biases and output weights, n each.
 * @param[in] n the number of hidden neurons.
 * @param[in] x the network input.
 * @return the sum, each product and sum rounded to float in this order.
 */
float fric_elm_sigmoid_f32(const float *w, const float *b, const float *beta, size_t n, float x);

/**
 * @brief The sine kernel, [F7]: sum_k beta[k] * sin(z_k), z_k = w[k] * x + b[k], k = 0 .. n-1
 *        in order, through libm's sinf (fric_elm_sine.c).
 * @param[in] w, b, beta the input weights, biases and output weights, n each.
 * @param[in] n the number of hidden neurons.
 * @param[in] x the network input.
 * @return the sum, each product and sum rounded to float in this order.
 */
float fric_elm_sine_f32(const float *w, const float *b, const float *beta, size_t n, float x);

/**
 * @brief The Gaussian RBF kernel, [F7]: sum_k beta[k] * exp(-z_k^2), z_k = w[k] * x + b[k],
 *        k = 0 .. n-1 in order, through libm's expf (fric_elm_rbf.c).
 * @param[in] w, b, beta the input weights, biases and output weights, n each.
 * @param[in] n the number of hidden neurons.
 * @param[in] x the network input.
 * @return the sum, each product and sum rounded to float in this order.
 */
float fric_elm_rbf_f32(const float *w, const float *b, const float *beta, size_t n, float x);

/**
 * @brief The multiquadric kernel, [F7]: sum_k beta[k] * sqrt(1 + z_k^2), z_k = w[k] * x + b[k],
 *        k = 0 .. n-1 in order, through libm's sqrtf (fric_elm_multiquadric.c).
 * @param[in] w, b, beta the input weights, biases and output weights, n each.
 * @param[in] n the number of hidden neurons.
 * @param[in] x the network input.
 * @return the sum, each product and sum rounded to float in this order.
 */
float fric_elm_multiquadric_f32(const float *w, const float *b, const float *beta, size_t n, float x);

/* The definition of a kernel NAME with the activation ACT, an expression of z. */
#define FRIC_ELM_KERNEL(NAME, ACT)                                                     \
    float NAME(const float *w, const float *b, const float *beta, size_t n, float x) \
    {                                                                                \
        float acc = 0.0f;                                                            \
        size_t k;                                                                    \
        for (k = 0; k < n; ++k) {                                                    \
            const float z = (w[k] * x) + b[k];                                       \
            acc += beta[k] * (ACT);                                                  \
        }                                                                            \
        return acc;                                                                  \
    }

#ifdef __cplusplus
}
#endif

#endif /* FRIC_KERNEL_H */
