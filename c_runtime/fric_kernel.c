/* fricgen C runtime: hidden-layer kernels of the Extreme Learning Machine, eq. (7)-(8). */
#include "fric_kernel.h"

#include <math.h>

#define FRIC_ELM_KERNEL(NAME, ACT)                                                     \
    float NAME(const float *w, const float *b, const float *beta, size_t n, float x) \
    {                                                                                \
        float acc = 0.0f;                                                            \
        size_t k;                                                                    \
        for (k = 0; k < n; ++k) {                                                    \
            const float z = w[k] * x + b[k];                                         \
            acc += beta[k] * (ACT);                                                  \
        }                                                                            \
        return acc;                                                                  \
    }

float fric_exp_neg_f32(float a)
{
    const float c = a > FRIC_EXP_ARG_MAX ? FRIC_EXP_ARG_MAX
                  : (a < -FRIC_EXP_ARG_MAX ? -FRIC_EXP_ARG_MAX : a); /* NaN stays NaN */
    return expf(-c);
}

/* eq. (8): 1 / (1 + exp(-z)), the exponential's argument clamped (z < -87 gives 1.6e-38). */
FRIC_ELM_KERNEL(fric_elm_sigmoid_f32, 1.0f / (1.0f + fric_exp_neg_f32(z)))
FRIC_ELM_KERNEL(fric_elm_sine_f32, sinf(z))
FRIC_ELM_KERNEL(fric_elm_rbf_f32, fric_exp_neg_f32(z * z))
FRIC_ELM_KERNEL(fric_elm_multiquadric_f32, sqrtf(1.0f + z * z))
