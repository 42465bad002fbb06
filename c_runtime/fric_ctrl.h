/* fricgen C runtime: adaptive backstepping position control with friction compensation
 * (section 6 of the multisource ELM friction paper). Part of fricgen; copied by `fricgen emit`.
 * C99, float only, no dynamic memory, no global state: the caller owns a fric_ctrl_t.
 *
 * Per sample (every ts seconds), with e1 = xd - x:
 *   v_d   = xd' + k1 e1                    e2 = v_d - v
 *   v_d'  = xd'' + k1 (e2 - k1 e1)         xi = [v_d', F_Fm / phi_n]
 *   i     = m_o_hat xi0 + k_hat xi1 + k2 e2 + e1, limited to [-i_max, i_max]
 *   A    += ts (e2 Gamma xi - sigma Gamma A),  A = [m_o_hat, k_hat], sigma = 0 (law a),
 *           delta (law b), delta sqrt(e1^2 + e2^2) (law c)
 * F_Fm is the friction compensation force in newtons, e.g. an emitted model's NAME_force.
 *
 * Usage:
 *   fric_ctrl_params_t p; fric_ctrl_t c;
 *   fric_ctrl_default_params(&p);  p.ts = 1e-3f;  ...
 *   if (fric_ctrl_init(&c, &p) != FRIC_CTRL_OK) { ... bad parameters ... }
 *   every ts:  i = fric_ctrl_step_fn(&c, x, v, xd, xd_dot, xd_ddot, NAME_force);
 * or, with the force computed elsewhere:
 *              i = fric_ctrl_step(&c, x, v, xd, xd_dot, xd_ddot, NAME_force(v));
 * Units: m, m/s, m/s^2, s, N, A. The returned current is to be held until the next sample.
 * Finite inputs give a current within [-i_max, i_max]; a NaN input makes the current and the
 * adaptive parameters NaN (check the inputs, or call fric_ctrl_init again to recover). */
#ifndef FRIC_CTRL_H
#define FRIC_CTRL_H

#ifdef __cplusplus
extern "C" {
#endif

#define FRIC_CTRL_VERSION 2

/* fricgen.control.c_abi mirrors the enums and structs below (fricgen's tests check that both
 * agree). The enums' size is the compiler's choice: int on most hosts, the smallest that fits
 * under arm-none-eabi-gcc (-fshort-enums is the AAPCS default there), so build the runtime and
 * its callers with the same compiler settings. */

/* Return codes of fric_ctrl_init. */
typedef enum {
    FRIC_CTRL_OK = 0,
    FRIC_CTRL_ERR_NULL = -1,  /* a NULL pointer */
    FRIC_CTRL_ERR_PARAM = -2  /* a parameter out of range (see fric_ctrl_params_t) */
} fric_ctrl_status_t;

/* Adaptation laws of eq. (12) a, b, c. */
typedef enum {
    FRIC_CTRL_LAW_A = 0,
    FRIC_CTRL_LAW_B = 1,
    FRIC_CTRL_LAW_C = 2
} fric_ctrl_law_t;

/* Where fric_ctrl_step_fn evaluates the friction model: the measured velocity v (the paper),
 * or the virtual control v_d = xd' + k1 e1 (keeps compensating while the axis sticks). */
typedef enum {
    FRIC_CTRL_FRICTION_AT_V = 0,
    FRIC_CTRL_FRICTION_AT_VD = 1
} fric_ctrl_friction_at_t;

/* Friction compensation model: force in newtons at velocity v (m/s). */
typedef float (*fric_ctrl_friction_fn)(float v);

typedef struct {
    float k1;           /* position gain, 1/s, > 0 */
    float k2;           /* velocity gain, A s/m, > 1/2 (eq. 14) */
    float gamma[4];     /* Gamma, row-major 2x2, symmetric positive definite */
    float delta;        /* leakage of laws b, c, >= 0 */
    float ts;           /* sampling time, s, > 0 */
    float phi_n;        /* nominal force constant, N/A, > 0 */
    float i_max;        /* current limit, A, > 0 */
    float m_o_hat0;     /* initial m_o_hat = m / phi, kg A / N */
    float k_hat0;       /* initial k_hat (1: trust the friction model) */
    fric_ctrl_law_t law;                  /* FRIC_CTRL_LAW_A, _B or _C */
    fric_ctrl_friction_at_t friction_at;  /* FRIC_CTRL_FRICTION_AT_V or _AT_VD
                                             (fric_ctrl_step_fn only) */
} fric_ctrl_params_t;

typedef struct {
    fric_ctrl_params_t p;  /* copy of the parameters */
    float m_o_hat;         /* adaptive parameters A = [m_o_hat, k_hat] */
    float k_hat;
    float e1;              /* last tracking error xd - x, m */
    float e2;              /* last velocity error v_d - v, m/s */
    float i;               /* last current command, A (after the limit) */
} fric_ctrl_t;

/* fricgen's defaults for a 2 kg linear motor axis with phi ~ 20 N/A at ts = 1 ms:
 * k1 = 80, k2 = 40, Gamma = diag(1, 20), delta = 0.005, phi_n = 20, i_max = 10,
 * A0 = [0.1, 1], law c, friction at v. */
void fric_ctrl_default_params(fric_ctrl_params_t *p);

/* Check the parameters and reset the controller (A = A0, errors and current 0).
 * Returns FRIC_CTRL_OK, FRIC_CTRL_ERR_NULL or FRIC_CTRL_ERR_PARAM (c is then untouched). */
fric_ctrl_status_t fric_ctrl_init(fric_ctrl_t *c, const fric_ctrl_params_t *p);

/* One sample: measured position x and velocity v, reference xd, xd', xd'', and the friction
 * compensation force friction (N; 0 for none). Returns the current command (A) and updates
 * the adaptive parameters. */
float fric_ctrl_step(fric_ctrl_t *c, float x, float v, float xd, float xd_dot, float xd_ddot,
                     float friction);

/* As fric_ctrl_step, the force taken from friction(v) or friction(v_d) (p.friction_at);
 * friction may be NULL (no compensation). */
float fric_ctrl_step_fn(fric_ctrl_t *c, float x, float v, float xd, float xd_dot, float xd_ddot,
                        fric_ctrl_friction_fn friction);

#ifdef __cplusplus
}
#endif

#endif /* FRIC_CTRL_H */
