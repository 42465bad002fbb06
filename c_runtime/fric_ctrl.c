/* fricgen C runtime: adaptive backstepping position control, section 6 (see fric_ctrl.h).
 * Every operation is a float operation in a fixed order; fricgen.control.AdaptiveBackstepping
 * with dtype="float32" mirrors it exactly. Part of fricgen; copied by `fricgen emit`.
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#include "fric_float.h" /* first: float semantics independent of the compiler's flags */

#include "fric_ctrl.h"
#include "fric_sqrt.h"   /* no libm: the controller links without it */

#include <math.h>     /* isfinite, isnan: macros, no libm call */
#include <stddef.h>

void fric_ctrl_default_params(fric_ctrl_params_t *p)
{
    if (p == NULL) {
        return;
    }
    p->k1 = 80.0f;
    p->k2 = 40.0f;
    p->gamma[0] = 1.0f;
    p->gamma[1] = 0.0f;
    p->gamma[2] = 0.0f;
    p->gamma[3] = 20.0f;
    p->delta = 0.005f;
    p->ts = 0.001f;
    p->phi_n = 20.0f;
    p->i_max = 10.0f;
    p->m_o_hat0 = 0.1f;
    p->k_hat0 = 1.0f;
    p->m_o_min = 0.01f;
    p->m_o_max = 1.0f;
    p->k_min = 0.0f;
    p->k_max = 10.0f;
    p->law = FRIC_CTRL_LAW_C;
    p->friction_at = FRIC_CTRL_FRICTION_AT_V;
}

/* lo <= value <= hi (false for NaN) */
static int fric_ctrl_within(float value, float lo, float hi)
{
    return (value >= lo) && (value <= hi);
}

static int fric_ctrl_params_ok(const fric_ctrl_params_t *p)
{
    const float *g = p->gamma;
    size_t k;
    const float checked[] = {p->k1, p->k2, g[0], g[1], g[2], g[3], p->delta, p->ts, p->phi_n,
                             p->i_max, p->m_o_hat0, p->k_hat0, p->m_o_min, p->m_o_max,
                             p->k_min, p->k_max};
    for (k = 0u; k < ((sizeof checked) / (sizeof checked[0])); ++k) {
        if (!isfinite(checked[k])) {
            return 0;
        }
    }
    if (!(p->k1 > 0.0f) || !(p->k2 > 0.5f) || !(p->delta >= 0.0f) || !(p->ts > 0.0f)
        || !(p->phi_n > 0.0f) || !(p->i_max > 0.0f)) {
        return 0;
    }
    /* Gamma symmetric positive definite: g00 > 0 and det = g00 g11 - g01^2 > 0. The first test
     * is g[1] != g[2] for every input (NaN, -0 == +0) without an exact float comparison. */
    if (!((g[1] <= g[2]) && (g[1] >= g[2])) || !(g[0] > 0.0f) || !((g[0] * g[3]) > (g[1] * g[2]))) {
        return 0;
    }
    if (!(p->m_o_min < p->m_o_max) || !(p->k_min < p->k_max)
        || !fric_ctrl_within(p->m_o_hat0, p->m_o_min, p->m_o_max)
        || !fric_ctrl_within(p->k_hat0, p->k_min, p->k_max)) {
        return 0;
    }
    if ((p->law != FRIC_CTRL_LAW_A) && (p->law != FRIC_CTRL_LAW_B) && (p->law != FRIC_CTRL_LAW_C)) {
        return 0;
    }
    return (p->friction_at == FRIC_CTRL_FRICTION_AT_V) || (p->friction_at == FRIC_CTRL_FRICTION_AT_VD)
           || (p->friction_at == FRIC_CTRL_FRICTION_AT_REF);
}

fric_ctrl_status_t fric_ctrl_init(fric_ctrl_t *c, const fric_ctrl_params_t *p)
{
    if ((c == NULL) || (p == NULL)) {
        return FRIC_CTRL_ERR_NULL;
    }
    if (!fric_ctrl_params_ok(p)) {
        return FRIC_CTRL_ERR_PARAM;
    }
    c->p = *p;
    c->m_o_hat = p->m_o_hat0;
    c->k_hat = p->k_hat0;
    c->e1 = 0.0f;
    c->e2 = 0.0f;
    c->i = 0.0f;
    c->flags = FRIC_CTRL_STEP_OK;
    return FRIC_CTRL_OK;
}

/* The updated estimate a + da projected onto [lo, hi]; a NaN (inf - inf in da) keeps a. */
static float fric_ctrl_project(float a, float updated, float lo, float hi,
                               fric_ctrl_flags_t *flags)
{
    if (isnan(updated) != 0) {
        *flags |= FRIC_CTRL_PROJECTED;
        return a;
    }
    if (updated < lo) {
        *flags |= FRIC_CTRL_PROJECTED;
        return lo;
    }
    if (updated > hi) {
        *flags |= FRIC_CTRL_PROJECTED;
        return hi;
    }
    return updated;
}

static fric_ctrl_flags_t fric_ctrl_fault(fric_ctrl_t *c, float *current)
{
    c->i = 0.0f;
    c->flags = FRIC_CTRL_INPUT_FAULT;
    *current = 0.0f;
    return FRIC_CTRL_INPUT_FAULT;
}

fric_ctrl_flags_t fric_ctrl_step(fric_ctrl_t *c, float x, float v, float xd, float xd_dot,
                                 float xd_ddot, float friction, float *current)
{
    float k1;
    float a0;
    float a1;
    float e1;
    float vd;
    float e2;
    float vd_dot;
    float xi0;
    float xi1;
    float d_hat;
    float demand;
    float i;
    float sigma;
    float g_xi0;
    float g_xi1;
    float g_a0;
    float g_a1;
    const float *g;
    fric_ctrl_flags_t flags = FRIC_CTRL_STEP_OK;

    if ((c == NULL) || (current == NULL)) {
        return FRIC_CTRL_FAULT_NULL;
    }
    if (!isfinite(x) || !isfinite(v) || !isfinite(xd) || !isfinite(xd_dot) || !isfinite(xd_ddot)
        || !isfinite(friction)) {
        return fric_ctrl_fault(c, current);
    }
    k1 = c->p.k1;
    g = c->p.gamma;
    a0 = c->m_o_hat;
    a1 = c->k_hat;
    e1 = xd - x;
    vd = xd_dot + (k1 * e1);                     /* [C3] */
    e2 = vd - v;                                 /* [C5] */
    vd_dot = xd_ddot + (k1 * (e2 - (k1 * e1)));  /* [C7] */
    xi0 = vd_dot;                                /* [C10] */
    xi1 = friction / c->p.phi_n;
    d_hat = (a0 * xi0) + (a1 * xi1);             /* [C9] */
    demand = (d_hat + (c->p.k2 * e2)) + e1;      /* [C11] */
    if (isnan(demand) != 0) {                    /* inf - inf from huge finite inputs */
        return fric_ctrl_fault(c, current);
    }
    if (!(demand <= c->p.i_max)) {
        i = c->p.i_max;
        flags = FRIC_CTRL_SATURATED;
    } else if (!(demand >= -c->p.i_max)) {
        i = -c->p.i_max;
        flags = FRIC_CTRL_SATURATED;
    } else {
        i = demand;
    }
    if (flags == FRIC_CTRL_STEP_OK) {            /* adaptation frozen while saturated */
        if (c->p.law == FRIC_CTRL_LAW_A) {
            sigma = 0.0f;
        } else if (c->p.law == FRIC_CTRL_LAW_B) {
            sigma = c->p.delta;
        } else {
            sigma = c->p.delta * fric_sqrt_f32((e1 * e1) + (e2 * e2)); /* = sqrtf */
        }
        g_xi0 = (g[0] * xi0) + (g[1] * xi1);     /* [C14]: Gamma xi, Gamma A */
        g_xi1 = (g[2] * xi0) + (g[3] * xi1);
        g_a0 = (g[0] * a0) + (g[1] * a1);
        g_a1 = (g[2] * a0) + (g[3] * a1);
        c->m_o_hat = fric_ctrl_project(a0, a0 + (c->p.ts * ((e2 * g_xi0) - (sigma * g_a0))),
                                       c->p.m_o_min, c->p.m_o_max, &flags);
        c->k_hat = fric_ctrl_project(a1, a1 + (c->p.ts * ((e2 * g_xi1) - (sigma * g_a1))),
                                     c->p.k_min, c->p.k_max, &flags);
    }
    c->e1 = e1;
    c->e2 = e2;
    c->i = i;
    c->flags = flags;
    *current = i;
    return flags;
}

float fric_ctrl_friction_velocity(const fric_ctrl_t *c, float x, float v, float xd, float xd_dot)
{
    float u = v;
    if (c->p.friction_at == FRIC_CTRL_FRICTION_AT_VD) {
        u = xd_dot + (c->p.k1 * (xd - x));
    } else if (c->p.friction_at == FRIC_CTRL_FRICTION_AT_REF) {
        u = xd_dot;
    } else {
        /* the measured v */
    }
    return u;
}

fric_ctrl_flags_t fric_ctrl_step_fn(fric_ctrl_t *c, float x, float v, float xd, float xd_dot,
                                    float xd_ddot, fric_ctrl_friction_fn friction,
                                    float *current)
{
    float force = 0.0f;
    if ((c == NULL) || (current == NULL)) {
        return FRIC_CTRL_FAULT_NULL;
    }
    if (friction != NULL) {
        const float u = fric_ctrl_friction_velocity(c, x, v, xd, xd_dot);
        if (isfinite(u) != 0) {
            force = friction(u);
        }
    }
    return fric_ctrl_step(c, x, v, xd, xd_dot, xd_ddot, force, current);
}

fric_ctrl_flags_t fric_ctrl_step_sample(fric_ctrl_t *c, const fric_ctrl_sample_t *s,
                                        fric_ctrl_friction_fn friction, float *current)
{
    if (s == NULL) {
        return FRIC_CTRL_FAULT_NULL;
    }
    return fric_ctrl_step_fn(c, s->x, s->v, s->xd, s->xd_dot, s->xd_ddot, friction, current);
}
