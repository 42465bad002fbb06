/* Minimal Cortex-M startup for the fricgen firmware under QEMU (mps2-an386: Cortex-M4F;
 * microbit: Cortex-M0, running the ARMv6-M Cortex-M0+ build): vector table, .data/.bss set-up,
 * FPU enable (hard-float builds), ARM semihosting output and exit. */
#include <stdint.h>

#include "semihost.h"

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
int main(void);
void Reset_Handler(void);
void Fault_Handler(void);

__attribute__((section(".vectors"), used)) const uintptr_t fw_vectors[16] = {
    (uintptr_t)&_estack, (uintptr_t)&Reset_Handler, (uintptr_t)&Fault_Handler,
    (uintptr_t)&Fault_Handler, (uintptr_t)&Fault_Handler, (uintptr_t)&Fault_Handler,
    (uintptr_t)&Fault_Handler, 0, 0, 0, 0, (uintptr_t)&Fault_Handler,
    (uintptr_t)&Fault_Handler, 0, (uintptr_t)&Fault_Handler, (uintptr_t)&Fault_Handler,
};

static int32_t sh_call(int32_t op, const void *arg)
{
    register int32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void sh_write0(const char *text)
{
    (void)sh_call(0x04, text);
}

void sh_put_hex(uint32_t value)
{
    char buf[9];
    int i;
    for (i = 7; i >= 0; --i) {
        buf[i] = "0123456789abcdef"[value & 0xfu];
        value >>= 4;
    }
    buf[8] = '\0';
    sh_write0(buf);
}

void sh_exit(int failed)
{
    /* ADP_Stopped_ApplicationExit (0x20026) -> exit 0; ADP_Stopped_RunTimeErrorUnknown -> 1 */
    for (;;) {
        (void)sh_call(0x18, (const void *)(uintptr_t)(failed ? 0x20023u : 0x20026u));
    }
}

void Fault_Handler(void)
{
    sh_write0("fault\n");
    sh_exit(1);
}

void Reset_Handler(void)
{
    uint32_t *src = &_sidata;
    uint32_t *dst;
    for (dst = &_sdata; dst < &_edata;) {
        *dst++ = *src++;
    }
    for (dst = &_sbss; dst < &_ebss;) {
        *dst++ = 0u;
    }
#if defined(__ARM_FP)
    /* CPACR: full access to CP10 and CP11 (the FPU) before any floating-point instruction */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
#endif
    sh_exit(main() != 0);
}
