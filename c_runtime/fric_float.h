/* fricgen C runtime: float semantics that do not depend on the compiler's flags.
 * Part of fricgen; copied by `fricgen emit` beside every float model. Every runtime file and
 * every generated NAME.c includes it (directly or through fric_kernel.h / fric_fast.h) before
 * its first function, so that every float operation of the runtime and of the model code is
 * rounded as written, which is what makes it bit-equal to its Python twin:
 * - -ffast-math and -ffinite-math-only are refused: they fold fric_fast.c's rounding trick
 *   (exp(-1) came out as 0.5) and drop the NaN checks the contracts rely on.
 * - Contraction of a * b + c into a fused multiply-add (GCC's default in its GNU modes, e.g.
 *   -std=gnu99; clang's default within one expression) is turned off for the rest of the
 *   translation unit. GCC ignores `#pragma STDC FP_CONTRACT` but honours
 *   `#pragma GCC optimize ("fp-contract=off")` for the functions defined after it (GCC 12,
 *   -std=gnu99 -O2 -mfma: 17 vfmadd in fric_fast.o without it, 0 with it, same code size).
 * - GCC's -funsafe-math-optimizations, -freciprocal-math and an effective -fassociative-math
 *   (which define __ASSOCIATIVE_MATH__ or __RECIPROCAL_MATH__) are refused: they reorder the
 *   sums and divisions the twin rounds as written (fm_force(-0.029) came out 28 % off).
 *   -fassociative-math alone GCC disables with a warning (signed zeros and trapping math take
 *   precedence) and defines no macro, yet a `#pragma GCC optimize` turned it back on for the
 *   functions after it (an ELM's force 62 % off, GCC 12): the pragma turns both off itself.
 * - Clang defines no macro for these flags; its file-scope pragmas below turn reassociation,
 *   reciprocal division and contraction off for the rest of the translation unit, whatever
 *   the command line says. Clang's -ffp-contract=fast ignores `fp contract(off)`; on x86,
 *   `STDC FENV_ACCESS ON` makes every operation a constrained one, which no flag fuses
 *   (clang 14, -O2 -mfma -ffp-contract=fast: 39 vfmadd in fric_adapt.o without it, 0 with
 *   it). Clang supports neither pragma on other targets and warns; there the emitted
 *   CMakeLists.txt adds -ffp-contract=off after the user's flags (clang 14 fuses under
 *   -ffp-contract=fast on AArch64 and RISC-V, not on the Cortex-M4F).
 * Include it from .c files only: the pragma applies to the rest of the including translation
 * unit (the public headers NAME.h and fric_ctrl.h do not include it).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#ifndef FRIC_FLOAT_H
#define FRIC_FLOAT_H

#if defined(__FAST_MATH__) || (defined(__FINITE_MATH_ONLY__) && (__FINITE_MATH_ONLY__ > 0))
#error "fricgen runtime: -ffast-math / -ffinite-math-only change its results; build it without them"
#endif
#if defined(__ASSOCIATIVE_MATH__) || defined(__RECIPROCAL_MATH__)
#error "fricgen runtime: -funsafe-math-optimizations / -fassociative-math / -freciprocal-math change its results; build it without them"
#endif
#if defined(__clang__)
#if defined(__x86_64__) || defined(__i386__)
#pragma float_control(precise, on)
#pragma STDC FENV_ACCESS ON
#endif
#pragma clang fp reassociate(off)
#pragma clang fp contract(off)
#elif defined(__GNUC__)
#pragma GCC optimize ("fp-contract=off", "no-associative-math", "no-reciprocal-math")
#else
#pragma STDC FP_CONTRACT OFF
#endif

#endif /* FRIC_FLOAT_H */
