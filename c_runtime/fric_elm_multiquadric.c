/* fricgen C runtime: the multiquadric kernel of the ELM, [F7], sqrt(1 + z^2) through libm's
 * sqrtf (fric_kernel.h).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#include "fric_kernel.h"

FRIC_ELM_KERNEL(fric_elm_multiquadric_f32, sqrtf(1.0f + (z * z)))
