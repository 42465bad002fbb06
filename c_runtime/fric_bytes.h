/* fricgen C runtime: the bytes of a saved blob, the same on every target: CRC-32 and
 * little-endian 32-bit words (a float as its IEEE bits). C99, no float library call, no dynamic
 * memory, no global state. Part of fricgen; copied by `fricgen emit --adapt` (fric_adapt_save)
 * and by `fricgen emit` of a model with a cogging map (NAME_cogging_map_save).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#ifndef FRIC_BYTES_H
#define FRIC_BYTES_H

#include <stdint.h>

#include "fric_version.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief The CRC-32 of IEEE 802.3 (reflected polynomial 0xEDB88320, as zlib's crc32).
 * @param[in] bytes the bytes, not NULL when count > 0.
 * @param[in] count how many.
 * @return the CRC-32 of bytes[0 .. count - 1].
 */
uint32_t fric_crc32(const unsigned char *bytes, unsigned int count);

/**
 * @brief Writes value at at[0 .. 3], least significant byte first.
 * @param[out] at four bytes.
 * @param[in] value the word.
 */
void fric_put_u32(unsigned char *at, uint32_t value);

/**
 * @brief The word at at[0 .. 3], least significant byte first.
 * @param[in] at four bytes.
 * @return the word.
 */
uint32_t fric_get_u32(const unsigned char *at);

/**
 * @brief The IEEE 754 bits of a float.
 * @param[in] f any float, NaN included.
 * @return its 32 bits.
 */
uint32_t fric_float_bits(float f);

/**
 * @brief The float of IEEE 754 bits.
 * @param[in] u 32 bits.
 * @return the float they encode (NaN and infinities included).
 */
float fric_bits_float(uint32_t u);

#ifdef __cplusplus
}
#endif

#endif /* FRIC_BYTES_H */
