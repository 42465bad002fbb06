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

/* eq. (8): 1 / (1 + exp(-z)); expf overflows to +inf for z < -88.7 and the quotient is 0. */
FRIC_ELM_KERNEL(fric_elm_sigmoid_f32, 1.0f / (1.0f + expf(-z)))
FRIC_ELM_KERNEL(fric_elm_sine_f32, sinf(z))
FRIC_ELM_KERNEL(fric_elm_rbf_f32, expf(-(z * z)))
FRIC_ELM_KERNEL(fric_elm_multiquadric_f32, sqrtf(1.0f + z * z))
