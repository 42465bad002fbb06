/* Closed-loop run of the fricgen controller against a small float32 plant (see fw_plant.h). */
#include "fw_plant.h"

#include <stdint.h>

#include "semihost.h"

float fw_plant_friction(const fw_plant_params_t *p, float v)
{
    const float speed = v < 0.0f ? -v : v;
    const float vs2 = p->v_s * p->v_s;
    const float level = p->f_c + (p->f_s - p->f_c) * (vs2 / (vs2 + v * v));
    return level * (v / (speed + p->v_eps)) + p->viscous * v;
}

void fw_plant_advance(fw_plant_t *s, const fw_plant_params_t *p, float i, float ts)
{
    const float h = ts / (float)p->substeps;
    float thrust;
    int k;
    if (i > p->i_max) {
        i = p->i_max;
    } else if (i < -p->i_max) {
        i = -p->i_max;
    }
    thrust = p->phi * i;
    for (k = 0; k < p->substeps; ++k) {
        const float a = (thrust - fw_plant_friction(p, s->v)) / p->mass;
        s->v = s->v + h * a;
        s->x = s->x + h * s->v;
    }
}

void fw_print_row(const char *tag, const float *values, unsigned n)
{
    char line[2 + FW_ROW_MAX * 9 + 2];
    char *p = line;
    unsigned j;
    int d;
    *p++ = tag[0];
    *p++ = tag[1];
    for (j = 0u; (j < n) && (j < FW_ROW_MAX); ++j) {
        union {
            float f;
            uint32_t u;
        } c;
        c.f = values[j];
        *p++ = ' ';
        for (d = 7; d >= 0; --d) {
            p[d] = "0123456789abcdef"[c.u & 0xfu];
            c.u >>= 4;
        }
        p += 8;
    }
    *p++ = '\n';
    *p = '\0';
    sh_write0(line);
}

int fw_closed_loop_run(const fw_loop_t *loop)
{
    fric_ctrl_t ctrl;
    fw_plant_t s;
    unsigned k;
    if (fric_ctrl_init(&ctrl, &loop->ctrl) != FRIC_CTRL_OK) {
        sh_write0("cl init-failed\n");
        return 1;
    }
    s.x = 0.0f;
    s.v = 0.0f;
    for (k = 0; k < loop->n; ++k) {
        float i = 0.0f;
        float row[5];
        (void)fric_ctrl_step_fn(&ctrl, s.x, s.v, loop->xd[k], loop->xd_dot[k], loop->xd_ddot[k],
                                loop->friction, &i);
        row[0] = s.x;
        row[1] = s.v;
        row[2] = i;
        row[3] = ctrl.m_o_hat;
        row[4] = ctrl.k_hat;
        fw_print_row("cl", row, 5u);
        fw_plant_advance(&s, &loop->plant, i, loop->ctrl.ts);
    }
    return 0;
}
