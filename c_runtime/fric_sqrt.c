/* fricgen C runtime: the correctly rounded square root without libm (fric_sqrt.h).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#include "fric_float.h" /* first: as every runtime source (integers only here) */
#include "fric_sqrt.h"

#include <stdint.h>

typedef union {
    float f;
    uint32_t u;
} fric_sqrt_bits;

float fric_sqrt_f32(float x)
{
    fric_sqrt_bits b;
    uint64_t rad;
    uint64_t rem;
    uint64_t root;
    uint64_t bit;
    uint32_t m;
    uint32_t shift;
    int e;
    int biased;
    b.f = x;
    if (((b.u & 0x7fffffffu) == 0u) || (b.u == 0x7f800000u) || ((b.u & 0x7fffffffu) > 0x7f800000u)) {
        return x;                               /* +-0, +inf, NaN */
    }
    if ((b.u & 0x80000000u) != 0u) {
        b.u = 0x7fc00000u;                      /* x < 0: the quiet NaN */
        return b.f;
    }
    e = (int)(b.u >> 23);                       /* x = m 2^(e - 150), m in [2^23, 2^24) */
    m = b.u & 0x007fffffu;
    if (e == 0) {                               /* subnormal: normalize m */
        e = 1;
        while ((m & 0x00800000u) == 0u) {
            m <<= 1;
            --e;
        }
    } else {
        m |= 0x00800000u;
    }
    e -= 150;
    /* rad = m 2^24 (e even) or m 2^23 (e odd): rad in [2^46, 2^48), its root in [2^23, 2^24) */
    if ((e % 2) != 0) {
        shift = 23u;
    } else {
        shift = 24u;
    }
    rad = (uint64_t)m << shift;
    e -= (int)shift;                            /* x = rad 2^e, e even */
    rem = rad;
    root = 0u;
    for (bit = (uint64_t)1 << 46; bit != 0u; bit >>= 2) {
        if (rem >= (root + bit)) {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
    }
    /* sqrt(rad) = root + f, 0 <= f < 1; f > 1/2 iff rem > root (never f = 1/2) */
    root += (rem > root) ? 1u : 0u;               /* 2^24 carries into the exponent below */
    biased = (e / 2) + 149;
    b.u = ((uint32_t)biased << 23) + (uint32_t)root;
    return b.f;
}
