/* ARM semihosting (bkpt 0xAB) for the bare-metal fricgen firmware: print and exit under QEMU. */
#ifndef FW_SEMIHOST_H
#define FW_SEMIHOST_H

#include <stdint.h>

void sh_write0(const char *text);          /* SYS_WRITE0: print a NUL-terminated string */
void sh_put_hex(uint32_t value);           /* eight lower-case hex digits */
void sh_exit(int failed) __attribute__((noreturn)); /* SYS_EXIT: QEMU exits with 0 or 1 */

#endif /* FW_SEMIHOST_H */
