/* fricgen C runtime: adaptive backstepping position control with friction compensation
 * (section 6 of the multisource ELM friction paper). Part of fricgen; copied by `fricgen emit`.
 * C99, float only, no dynamic memory, no global state: the caller owns a fric_ctrl_t.
 *
 * Per sample (every ts seconds), with e1 = xd - x:
 *   v_d   = xd' + k1 e1                    e2 = v_d - v
 *   v_d'  = xd'' + k1 (e2 - k1 e1)         xi = [v_d', F_Fm / phi_n]
 *   i     = m_o_hat xi0 + k_hat xi1 + k2 e2 + e1, limited to [-i_max, i_max]
 *   A    += ts (e2 Gamma xi - sigma Gamma A),  A = [m_o_hat, k_hat], sigma = 0 (law a),
 *           delta (law b), delta sqrt(e1^2 + e2^2) (law c); each estimate then projected onto
 *           its interval [m_o_min, m_o_max], [k_min, k_max]
 * F_Fm is the friction compensation force in newtons, e.g. an emitted model's NAME_force.
 *
 * Usage:
 *   fric_ctrl_params_t p; fric_ctrl_t c; float i;
 *   fric_ctrl_default_params(&p);  p.ts = 1e-3f;  ...
 *   if (fric_ctrl_init(&c, &p) != FRIC_CTRL_OK) { ... bad parameters ... }
 *   every ts:  flags = fric_ctrl_step_fn(&c, x, v, xd, xd_dot, xd_ddot, NAME_force, &i);
 * or, with the force computed elsewhere:
 *              flags = fric_ctrl_step(&c, x, v, xd, xd_dot, xd_ddot, NAME_force(v), &i);
 * Units: m, m/s, m/s^2, s, N, A. The current i is to be held until the next sample.
 *
 * The contract of a step, for a c that fric_ctrl_init accepted and nothing else wrote since:
 * - Whatever the inputs (NaN, +-inf, huge or denormal floats), the current written is finite
 *   and within [-i_max, i_max], and m_o_hat, k_hat stay finite within their intervals.
 * - A non-finite input (x, v, xd, xd_dot, xd_ddot, or the friction force), or finite inputs so
 *   large that the demanded current is NaN (an overflow, inf - inf), is an input fault: the
 *   current is 0 A (not the last one: a dead sensor must not keep the axis driven), the
 *   estimates and e1, e2 are left as they were, the step returns FRIC_CTRL_INPUT_FAULT.
 * - A demand beyond +-i_max (an overflow to +-inf included) gives +-i_max and
 *   FRIC_CTRL_SATURATED; the estimates are not adapted in that step (no wind-up).
 * - An estimate that the adaptive law would move out of its interval is set to the nearer end,
 *   and the step returns FRIC_CTRL_PROJECTED.
 * - Nothing is remembered of a faulty sample: the first step with finite inputs after a glitch
 *   computes exactly what it would have computed with the same estimates before it, so the
 *   controller recovers as the closed loop does from the error the glitch left.
 * - A NULL c or current returns FRIC_CTRL_FAULT_NULL and writes nothing.
 * The float operations are those written here, in this order, each rounded to float (the file
 * refuses -ffast-math and turns contraction to fused multiply-add off);
 * fricgen.control.AdaptiveBackstepping(dtype="float32") computes the same bits.
 * Calling contexts: no global or static variable is written and no errno is set, so every
 * function is reentrant on distinct structs. Update one struct from one context (the control
 * ISR); read it elsewhere (save, export, logging) from a copy taken with that interrupt masked;
 * init, reset and restore before the ISR starts or with it masked (docs/reference/c-api.md).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#ifndef FRIC_CTRL_H
#define FRIC_CTRL_H

#include <stdint.h>
#include "fric_version.h" /* FRIC_RUNTIME_VERSION_MAJOR, _MINOR, _PATCH */

#ifdef __cplusplus
extern "C" {
#endif

#define FRIC_CTRL_VERSION 4

/* fricgen.control.c_abi mirrors the enums, flags and structs below (fricgen's tests check that
 * both agree). The choices a struct holds (law, friction_at) are int32_t with typed constants,
 * not enums: an enum's size is the compiler's (int on most hosts, the smallest that fits under
 * arm-none-eabi-gcc, whose AAPCS default is -fshort-enums), and the structs keep one layout
 * whatever it is. */

/* Return codes of fric_ctrl_init. */
typedef enum {
    FRIC_CTRL_OK = 0,
    FRIC_CTRL_ERR_NULL = -1,  /* a NULL pointer */
    FRIC_CTRL_ERR_PARAM = -2  /* a parameter out of range (see fric_ctrl_params_t) */
} fric_ctrl_status_t;

/* Adaptation laws a, b, c of [C14]. */
typedef int32_t fric_ctrl_law_t;
#define FRIC_CTRL_LAW_A ((fric_ctrl_law_t)0)
#define FRIC_CTRL_LAW_B ((fric_ctrl_law_t)1)
#define FRIC_CTRL_LAW_C ((fric_ctrl_law_t)2)

/* Where fric_ctrl_step_fn evaluates the friction model: the measured velocity v (the paper),
 * the virtual control v_d = xd' + k1 e1 (keeps compensating while the axis sticks), or the
 * reference velocity xd' (free of the sensor's noise: a stateful model does not hunt at rest). */
typedef int32_t fric_ctrl_friction_at_t;
#define FRIC_CTRL_FRICTION_AT_V ((fric_ctrl_friction_at_t)0)
#define FRIC_CTRL_FRICTION_AT_VD ((fric_ctrl_friction_at_t)1)
#define FRIC_CTRL_FRICTION_AT_REF ((fric_ctrl_friction_at_t)2)

/* What a step returns: 0 (FRIC_CTRL_STEP_OK) or an OR of the flags below. One family with
 * fric_adapt.h's FRIC_ADAPT_* flags: a bit means one thing in every flags word of the runtime
 * (1, 2 and 8 are both headers'; fric_adapt_ctrl_step returns the OR of its controller's flags
 * and its update's). */
typedef unsigned int fric_ctrl_flags_t;
#define FRIC_CTRL_STEP_OK 0u
#define FRIC_CTRL_FAULT_NULL 1u   /* c or current is NULL: nothing written */
#define FRIC_CTRL_INPUT_FAULT 2u  /* an input not finite, or a NaN demand: current 0 A, no update */
#define FRIC_CTRL_SATURATED 4u    /* the demand was beyond +-i_max: current +-i_max, no update */
#define FRIC_CTRL_PROJECTED 8u    /* an estimate was held at an end of its interval */

/* Friction compensation model: force in newtons at velocity v (m/s). */
typedef float (*fric_ctrl_friction_fn)(float v);

typedef struct {
    float k1;           /* position gain, 1/s, > 0 */
    float k2;           /* velocity gain, A s/m, > 1/2 [C16] */
    float gamma[4];     /* Gamma, row-major 2x2, symmetric positive definite */
    float delta;        /* leakage of laws b, c, >= 0 */
    float ts;           /* sampling time, s, > 0 */
    float phi_n;        /* nominal force constant, N/A, > 0 */
    float i_max;        /* current limit, A, > 0 */
    float m_o_hat0;     /* initial m_o_hat = m / phi, kg A / N, in [m_o_min, m_o_max] */
    float k_hat0;       /* initial k_hat (1: trust the friction model), in [k_min, k_max] */
    float m_o_min;      /* interval of m_o_hat, m_o_min < m_o_max */
    float m_o_max;
    float k_min;        /* interval of k_hat, k_min < k_max */
    float k_max;
    fric_ctrl_law_t law;                  /* FRIC_CTRL_LAW_A, _B or _C */
    fric_ctrl_friction_at_t friction_at;  /* FRIC_CTRL_FRICTION_AT_V, _AT_VD or _AT_REF
                                             (fric_ctrl_step_fn only) */
} fric_ctrl_params_t;

typedef struct {
    fric_ctrl_params_t p;     /* copy of the parameters */
    float m_o_hat;            /* adaptive parameters A = [m_o_hat, k_hat] */
    float k_hat;
    float e1;                 /* last tracking error xd - x, m (of the last fault-free step) */
    float e2;                 /* last velocity error v_d - v, m/s (likewise) */
    float i;                  /* last current command, A (after the limit) */
    fric_ctrl_flags_t flags;  /* what the last step returned */
} fric_ctrl_t;

/* One sample's measurements and reference, for the _sample steps (units as fric_ctrl_step's). */
typedef struct {
    float x;        /* measured position, m (rad) */
    float v;        /* measured velocity, m/s */
    float xd;       /* reference position, m */
    float xd_dot;   /* its first derivative, m/s */
    float xd_ddot;  /* its second derivative, m/s^2 */
} fric_ctrl_sample_t;

/**
 * @brief fricgen's defaults for a 2 kg linear motor axis with phi ~ 20 N/A at ts = 1 ms.
 *
 * k1 = 80, k2 = 40, Gamma = diag(1, 20), delta = 0.005, phi_n = 20, i_max = 10, A0 = [0.1, 1],
 * law c, friction at v; the estimates within a factor 10 of A0: m_o_hat in [0.01, 1] kg A/N,
 * k_hat in [0, 10] (0: no compensation). Set ts, phi_n and i_max to your loop's.
 * @param[out] p the parameters to fill; NULL is ignored.
 * Reentrant; no errno; call before the control ISR starts.
 */
void fric_ctrl_default_params(fric_ctrl_params_t *p);

/**
 * @brief Check the parameters and reset the controller: A = A0, errors, current and flags 0.
 * @param[out] c the controller, untouched unless FRIC_CTRL_OK is returned.
 * @param[in] p the parameters, copied into c (ranges: fric_ctrl_params_t's comments).
 * @return FRIC_CTRL_OK, FRIC_CTRL_ERR_NULL (c or p NULL) or FRIC_CTRL_ERR_PARAM (a parameter
 *         out of range or not finite).
 * Reentrant on distinct structs; no errno; call before the ISR starts or with it masked.
 */
fric_ctrl_status_t fric_ctrl_init(fric_ctrl_t *c, const fric_ctrl_params_t *p);

/**
 * @brief One sample of the adaptive backstepping controller, [C3]-[C14].
 * @param[in,out] c the controller (fric_ctrl_init first).
 * @param[in] x measured position, m (rad for a rotary axis; every unit below likewise).
 * @param[in] v measured velocity, m/s.
 * @param[in] xd, xd_dot, xd_ddot the reference and its first two derivatives, m, m/s, m/s^2.
 * @param[in] friction the friction compensation force, N (0 for none).
 * @param[out] current the current command, A, within +-i_max; 0 A on an input fault.
 * @return FRIC_CTRL_STEP_OK or an OR of FRIC_CTRL_FAULT_NULL (c or current NULL: nothing
 *         written), FRIC_CTRL_INPUT_FAULT (an input not finite or a NaN demand: 0 A, no
 *         update), FRIC_CTRL_SATURATED (the demand beyond +-i_max: +-i_max, no update),
 *         FRIC_CTRL_PROJECTED (an estimate held at an end of its interval).
 * Any finite or non-finite input keeps the current within +-i_max and the estimates within
 * their intervals. Reentrant on distinct structs; no errno; call from one context (the ISR).
 */
fric_ctrl_flags_t fric_ctrl_step(fric_ctrl_t *c, float x, float v, float xd, float xd_dot,
                                 float xd_ddot, float friction, float *current);

/**
 * @brief Where the friction model is evaluated (p.friction_at): v, v_d = xd' + k1 (xd - x)
 *        ([C3]) or xd'.
 * @param[in] c the controller (fric_ctrl_init first; not NULL).
 * @param[in] x, v, xd, xd_dot as fric_ctrl_step's (m, m/s, m, m/s).
 * @return the velocity, m/s (not finite where its inputs are not).
 * Contract (bounds, reentrancy, context): fric_ctrl_step's.
 */
float fric_ctrl_friction_velocity(const fric_ctrl_t *c, float x, float v, float xd, float xd_dot);

/**
 * @brief As fric_ctrl_step, the force taken from the model at fric_ctrl_friction_velocity:
 *        friction(v), friction(v_d) or friction(xd').
 * @param[in,out] c the controller (fric_ctrl_init first).
 * @param[in] x, v, xd, xd_dot, xd_ddot as fric_ctrl_step's (m, m/s, m, m/s, m/s^2).
 * @param[in] friction the model (NAME_force), or NULL for no compensation; it is not called
 *            at a non-finite velocity (the force is then 0).
 * @param[out] current the current command, A, within +-i_max.
 * @return fric_ctrl_step's flags. Contract (bounds, reentrancy, context): fric_ctrl_step's.
 */
fric_ctrl_flags_t fric_ctrl_step_fn(fric_ctrl_t *c, float x, float v, float xd, float xd_dot,
                                    float xd_ddot, fric_ctrl_friction_fn friction,
                                    float *current);

/**
 * @brief fric_ctrl_step_fn with the sample's five values in one struct.
 * @param[in,out] c the controller (fric_ctrl_init first).
 * @param[in] s the measurements and reference; NULL: FRIC_CTRL_FAULT_NULL, nothing written.
 * @param[in] friction the model (NAME_force), or NULL for no compensation.
 * @param[out] current the current command, A, within +-i_max.
 * @return fric_ctrl_step_fn's flags; bit for bit fric_ctrl_step_fn with s's five values, and
 *         its contract.
 */
fric_ctrl_flags_t fric_ctrl_step_sample(fric_ctrl_t *c, const fric_ctrl_sample_t *s,
                                        fric_ctrl_friction_fn friction, float *current);

#ifdef __cplusplus
}
#endif

#endif /* FRIC_CTRL_H */
