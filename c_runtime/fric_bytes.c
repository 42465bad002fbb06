/* fricgen C runtime: the bytes of a saved blob (fric_bytes.h).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#include "fric_float.h" /* first: as every runtime source (integers only here) */
#include "fric_bytes.h"

typedef union {
    float f;
    uint32_t u;
} fric_bytes_pun;

uint32_t fric_crc32(const unsigned char *bytes, unsigned int count)
{
    uint32_t crc = 0xFFFFFFFFu;
    unsigned int k;
    unsigned int bit;
    for (k = 0u; k < count; ++k) {
        crc ^= (uint32_t)bytes[k];
        for (bit = 0u; bit < 8u; ++bit) {
            crc = ((crc & 1u) != 0u) ? ((crc >> 1) ^ 0xEDB88320u) : (crc >> 1);
        }
    }
    return crc ^ 0xFFFFFFFFu;
}

void fric_put_u32(unsigned char *at, uint32_t value)
{
    at[0] = (unsigned char)(value & 0xFFu);
    at[1] = (unsigned char)((value >> 8) & 0xFFu);
    at[2] = (unsigned char)((value >> 16) & 0xFFu);
    at[3] = (unsigned char)((value >> 24) & 0xFFu);
}

uint32_t fric_get_u32(const unsigned char *at)
{
    return (uint32_t)at[0] | ((uint32_t)at[1] << 8) | ((uint32_t)at[2] << 16) | ((uint32_t)at[3] << 24);
}

uint32_t fric_float_bits(float f)
{
    fric_bytes_pun pun;
    pun.f = f;
    return pun.u;
}

float fric_bits_float(uint32_t u)
{
    fric_bytes_pun pun;
    pun.u = u;
    return pun.f;
}
