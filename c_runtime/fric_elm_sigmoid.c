/* fricgen C runtime: the sigmoid kernel of the ELM, [F7]-[F8], through libm's expf (fric_kernel.h).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#include "fric_kernel.h"

/* [F8]: 1 / (1 + exp(-z)), the exponential's argument clamped (z < -87 gives 1.6e-38). */
FRIC_ELM_KERNEL(fric_elm_sigmoid_f32, 1.0f / (1.0f + fric_exp_neg_inline_f32(z)))
