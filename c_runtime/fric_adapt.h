/* fricgen C runtime: online adaptation of the friction model's linear output parameters, and the
 * adaptive backstepping step of section 6 (fric_ctrl.h) compensating with the adapted model.
 * Part of fricgen; copied by `fricgen emit --adapt`. C99, float only, no dynamic memory, no
 * global state: the caller owns a fric_adapt_t (and the fric_ctrl_t it drives).
 *
 * The model is F(v) = f0(v) + theta^T phi(v): `fricgen emit --adapt` generates the regressor
 * NAME_regressor (writes phi, returns f0) and NAME_adapt_default_params (theta0, the box and the
 * scales of the trained model). Two rules update theta (fricgen.control.adaptation):
 *   RLS with forgetting on the friction observed by inverse dynamics at the nominal force
 *   constant (not k_hat, which scales the compensation too: the two would run away together),
 *       y = phi_n (i_prev - m_o_hat (v - v_prev) / ts)  at  (v + v_prev) / 2,
 *   P's update computed on its upper triangle and mirrored, so that P stays symmetric in float;
 *   Lyapunov ([C14] extended to theta): theta += gain scale^2 e2 phi(v).
 * Safety, in this order: a non-finite input changes nothing (FRIC_ADAPT_INPUT_FAULT); hold != 0
 * (the controller saturated or faulted) changes nothing (FRIC_ADAPT_HELD); |v| > v_max changes
 * nothing (FRIC_ADAPT_OUT_OF_RANGE: the viscous feature v is unbounded); no update for
 * |v| < v_dead or |error| < e_dead (FRIC_ADAPT_DEAD_ZONE); the error clamped to +-e_max
 * (FRIC_ADAPT_CLAMPED: one update moves theta a bounded step, whatever finite input it gets);
 * RLS: sum_k P_kk / scale_k^2 is held at most trace_max (FRIC_ADAPT_TRACE_CLAMPED); leakage
 * theta_k -= leak (theta_k - theta0_k) for k < n_leak; each theta_k projected onto [lo_k, hi_k]
 * (FRIC_ADAPT_PROJECTED; a NaN update keeps theta_k). The force applied, fric_adapt_force, is
 * the trained model's plus the adapted correction sum_k (theta_k - theta0_k) phi_k saturated at
 * +-band (N): within the band around the trained model at every velocity, whatever the
 * parameters.
 *
 * Usage, every ts (after fric_ctrl_init(&c, ...) and NAME_adapt_default_params(&p),
 * fric_adapt_init(&a, &p)):
 *     flags = fric_adapt_ctrl_step(&a, &c, NAME_regressor, x, v, xd, xd_dot, xd_ddot, &i);
 * The float operations are those written here, in this order, each rounded to float;
 * fricgen.control.adaptation (dtype="float32") computes the same bits.
 * Calling contexts: no global or static variable is written and no errno is set, so every
 * function is reentrant on distinct structs. Update one struct from one context (the control
 * ISR); read it elsewhere (save, export, logging) from a copy taken with that interrupt masked;
 * init, reset and restore before the ISR starts or with it masked (docs/reference/c-api.md).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#ifndef FRIC_ADAPT_H
#define FRIC_ADAPT_H

#include "fric_ctrl.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The runtime's interface: 4 since the rule is an int32_t, 5 since fric_adapt_t holds settle,
 * fric_adapt_params_t n_leak and FRIC_ADAPT_MAX_PARAMS is 18, 6 since fric_adapt_params_t holds
 * hold_at_rest, 7 since the flags are one family with fric_ctrl.h's and fric_adapt_ctrl_step
 * returns both (the saved state's format, FRIC_ADAPT_STATE_FORMAT, is another number). */
#define FRIC_ADAPT_VERSION 7
/* The format of a saved state (fric_adapt_save): what a blob holds, not the structs' layout.
 * 4 holds the controller's k_hat and m_o_hat; fric_adapt_restore reads 3 (without them) too. */
#define FRIC_ADAPT_STATE_FORMAT 4u
/* The most parameters a fric_adapt_t holds (fricgen.control.adaptation.MAX_PARAMS). */
#define FRIC_ADAPT_MAX_PARAMS 18u

typedef enum {
    FRIC_ADAPT_OK_INIT = 0,
    FRIC_ADAPT_ERR_NULL = -1,
    FRIC_ADAPT_ERR_PARAM = -2,
    FRIC_ADAPT_ERR_SIZE = -3,      /* a saved state of another size than this adaptation's */
    FRIC_ADAPT_ERR_FOREIGN = -4,   /* a saved state of another format, version or model */
    FRIC_ADAPT_ERR_CHECKSUM = -5,  /* a saved state whose CRC-32 does not match */
    FRIC_ADAPT_ERR_RANGE = -6      /* a saved state with a value not finite or out of its box */
} fric_adapt_status_t;

/* The bytes of a saved state of n parameters (fric_adapt_save): "FRAS", FRIC_ADAPT_STATE_FORMAT and n
 * (16 bits each, little-endian), the model hash (16 bytes, NUL-padded), theta (n) and P (n x n)
 * as float bits (32 bits each, little-endian), whether a controller step recorded the next two
 * (0 or 1, 32 bits), the controller's k_hat and m_o_hat (float bits), then the CRC-32 (IEEE
 * 802.3) of all before it. */
#define FRIC_ADAPT_STATE_SIZE(n) (40u + (4u * (n)) + (4u * (n) * (n)))
/* fric_adapt_t.held after a restore of a state with k_hat and m_o_hat: the next
 * fric_adapt_ctrl_step gives the controller those (each within its interval) before its step. */
#define FRIC_ADAPT_RESUMED 2
/* How long fric_adapt_ctrl_step holds the updates driven by e2 after the axis leaves the dead
 * zone |v| < v_dead, in time constants 1 / k1 of the position error (e1' = -k1 e1 + e2): while
 * the axis sticks at a reversal the reference runs on, and the error it catches up afterwards
 * is the stick's, not a model's. Adapting on it biased k_hat F by +4.4 % and m_o_hat by +150 %
 * on the built-in axis (benchmarks/adaptation_readback.py). */
#define FRIC_ADAPT_SETTLE 3.0f
/* The longest model hash a saved state holds. */
#define FRIC_ADAPT_HASH_MAX 16u

/* The update rule (int32_t with typed constants, not an enum: fric_ctrl.h says why). */
typedef int32_t fric_adapt_rule_t;
#define FRIC_ADAPT_RULE_RLS ((fric_adapt_rule_t)0)
#define FRIC_ADAPT_RULE_LYAPUNOV ((fric_adapt_rule_t)1)

/* What an update returns: 0 or an OR of these. One family with fric_ctrl.h's FRIC_CTRL_* flags:
 * a bit means one thing in every flags word (FRIC_CTRL_SATURATED's 4 is no update's), so that
 * fric_adapt_ctrl_step returns the OR of the two, one word to test. */
typedef unsigned int fric_adapt_flags_t;
#define FRIC_ADAPT_OK 0u
#define FRIC_ADAPT_FAULT_NULL 1u      /* a NULL pointer: nothing written (FRIC_CTRL_FAULT_NULL) */
#define FRIC_ADAPT_INPUT_FAULT 2u     /* an input not finite: no update (FRIC_CTRL_INPUT_FAULT) */
#define FRIC_ADAPT_PROJECTED 8u       /* a parameter was held at an end of its interval
                                         (FRIC_CTRL_PROJECTED) */
#define FRIC_ADAPT_HELD 16u           /* hold was set: no update */
#define FRIC_ADAPT_DEAD_ZONE 32u      /* |v| < v_dead or |error| < e_dead: no update */
#define FRIC_ADAPT_TRACE_CLAMPED 64u  /* P was scaled down to the trace bound */
#define FRIC_ADAPT_CLAMPED 128u       /* the error was clamped to +-e_max */
#define FRIC_ADAPT_COVARIANCE_RESET 256u  /* RLS: P lost definiteness and was reset */
#define FRIC_ADAPT_OUT_OF_RANGE 512u  /* |v| > v_max: no update */
/* Of the family, 1 and 2 say an input was refused; the others report what a step or an update
 * did with valid inputs (a nonzero word is no fault by itself). */

/* The regressor: writes phi[0 .. n-1] at the finite velocity v (m/s), returns f0(v) (N). */
typedef float (*fric_adapt_regressor_fn)(float v, float *phi);

typedef struct {
    unsigned int n;                          /* parameters, 1 .. FRIC_ADAPT_MAX_PARAMS */
    fric_adapt_rule_t rule;                  /* FRIC_ADAPT_RULE_RLS or _LYAPUNOV */
    unsigned int n_leak;                     /* the leakage acts on theta[0 .. n_leak - 1], <= n;
                                                the rest (the axis's offset) does not leak */
    unsigned int hold_at_rest;               /* 1 (the default): fric_adapt_ctrl_step holds the
                                                e2-driven estimates while the axis sticks and
                                                settles; 0: they adapt through every stick */
    float theta0[FRIC_ADAPT_MAX_PARAMS];     /* trained values */
    float lo[FRIC_ADAPT_MAX_PARAMS];         /* box, lo <= theta0 <= hi */
    float hi[FRIC_ADAPT_MAX_PARAMS];
    float scale[FRIC_ADAPT_MAX_PARAMS];      /* > 0: P0 = p0 scale^2, Gamma = gain scale^2 */
    float forgetting;                        /* RLS lambda, in (0, 1] */
    float p0;                                /* > 0 */
    float trace_max;                         /* >= p0 n */
    float gain;                              /* Lyapunov: ts gamma / phi_n, >= 0 */
    float leak;                              /* in [0, 1) */
    float v_dead;                            /* m/s, >= 0 */
    float e_dead;                            /* N (RLS) or m/s (Lyapunov), >= 0 */
    float e_max;                             /* the error's clamp, same unit, > 0 */
    float band;                              /* N, > 0: |F - F_trained| <= band */
    float v_max;                             /* m/s, > 0: no update beyond */
} fric_adapt_params_t;

typedef struct {
    fric_adapt_params_t p;                   /* copy of the parameters */
    float theta[FRIC_ADAPT_MAX_PARAMS];      /* the adapted parameters */
    float P[FRIC_ADAPT_MAX_PARAMS * FRIC_ADAPT_MAX_PARAMS];  /* covariance, row-major n x n */
    float scale2[FRIC_ADAPT_MAX_PARAMS];     /* scale^2 */
    float error;                             /* last error (N, RLS) or e2 (Lyapunov) */
    float v_prev;                            /* fric_adapt_ctrl_step's last v and current */
    float i_prev;
    float k_hat;                             /* the controller's k_hat at the last step (1 before) */
    float m_o_hat;                           /* ... and its m_o_hat (0 before) */
    int held;                                /* the last controller step saturated or faulted
                                                (FRIC_ADAPT_RESUMED: a state was restored) */
    int recorded;                            /* 1 once a controller step recorded k_hat, m_o_hat */
    float settle;                            /* s left of the hold after the dead zone (not saved) */
    fric_adapt_flags_t flags;                /* what the last update returned */
} fric_adapt_t;

/**
 * @brief Check p and reset a (fric_adapt_reset).
 * @param[out] a the adaptation, untouched unless FRIC_ADAPT_OK_INIT is returned.
 * @param[in] p its parameters (NAME_adapt_default_params fills them), copied into a.
 * @return FRIC_ADAPT_OK_INIT, FRIC_ADAPT_ERR_NULL or FRIC_ADAPT_ERR_PARAM (a field out of the
 *         range its comment in fric_adapt_params_t gives, or not finite).
 * Reentrant on distinct structs; no errno; call before the control ISR starts.
 */
fric_adapt_status_t fric_adapt_init(fric_adapt_t *a, const fric_adapt_params_t *p);

/**
 * @brief theta = theta0, P = p0 diag(scale^2), error and flags 0, held (no RLS update before
 *        the first controller step).
 * @param[in,out] a the adaptation; NULL is ignored.
 */
void fric_adapt_reset(fric_adapt_t *a);

/**
 * @brief The adapted force F(v), N: f0 + sum_k theta0_k phi_k + sat_band(sum_k (theta_k -
 *        theta0_k) phi_k), k ascending: within +-band of the trained model at every v.
 * @param[in] a the adaptation; @param[in] reg the model's regressor (NAME_regressor);
 * @param[in] v velocity, m/s (rad/s).
 * @return the force, N (Nm); 0 at a non-finite v or for a NULL argument.
 */
float fric_adapt_force(const fric_adapt_t *a, fric_adapt_regressor_fn reg, float v);

/**
 * @brief One RLS update on the friction force observed at velocity v.
 * @param[in,out] a the adaptation (rule FRIC_ADAPT_RULE_RLS).
 * @param[in] reg the regressor; @param[in] v velocity, m/s; @param[in] force observed, N.
 * @param[in] hold non-zero: no update (the controller saturated or faulted).
 * @return FRIC_ADAPT_OK or an OR of the FRIC_ADAPT_* flags (also in a->flags). Any input moves
 *         theta by a bounded step and keeps it in [lo, hi]. Reentrant on distinct structs.
 */
fric_adapt_flags_t fric_adapt_rls(fric_adapt_t *a, fric_adapt_regressor_fn reg, float v,
                                  float force, int hold);

/**
 * @brief One Lyapunov update with the controller's velocity error e2 at velocity v.
 * @param[in,out] a the adaptation (rule FRIC_ADAPT_RULE_LYAPUNOV).
 * @param[in] reg the regressor; @param[in] v velocity, m/s; @param[in] e2 v_d - v, m/s.
 * @param[in] hold non-zero: no update.
 * @return as fric_adapt_rls.
 */
fric_adapt_flags_t fric_adapt_lyapunov(fric_adapt_t *a, fric_adapt_regressor_fn reg, float v,
                                       float e2, int hold);

/**
 * @brief One sample of the controller c compensating with the adapted model.
 *
 * F at v or v_d (c->p.friction_at), fric_ctrl_step, then the RLS update on the friction
 * observed over the last sample (held unless this step and the last were fault-free and
 * unsaturated) or the Lyapunov update with its e2 (held unless this step was fault-free and
 * unsaturated); records c's k_hat in a->k_hat (for fric_adapt_export). The updates driven by
 * e2, the controller's m_o_hat and k_hat [C14] and Lyapunov's theta, are held while
 * |v| < v_dead and for FRIC_ADAPT_SETTLE / k1 seconds after (c keeps the estimates it had
 * before the step, without FRIC_CTRL_PROJECTED; theta's update returns FRIC_ADAPT_HELD after
 * the dead zone): the velocity error of a stick and of the catch-up after it is no model's.
 * @param[in,out] a the adaptation; @param[in,out] c the controller; @param[in] reg the regressor.
 * @param[in] x, v, xd, xd_dot, xd_ddot as fric_ctrl_step's; @param[out] current the command, A.
 * @return fric_ctrl_step's flags OR the update's (one family: FRIC_CTRL_SATURATED with
 *         FRIC_ADAPT_HELD, say; a->flags holds the update's alone). Call from one context (the
 *         control ISR); on a Cortex-M4F the ISR saves the FPU context (lazy stacking).
 * Cost beyond fric_ctrl_step_fn with the fixed model, for an ELM of M sigmoid units whose
 * theta ends with the axis's offset (benchmarks/adaptation_cost.py under QEMU,
 * arm-none-eabi-gcc -O2, newlib; fricgen.codegen.cost): Cortex-M4F, Lyapunov about 254 + 140 M
 * instructions with libm (254 + 115 M with --activation-impl fast), RLS about 450 + 232 M +
 * 10.8 M^2; at M = 10 on the soft-float Cortex-M0+ Lyapunov 47,223 (libm) and 36,084 (fast),
 * RLS 133,831 and 122,930; a grey-box model of 3 sources 747 (M4F, libm) and 16,122 (M0+).
 */
fric_ctrl_flags_t fric_adapt_ctrl_step(fric_adapt_t *a, fric_ctrl_t *c, fric_adapt_regressor_fn reg,
                                       float x, float v, float xd, float xd_dot, float xd_ddot,
                                       float *current);

/**
 * @brief fric_adapt_ctrl_step with the sample's five values in one struct.
 * @param[in,out] a the adaptation; @param[in,out] c the controller; @param[in] reg the regressor.
 * @param[in] s the measurements and reference; NULL: FRIC_CTRL_FAULT_NULL, nothing written.
 * @param[out] current the current command, A.
 * @return fric_adapt_ctrl_step's flags; bit for bit fric_adapt_ctrl_step with s's five values,
 *         and its contract.
 */
fric_ctrl_flags_t fric_adapt_ctrl_step_sample(fric_adapt_t *a, fric_ctrl_t *c,
                                              fric_adapt_regressor_fn reg,
                                              const fric_ctrl_sample_t *s, float *current);

/**
 * @brief Save what a has learned (theta, P, and the controller's k_hat and m_o_hat at the last
 *        step, where a step recorded them) into buf, for non-volatile memory.
 * @param[in] a the adaptation (a copy taken with the control ISR masked).
 * @param[in] model_hash NAME_ADAPT_MODEL_HASH, at most FRIC_ADAPT_HASH_MAX characters.
 * @param[out] buf at least FRIC_ADAPT_STATE_SIZE(a->p.n) bytes; @param[in] size its size.
 * @return the bytes written, FRIC_ADAPT_STATE_SIZE(a->p.n), or 0 (nothing written) for a NULL
 *         argument, a longer hash or a buf too small. No float arithmetic, no libc.
 */
unsigned int fric_adapt_save(const fric_adapt_t *a, const char *model_hash, unsigned char *buf,
                             unsigned int size);

/**
 * @brief Restore a state fric_adapt_save wrote, at boot after fric_adapt_init.
 * @param[in,out] a the adaptation; @param[in] model_hash NAME_ADAPT_MODEL_HASH;
 * @param[in] buf, size the saved bytes.
 * @return FRIC_ADAPT_OK_INIT, or (a untouched) FRIC_ADAPT_ERR_NULL, _ERR_PARAM, _ERR_SIZE
 *         (not the size of this adaptation's state: another number of parameters, or cut
 *         short), _ERR_FOREIGN (another format or model), _ERR_CHECKSUM, _ERR_RANGE (theta
 *         outside [lo, hi], a value not finite, a covariance diagonal below 0). The next
 *         controller step (fric_adapt_ctrl_step) gives the controller the saved k_hat and
 *         m_o_hat, each within its interval (a state saved before any controller step, or of
 *         format 3, has none: the controller's initial values stay), and does no RLS update
 *         (no last sample).
 */
fric_adapt_status_t fric_adapt_restore(fric_adapt_t *a, const char *model_hash,
                                       const unsigned char *buf, unsigned int size);

/**
 * @brief The adapted friction as text, for `fricgen readback`.
 *
 * Four lines, each ending in '\n', NUL-terminated:
 *     fricgen-adapt-dump 2
 *     model <model_hash>                      (NAME_ADAPT_MODEL_HASH)
 *     theta <8 hex digits> ... <8 hex digits> (the float bits of theta[0 .. n-1])
 *     scale <8 hex digits>                    (the float bits of k_hat)
 * The loop applies k_hat F(v): k_hat scales the compensation and trades against theta (their
 * product is what the data determine), so the dump carries both and readback's model is the
 * friction the loop applies.
 * @param[in] a the adaptation; @param[in] model_hash NAME_ADAPT_MODEL_HASH;
 * @param[out] buf the text; @param[in] size its size: 50 + the hash's length + 9 n suffice.
 * @return the characters written without the NUL, or 0 (buf then holds "" if size > 0) for a
 *         NULL argument or a buf too small. No libc formatting, no float arithmetic.
 */
unsigned int fric_adapt_export(const fric_adapt_t *a, const char *model_hash, char *buf,
                               unsigned int size);

#ifdef __cplusplus
}
#endif

#endif /* FRIC_ADAPT_H */
