/* fricgen C runtime: the Gaussian RBF kernel of the ELM, [F7], exp(-z^2) through libm's expf
 * (fric_kernel.h).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#include "fric_kernel.h"

FRIC_ELM_KERNEL(fric_elm_rbf_f32, fric_exp_neg_inline_f32(z * z))
