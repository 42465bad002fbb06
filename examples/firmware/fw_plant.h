/* A small float32 plant for closed-loop runs of the fricgen controller on the emulated MCU:
 * the linear axis x' = v, m v' = phi i - F(v) with the current limited to [-i_max, i_max],
 * integrated by semi-implicit Euler (v first, then x with the new v) in `substeps` steps per
 * controller sample. The friction is rational (no libm call), so every operation is a basic
 * IEEE float operation that fricgen.firmware.Float32Plant mirrors exactly:
 *   F(v) = (f_c + (f_s - f_c) v_s^2 / (v_s^2 + v^2)) v / (|v| + v_eps) + viscous v
 * (Coulomb level f_c, Stribeck peak f_s near v = 0 over the scale v_s, smoothed through zero
 * over v_eps, plus viscous friction). */
#ifndef FW_PLANT_H
#define FW_PLANT_H

#include "fric_ctrl.h"

typedef struct {
    float mass;     /* kg */
    float phi;      /* force constant, N/A */
    float i_max;    /* current limit, A */
    float f_c;      /* Coulomb level, N */
    float f_s;      /* Stribeck peak, N */
    float v_s;      /* Stribeck velocity, m/s */
    float v_eps;    /* smoothing of the sign through zero, m/s */
    float viscous;  /* N s/m */
    int substeps;   /* Euler steps per controller sample, >= 1 */
} fw_plant_params_t;

typedef struct {
    float x;  /* m */
    float v;  /* m/s */
} fw_plant_t;

float fw_plant_friction(const fw_plant_params_t *p, float v);

/* Advance the state over ts seconds with the current i held. */
void fw_plant_advance(fw_plant_t *s, const fw_plant_params_t *p, float i, float ts);

/* The most values fw_print_row prints on one line. */
#define FW_ROW_MAX 16u

/* Prints one line: the two characters of tag, then " " and the 8 hex digits of the bits of
 * each of the n values (at most FW_ROW_MAX). */
void fw_print_row(const char *tag, const float *values, unsigned n);

/* A closed-loop run: n samples of the reference xd, xd', xd'' (arrays of n floats). */
typedef struct {
    fw_plant_params_t plant;
    fric_ctrl_params_t ctrl;
    fric_ctrl_friction_fn friction;  /* compensation, e.g. an emitted model's NAME_force */
    unsigned n;
    const float *xd;
    const float *xd_dot;
    const float *xd_ddot;
} fw_loop_t;

/* Run the loop from rest at x = 0 and print, for each sample k, one line
 * "cl X V I M K": the hex bits of x_k, v_k (measured), the current i_k and the adaptive
 * parameters m_o_hat, k_hat after the step. Prints "cl init-failed" if the controller
 * rejects its parameters. Returns 0 on success. */
int fw_closed_loop_run(const fw_loop_t *loop);

#endif /* FW_PLANT_H */
