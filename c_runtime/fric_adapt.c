/* fricgen C runtime: online adaptation of the friction model's output parameters (fric_adapt.h).
 * Every operation is a float operation in a fixed order; fricgen.control.adaptation with
 * dtype="float32" mirrors it exactly. Part of fricgen; copied by `fricgen emit --adapt`.
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#include "fric_float.h"   /* first: no -ffast-math, no contraction (as fric_ctrl.c) */
#include "fric_adapt.h"
#include "fric_bytes.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

static int fric_adapt_params_ok(const fric_adapt_params_t *p)
{
    unsigned int k;
    const float scalars[] = {p->forgetting, p->p0, p->trace_max, p->gain, p->leak, p->v_dead,
                             p->e_dead, p->e_max, p->band, p->v_max};
    if ((p->n < 1u) || (p->n > FRIC_ADAPT_MAX_PARAMS) || (p->n_leak > p->n)
        || (p->hold_at_rest > 1u)) {
        return 0;
    }
    if ((p->rule != FRIC_ADAPT_RULE_RLS) && (p->rule != FRIC_ADAPT_RULE_LYAPUNOV)) {
        return 0;
    }
    for (k = 0; k < (unsigned int)((sizeof scalars) / (sizeof scalars[0])); ++k) {
        if (!isfinite(scalars[k])) {
            return 0;
        }
    }
    for (k = 0; k < p->n; ++k) {
        if (!isfinite(p->theta0[k]) || !isfinite(p->lo[k]) || !isfinite(p->hi[k])
            || !(p->lo[k] <= p->theta0[k]) || !(p->theta0[k] <= p->hi[k])
            || !(p->scale[k] > 0.0f) || !isfinite(p->scale[k] * p->scale[k])) {
            return 0;
        }
    }
    return (p->forgetting > 0.0f) && (p->forgetting <= 1.0f) && (p->p0 > 0.0f)
           && (p->trace_max >= (p->p0 * (float)p->n)) && (p->gain >= 0.0f) && (p->leak >= 0.0f)
           && (p->leak < 1.0f) && (p->v_dead >= 0.0f) && (p->e_dead >= 0.0f) && (p->e_max > 0.0f)
           && (p->band > 0.0f) && (p->v_max > 0.0f);
}

static void fric_adapt_reset_covariance(fric_adapt_t *a)
{
    const unsigned int n = a->p.n;
    unsigned int i;
    unsigned int j;
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j) {
            a->P[(i * n) + j] = (i == j) ? (a->p.p0 * a->scale2[i]) : 0.0f;
        }
    }
}

void fric_adapt_reset(fric_adapt_t *a)
{
    unsigned int k;
    if (a == NULL) {
        return;
    }
    for (k = 0; k < FRIC_ADAPT_MAX_PARAMS; ++k) {   /* beyond n: 0 */
        a->theta[k] = (k < a->p.n) ? a->p.theta0[k] : 0.0f;
        a->scale2[k] = (k < a->p.n) ? (a->p.scale[k] * a->p.scale[k]) : 0.0f;
    }
    for (k = 0; k < (FRIC_ADAPT_MAX_PARAMS * FRIC_ADAPT_MAX_PARAMS); ++k) {
        a->P[k] = 0.0f;
    }
    fric_adapt_reset_covariance(a);
    a->error = 0.0f;
    a->v_prev = 0.0f;
    a->i_prev = 0.0f;
    a->k_hat = 1.0f;
    a->m_o_hat = 0.0f;
    a->held = 1;
    a->recorded = 0;
    a->settle = 0.0f;
    a->flags = FRIC_ADAPT_OK;
}

fric_adapt_status_t fric_adapt_init(fric_adapt_t *a, const fric_adapt_params_t *p)
{
    if ((a == NULL) || (p == NULL)) {
        return FRIC_ADAPT_ERR_NULL;
    }
    if (!fric_adapt_params_ok(p)) {
        return FRIC_ADAPT_ERR_PARAM;
    }
    a->p = *p;
    fric_adapt_reset(a);
    return FRIC_ADAPT_OK_INIT;
}

/* f0 + sum_k theta_k phi_k, k ascending; phi written */
static float fric_adapt_predict(const fric_adapt_t *a, fric_adapt_regressor_fn reg, float v,
                                float *phi)
{
    float acc = reg(v, phi);
    unsigned int k;
    for (k = 0; k < a->p.n; ++k) {
        acc += a->theta[k] * phi[k];
    }
    return acc;
}

float fric_adapt_force(const fric_adapt_t *a, fric_adapt_regressor_fn reg, float v)
{
    float phi[FRIC_ADAPT_MAX_PARAMS];
    float trained;
    float delta = 0.0f;
    unsigned int k;
    if ((a == NULL) || (reg == NULL) || !isfinite(v)) {
        return 0.0f;
    }
    trained = reg(v, phi);
    for (k = 0; k < a->p.n; ++k) {
        trained += a->p.theta0[k] * phi[k];
        delta += (a->theta[k] - a->p.theta0[k]) * phi[k];
    }
    if (delta > a->p.band) {
        delta = a->p.band;
    } else if (delta < -a->p.band) {
        delta = -a->p.band;
    } else {
        /* within the band */
    }
    return trained + delta;
}

static fric_adapt_flags_t fric_adapt_done(fric_adapt_t *a, fric_adapt_flags_t flags)
{
    a->flags = flags;
    return flags;
}

/* leakage toward theta0 (of the first n_leak), then projection onto [lo, hi] (NaN keeps theta) */
static fric_adapt_flags_t fric_adapt_finish(fric_adapt_t *a, const float *updated,
                                            fric_adapt_flags_t flags)
{
    unsigned int k;
    fric_adapt_flags_t out = flags;
    for (k = 0; k < a->p.n; ++k) {
        const float u = (k < a->p.n_leak) ? (updated[k] - (a->p.leak * (updated[k] - a->p.theta0[k])))
                                          : updated[k];
        if (isnan(u) != 0) {
            out |= FRIC_ADAPT_PROJECTED;
        } else if (u < a->p.lo[k]) {
            a->theta[k] = a->p.lo[k];
            out |= FRIC_ADAPT_PROJECTED;
        } else if (u > a->p.hi[k]) {
            a->theta[k] = a->p.hi[k];
            out |= FRIC_ADAPT_PROJECTED;
        } else {
            a->theta[k] = u;
        }
    }
    return fric_adapt_done(a, out);
}

/* e clamped to +-e_max; FRIC_ADAPT_CLAMPED added to *flags when it was */
static float fric_adapt_clamp(const fric_adapt_t *a, float e, fric_adapt_flags_t *flags)
{
    if (e > a->p.e_max) {
        *flags |= FRIC_ADAPT_CLAMPED;
        return a->p.e_max;
    }
    if (e < -a->p.e_max) {
        *flags |= FRIC_ADAPT_CLAMPED;
        return -a->p.e_max;
    }
    return e;
}

/* Whether an update stops at its inputs (fricgen.control.adaptation's _gate): v or the rule's
 * input x not finite, hold, or |v| > v_max; then *flags holds the finished update's flags. */
static int fric_adapt_stops(fric_adapt_t *a, float v, float x, int hold, fric_adapt_flags_t *flags)
{
    if (!isfinite(v) || !isfinite(x)) {
        *flags = fric_adapt_done(a, FRIC_ADAPT_INPUT_FAULT);
        return 1;
    }
    if (hold != 0) {
        *flags = fric_adapt_done(a, FRIC_ADAPT_HELD);
        return 1;
    }
    if (fabsf(v) > a->p.v_max) {
        *flags = fric_adapt_done(a, FRIC_ADAPT_OUT_OF_RANGE);
        return 1;
    }
    return 0;
}

fric_adapt_flags_t fric_adapt_rls(fric_adapt_t *a, fric_adapt_regressor_fn reg, float v,
                                  float force, int hold)
{
    float phi[FRIC_ADAPT_MAX_PARAMS];
    float p_phi[FRIC_ADAPT_MAX_PARAMS];
    float g[FRIC_ADAPT_MAX_PARAMS];
    float updated[FRIC_ADAPT_MAX_PARAMS];
    float err;
    float step;
    float denom;
    float trace;
    float lam;
    unsigned int i;
    unsigned int k;
    unsigned int n;
    fric_adapt_flags_t flags = FRIC_ADAPT_OK;

    if ((a == NULL) || (reg == NULL)) {
        return FRIC_ADAPT_FAULT_NULL;
    }
    if (fric_adapt_stops(a, v, force, hold, &flags) != 0) {
        return flags;
    }
    n = a->p.n;
    lam = a->p.forgetting;
    err = force - fric_adapt_predict(a, reg, v, phi);
    a->error = err;
    if (!((fabsf(v) >= a->p.v_dead) && (fabsf(err) >= a->p.e_dead))) {
        return fric_adapt_done(a, FRIC_ADAPT_DEAD_ZONE);
    }
    step = fric_adapt_clamp(a, err, &flags);
    for (i = 0; i < n; ++i) {                    /* P phi, each row in k order */
        float acc = 0.0f;
        for (k = 0; k < n; ++k) {
            acc += a->P[(i * n) + k] * phi[k];
        }
        p_phi[i] = acc;
    }
    denom = lam;
    for (k = 0; k < n; ++k) {
        denom += phi[k] * p_phi[k];
    }
    if (!isfinite(denom) || !(denom > 0.0f)) {   /* P lost definiteness: start it again */
        fric_adapt_reset_covariance(a);
        return fric_adapt_done(a, FRIC_ADAPT_COVARIANCE_RESET);
    }
    for (i = 0; i < n; ++i) {
        g[i] = p_phi[i] / denom;
        updated[i] = a->theta[i] + (g[i] * step);
    }
    for (i = 0; i < n; ++i) {                    /* the upper triangle, mirrored: P stays */
        for (k = i; k < n; ++k) {                /* symmetric in float, whatever the rounding */
            const float pik = (a->P[(i * n) + k] - (g[i] * p_phi[k])) / lam;
            a->P[(i * n) + k] = pik;
            a->P[(k * n) + i] = pik;
        }
    }
    trace = 0.0f;
    for (k = 0; k < n; ++k) {
        trace += a->P[(k * n) + k] / a->scale2[k];
    }
    if (!(trace <= a->p.trace_max)) {            /* also NaN */
        const float s = a->p.trace_max / trace;
        for (k = 0; k < (n * n); ++k) {
            a->P[k] = a->P[k] * s;
        }
        flags |= FRIC_ADAPT_TRACE_CLAMPED;
    }
    return fric_adapt_finish(a, updated, flags);
}

fric_adapt_flags_t fric_adapt_lyapunov(fric_adapt_t *a, fric_adapt_regressor_fn reg, float v,
                                       float e2, int hold)
{
    float phi[FRIC_ADAPT_MAX_PARAMS];
    float updated[FRIC_ADAPT_MAX_PARAMS];
    float step;
    unsigned int k;
    fric_adapt_flags_t flags = FRIC_ADAPT_OK;

    if ((a == NULL) || (reg == NULL)) {
        return FRIC_ADAPT_FAULT_NULL;
    }
    if (fric_adapt_stops(a, v, e2, hold, &flags) != 0) {
        return flags;
    }
    a->error = e2;
    if (!((fabsf(v) >= a->p.v_dead) && (fabsf(e2) >= a->p.e_dead))) {
        return fric_adapt_done(a, FRIC_ADAPT_DEAD_ZONE);
    }
    step = fric_adapt_clamp(a, e2, &flags);
    (void)reg(v, phi);
    for (k = 0; k < a->p.n; ++k) {
        updated[k] = a->theta[k] + (((a->p.gain * a->scale2[k]) * step) * phi[k]);
    }
    return fric_adapt_finish(a, updated, flags);
}

fric_ctrl_flags_t fric_adapt_ctrl_step(fric_adapt_t *a, fric_ctrl_t *c, fric_adapt_regressor_fn reg,
                                       float x, float v, float xd, float xd_dot, float xd_ddot,
                                       float *current)
{
    fric_ctrl_flags_t flags;
    float u;
    float force;
    float m_o_hat;
    float k_hat;
    int held;
    int resting;
    int settling;

    if ((a == NULL) || (c == NULL) || (reg == NULL) || (current == NULL)) {
        return FRIC_CTRL_FAULT_NULL;
    }
    if (a->held == FRIC_ADAPT_RESUMED) {   /* restored: the controller resumes k_hat, m_o_hat */
        c->k_hat = (a->k_hat < c->p.k_min) ? c->p.k_min
                                            : ((a->k_hat > c->p.k_max) ? c->p.k_max : a->k_hat);
        c->m_o_hat = (a->m_o_hat < c->p.m_o_min) ? c->p.m_o_min
                                                  : ((a->m_o_hat > c->p.m_o_max) ? c->p.m_o_max
                                                                                 : a->m_o_hat);
    }
    /* at rest (or a non-finite v), and settling for FRIC_ADAPT_SETTLE / k1 s after it */
    resting = 1;
    settling = 0;
    if (fabsf(v) >= a->p.v_dead) {
        resting = 0;
        if (a->settle > 0.0f) {
            a->settle = a->settle - c->p.ts;
            settling = (a->settle > 0.0f) ? 1 : settling;
        }
    } else {
        a->settle = FRIC_ADAPT_SETTLE / c->p.k1;
    }
    if (a->p.hold_at_rest == 0u) {           /* the estimates adapt through every stick */
        resting = 0;
        settling = 0;
    }
    m_o_hat = c->m_o_hat;
    k_hat = c->k_hat;
    u = fric_ctrl_friction_velocity(c, x, v, xd, xd_dot);
    force = fric_adapt_force(a, reg, u);
    flags = fric_ctrl_step(c, x, v, xd, xd_dot, xd_ddot, force, current);
    if ((flags & (FRIC_CTRL_SATURATED | FRIC_CTRL_INPUT_FAULT)) != 0u) {
        held = 1;
    } else {
        held = 0;
    }
    if ((resting != 0) || (settling != 0)) {     /* the stick's error: A as it was */
        c->m_o_hat = m_o_hat;
        c->k_hat = k_hat;
        flags = flags & ~FRIC_CTRL_PROJECTED;
        c->flags = flags;
    }
    if ((a->p.rule == FRIC_ADAPT_RULE_RLS) && ((a->held != 0) || (held != 0))) {
        /* held: the observation spans this step's or the last one's fault or saturation (a
         * glitch's v_prev), so it is not formed; this step's own inputs are still checked */
        (void)fric_adapt_rls(a, reg, v, 0.0f, 1);
    } else if (a->p.rule == FRIC_ADAPT_RULE_RLS) {
        const float accel = (v - a->v_prev) / c->p.ts;
        const float observed = c->p.phi_n * (a->i_prev - (c->m_o_hat * accel));
        const float v_mid = 0.5f * (v + a->v_prev);
        (void)fric_adapt_rls(a, reg, v_mid, observed, 0);
    } else {
        (void)fric_adapt_lyapunov(a, reg, v, c->e2, ((held != 0) || (settling != 0)) ? 1 : 0);
    }
    a->v_prev = v;
    a->i_prev = *current;
    a->k_hat = c->k_hat;
    a->m_o_hat = c->m_o_hat;
    a->recorded = 1;
    a->held = held;
    return flags | a->flags;
}

/* Appends text to buf at *len if it fits below size - 1 (room for the NUL); 0 if not. */
static int fric_adapt_put(char *buf, unsigned int size, unsigned int *len, const char *text)
{
    unsigned int k = 0u;
    int ok = 1;
    while ((ok != 0) && (text[k] != '\0')) {
        if ((*len + 1u) >= size) {
            ok = 0;
        } else {
            buf[*len] = text[k];
            *len = *len + 1u;
            k = k + 1u;
        }
    }
    return ok;
}

unsigned int fric_adapt_export(const fric_adapt_t *a, const char *model_hash, char *buf,
                               unsigned int size)
{
    static const char hex[] = "0123456789abcdef";
    unsigned int len = 0u;
    unsigned int k;
    unsigned int n;
    char word[10];
    int ok;

    if ((a == NULL) || (model_hash == NULL) || (buf == NULL) || (size == 0u)) {
        return 0u;
    }
    n = (a->p.n <= (unsigned int)FRIC_ADAPT_MAX_PARAMS) ? a->p.n : 0u;
    ok = fric_adapt_put(buf, size, &len, "fricgen-adapt-dump 2\nmodel ");
    ok = (ok != 0) ? fric_adapt_put(buf, size, &len, model_hash) : 0;
    ok = (ok != 0) ? fric_adapt_put(buf, size, &len, "\ntheta") : 0;
    for (k = 0u; (ok != 0) && (k <= n); ++k) {
        const uint32_t bits = fric_float_bits((k < n) ? a->theta[k] : a->k_hat);
        unsigned int d;
        word[0] = ' ';
        for (d = 0u; d < 8u; ++d) {
            word[1u + d] = hex[(bits >> (28u - (4u * d))) & 0xFu];
        }
        word[9] = '\0';
        if ((k == n) && (ok != 0)) {
            ok = fric_adapt_put(buf, size, &len, "\nscale");
        }
        ok = (ok != 0) ? fric_adapt_put(buf, size, &len, word) : 0;
    }
    ok = (ok != 0) ? fric_adapt_put(buf, size, &len, "\n") : 0;
    if (ok == 0) {
        len = 0u;
    }
    buf[len] = '\0';
    return len;
}


/* ---------------------------------------------------------------- saved state */

fric_ctrl_flags_t fric_adapt_ctrl_step_sample(fric_adapt_t *a, fric_ctrl_t *c,
                                              fric_adapt_regressor_fn reg,
                                              const fric_ctrl_sample_t *s, float *current)
{
    if (s == NULL) {
        return FRIC_CTRL_FAULT_NULL;
    }
    return fric_adapt_ctrl_step(a, c, reg, s->x, s->v, s->xd, s->xd_dot, s->xd_ddot, current);
}

/* The length of model_hash if at most FRIC_ADAPT_HASH_MAX, else FRIC_ADAPT_HASH_MAX + 1. */
static unsigned int fric_adapt_hash_length(const char *model_hash)
{
    unsigned int k = 0u;
    while ((k <= FRIC_ADAPT_HASH_MAX) && (model_hash[k] != '\0')) {
        k = k + 1u;
    }
    return k;
}

/* The 24 bytes before theta: "FRAS", the format, n and the NUL-padded hash. */
static void fric_adapt_state_head(unsigned char *head, unsigned int format, unsigned int n,
                                  const char *model_hash)
{
    const unsigned int length = fric_adapt_hash_length(model_hash);
    unsigned int k;
    head[0] = (unsigned char)'F';
    head[1] = (unsigned char)'R';
    head[2] = (unsigned char)'A';
    head[3] = (unsigned char)'S';
    head[4] = (unsigned char)(format & 0xFFu);
    head[5] = (unsigned char)((format >> 8) & 0xFFu);
    head[6] = (unsigned char)(n & 0xFFu);
    head[7] = (unsigned char)((n >> 8) & 0xFFu);
    for (k = 0u; k < FRIC_ADAPT_HASH_MAX; ++k) {
        head[8u + k] = (k < length) ? (unsigned char)model_hash[k] : 0u;
    }
}

unsigned int fric_adapt_save(const fric_adapt_t *a, const char *model_hash, unsigned char *buf,
                             unsigned int size)
{
    unsigned int n;
    unsigned int total;
    unsigned int k;
    unsigned char *at;
    if ((a == NULL) || (model_hash == NULL) || (buf == NULL)) {
        return 0u;
    }
    n = a->p.n;
    if ((n < 1u) || (n > FRIC_ADAPT_MAX_PARAMS)
        || (fric_adapt_hash_length(model_hash) > FRIC_ADAPT_HASH_MAX)) {
        return 0u;
    }
    total = FRIC_ADAPT_STATE_SIZE(n);
    if (size < total) {
        return 0u;
    }
    fric_adapt_state_head(buf, FRIC_ADAPT_STATE_FORMAT, n, model_hash);
    at = &buf[24];
    for (k = 0u; k < n; ++k) {
        fric_put_u32(at, fric_float_bits(a->theta[k]));
        at = &at[4];
    }
    for (k = 0u; k < (n * n); ++k) {
        fric_put_u32(at, fric_float_bits(a->P[k]));
        at = &at[4];
    }
    fric_put_u32(at, (a->recorded != 0) ? 1u : 0u);
    at = &at[4];
    fric_put_u32(at, fric_float_bits(a->k_hat));
    at = &at[4];
    fric_put_u32(at, fric_float_bits(a->m_o_hat));
    at = &at[4];
    fric_put_u32(at, fric_crc32(buf, total - 4u));
    return total;
}

fric_adapt_status_t fric_adapt_restore(fric_adapt_t *a, const char *model_hash,
                                       const unsigned char *buf, unsigned int size)
{
    unsigned char head[24];
    float theta[FRIC_ADAPT_MAX_PARAMS];
    float k_hat = 0.0f;
    float m_o_hat = 0.0f;
    uint32_t recorded = 0u;
    const unsigned char *covariance;
    unsigned int n;
    unsigned int total;
    unsigned int format;
    unsigned int k;
    const unsigned char *at;
    if ((a == NULL) || (model_hash == NULL) || (buf == NULL)) {
        return FRIC_ADAPT_ERR_NULL;
    }
    n = a->p.n;
    if ((n < 1u) || (n > FRIC_ADAPT_MAX_PARAMS)
        || (fric_adapt_hash_length(model_hash) > FRIC_ADAPT_HASH_MAX)) {
        return FRIC_ADAPT_ERR_PARAM;
    }
    total = FRIC_ADAPT_STATE_SIZE(n);
    format = FRIC_ADAPT_STATE_FORMAT;
    if (size == (total - 12u)) {                     /* format 3: saved without k_hat */
        total = total - 12u;
        format = 3u;
    }
    if (size != total) {
        return FRIC_ADAPT_ERR_SIZE;
    }
    fric_adapt_state_head(head, format, n, model_hash);
    for (k = 0u; k < 24u; ++k) {
        if (head[k] != buf[k]) {
            return FRIC_ADAPT_ERR_FOREIGN;
        }
    }
    if (fric_crc32(buf, total - 4u) != fric_get_u32(&buf[total - 4u])) {
        return FRIC_ADAPT_ERR_CHECKSUM;
    }
    at = &buf[24];
    for (k = 0u; k < n; ++k) {
        theta[k] = fric_bits_float(fric_get_u32(at));
        if (!isfinite(theta[k]) || !(theta[k] >= a->p.lo[k]) || !(theta[k] <= a->p.hi[k])) {
            return FRIC_ADAPT_ERR_RANGE;
        }
        at = &at[4];
    }
    covariance = at;
    for (k = 0u; k < (n * n); ++k) {                 /* checked first: a untouched if not */
        float entry = fric_bits_float(fric_get_u32(at));
        if (!isfinite(entry) || (((k % (n + 1u)) == 0u) && !(entry >= 0.0f))) {
            return FRIC_ADAPT_ERR_RANGE;             /* a covariance's diagonal is >= 0 */
        }
        at = &at[4];
    }
    if (format == FRIC_ADAPT_STATE_FORMAT) {
        recorded = fric_get_u32(at);
        k_hat = fric_bits_float(fric_get_u32(&at[4]));
        m_o_hat = fric_bits_float(fric_get_u32(&at[8]));
        if ((recorded > 1u) || !isfinite(k_hat) || !isfinite(m_o_hat)) {
            return FRIC_ADAPT_ERR_RANGE;
        }
    }
    for (k = 0u; k < n; ++k) {
        a->theta[k] = theta[k];
    }
    for (k = 0u; k < (n * n); ++k) {
        a->P[k] = fric_bits_float(fric_get_u32(covariance));
        covariance = &covariance[4];
    }
    if (recorded == 1u) {
        a->k_hat = k_hat;
        a->m_o_hat = m_o_hat;
        a->recorded = 1;
        a->held = FRIC_ADAPT_RESUMED;                /* the next step gives c k_hat, m_o_hat */
    } else {
        a->held = 1;
    }
    return FRIC_ADAPT_OK_INIT;
}
