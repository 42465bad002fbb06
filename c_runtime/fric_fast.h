/* fricgen C runtime: ELM hidden-layer kernel with the fast sigmoid, [F7]-[F8], without libm.
 * Also exp(-a) without libm for the grey-box Stribeck model, [F2].
 * C99, float only, no dynamic memory, no global state. Part of fricgen; copied by
 * `fricgen emit --activation-impl fast`.
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#ifndef FRIC_FAST_H
#define FRIC_FAST_H

#include "fric_float.h"   /* float semantics independent of the compiler's flags */
#include "fric_version.h" /* FRIC_RUNTIME_VERSION_MAJOR, _MINOR, _PATCH */

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The kernel clamps its input x to [0, FRIC_FAST_X_MAX] (NaN -> 0): the network's domain is
 * [0, 1] ([F3] saturates it) and `fricgen emit` checks that every |w[k] x + b[k]| <= 125 there
 * (the pre-multiplied tables below). */
#define FRIC_FAST_X_MAX 1.0009765625f

/**
 * @brief The fast sigmoid of [F8]: 1 / (1 + 2^t), t = -z log2(e), 2^t from exponent arithmetic
 *        and a degree-4 polynomial; no libm call.
 *
 * For every float z: |fric_sigmoid_fast_f32(z) - 1/(1+exp(-z))| <= 8.7e-7 (the bound derived in
 * fricgen.fast_sigmoid, enforced by tests/test_fast_sigmoid.py).
 * @param[in] z any float, clamped to [-86, 86] (so -inf -> 4.5e-38, +inf -> 1).
 * @return the sigmoid of z, within 8.7e-7; NaN returns NaN.
 */
float fric_sigmoid_fast_f32(float z);

/**
 * @brief The ELM sigmoid kernel without libm: sum_k beta[k] / (1 + 2^t_k), t_k = w[k] * x + b[k],
 *        k = 0, 1, ...
 *
 * The tables are pre-multiplied: w[k] = -log2(e) w_k, b[k] = -log2(e) b_k for the network's
 * w_k, b_k (emit rounds each product once to float), so t_k = -log2(e) z_k. Each float operation
 * is rounded in this order; fricgen.fast_sigmoid mirrors it exactly.
 * @param[in] w, b the pre-multiplied input weights and biases, -log2(e) w_k and -log2(e) b_k,
 *            n each.
 * @param[in] beta the output weights, n.
 * @param[in] n the number of hidden neurons.
 * @param[in] x the network input, clamped to [0, FRIC_FAST_X_MAX] (NaN -> 0).
 * @return the sum; each term is within 8.5e-7 |beta[k]| of beta[k] / (1 + 2^t_k) for the float
 *         t_k formed.
 */
float fric_elm_sigmoid_fast_f32(const float *w, const float *b, const float *beta, size_t n, float x);

/**
 * @brief exp(-a) = 2^t, t = a * fl(-log2(e)), without libm, for the Stribeck shapes of [F2]
 *        (`fricgen emit` of a grey-box model).
 * @param[in] a the argument, clamped to [-86, 86] (|t| <= 125).
 * @return exp(-a) of the clamped a, its relative error that of the polynomial plus the rounding
 *         of t (fricgen.fast_sigmoid.exp_neg_error_bound); NaN returns NaN.
 */
float fric_exp_neg_fast_f32(float a);

#ifdef __cplusplus
}
#endif

#endif /* FRIC_FAST_H */
