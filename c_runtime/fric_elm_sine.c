/* fricgen C runtime: the sine kernel of the ELM, [F7], through libm's sinf (fric_kernel.h).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#include "fric_kernel.h"

FRIC_ELM_KERNEL(fric_elm_sine_f32, sinf(z))
