/* fricgen C runtime: exp(-a) through libm's expf, argument clamped (fric_kernel.h).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#include "fric_kernel.h"

float fric_exp_neg_f32(float a)
{
    return fric_exp_neg_inline_f32(a);
}
