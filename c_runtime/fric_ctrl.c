/* fricgen C runtime: adaptive backstepping position control, section 6 (see fric_ctrl.h).
 * Every operation is a float operation in a fixed order; fricgen.control.AdaptiveBackstepping
 * with dtype="float32" mirrors it exactly. Part of fricgen; copied by `fricgen emit`. */
#include "fric_ctrl.h"

#include <math.h>
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
    p->law = FRIC_CTRL_LAW_C;
    p->friction_at = FRIC_CTRL_FRICTION_AT_V;
}

static int fric_ctrl_params_ok(const fric_ctrl_params_t *p)
{
    const float *g = p->gamma;
    int k;
    const float checked[] = {p->k1, p->k2, g[0], g[1], g[2], g[3], p->delta, p->ts, p->phi_n,
                             p->i_max, p->m_o_hat0, p->k_hat0};
    for (k = 0; k < (int)(sizeof checked / sizeof checked[0]); ++k) {
        if (!isfinite(checked[k])) {
            return 0;
        }
    }
    if (!(p->k1 > 0.0f) || !(p->k2 > 0.5f) || !(p->delta >= 0.0f) || !(p->ts > 0.0f)
        || !(p->phi_n > 0.0f) || !(p->i_max > 0.0f)) {
        return 0;
    }
    /* Gamma symmetric positive definite: g00 > 0 and det = g00 g11 - g01^2 > 0 */
    if (g[1] != g[2] || !(g[0] > 0.0f) || !(g[0] * g[3] > g[1] * g[2])) {
        return 0;
    }
    if (p->law != FRIC_CTRL_LAW_A && p->law != FRIC_CTRL_LAW_B && p->law != FRIC_CTRL_LAW_C) {
        return 0;
    }
    return p->friction_at == FRIC_CTRL_FRICTION_AT_V || p->friction_at == FRIC_CTRL_FRICTION_AT_VD;
}

fric_ctrl_status_t fric_ctrl_init(fric_ctrl_t *c, const fric_ctrl_params_t *p)
{
    if (c == NULL || p == NULL) {
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
    return FRIC_CTRL_OK;
}

float fric_ctrl_step(fric_ctrl_t *c, float x, float v, float xd, float xd_dot, float xd_ddot,
                     float friction)
{
    const float k1 = c->p.k1;
    const float *g = c->p.gamma;
    const float a0 = c->m_o_hat;
    const float a1 = c->k_hat;
    const float e1 = xd - x;
    const float vd = xd_dot + k1 * e1;                     /* eq. (3) */
    const float e2 = vd - v;                               /* eq. (5) */
    const float vd_dot = xd_ddot + k1 * (e2 - k1 * e1);   /* eq. (7) */
    const float xi0 = vd_dot;                              /* eq. (10) */
    const float xi1 = friction / c->p.phi_n;
    const float d_hat = a0 * xi0 + a1 * xi1;               /* eq. (9) */
    float i = d_hat + c->p.k2 * e2 + e1;                   /* eq. (28) */
    float sigma;
    float g_xi0, g_xi1, g_a0, g_a1;

    if (i > c->p.i_max) {
        i = c->p.i_max;
    } else if (i < -c->p.i_max) {
        i = -c->p.i_max;
    }
    if (c->p.law == FRIC_CTRL_LAW_A) {
        sigma = 0.0f;
    } else if (c->p.law == FRIC_CTRL_LAW_B) {
        sigma = c->p.delta;
    } else {
        sigma = c->p.delta * sqrtf(e1 * e1 + e2 * e2);
    }
    g_xi0 = g[0] * xi0 + g[1] * xi1;                       /* eq. (12): Gamma xi, Gamma A */
    g_xi1 = g[2] * xi0 + g[3] * xi1;
    g_a0 = g[0] * a0 + g[1] * a1;
    g_a1 = g[2] * a0 + g[3] * a1;
    c->m_o_hat = a0 + c->p.ts * (e2 * g_xi0 - sigma * g_a0);
    c->k_hat = a1 + c->p.ts * (e2 * g_xi1 - sigma * g_a1);
    c->e1 = e1;
    c->e2 = e2;
    c->i = i;
    return i;
}

float fric_ctrl_step_fn(fric_ctrl_t *c, float x, float v, float xd, float xd_dot, float xd_ddot,
                        fric_ctrl_friction_fn friction)
{
    float force = 0.0f;
    if (friction != NULL) {
        const float u = c->p.friction_at == FRIC_CTRL_FRICTION_AT_VD
                            ? xd_dot + c->p.k1 * (xd - x) : v;
        force = friction(u);
    }
    return fric_ctrl_step(c, x, v, xd, xd_dot, xd_ddot, force);
}
