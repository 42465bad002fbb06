/* fricgen firmware harness: evaluates a model (and optionally runs the controller) on the
 * emulated MCU and prints every result as the hex bits of its float32/int32 value.
 * fw_config.h is written by fricgen.firmware: it includes the model and defines
 * fw_input_t, fw_output_t, FW_EVAL(x), FW_BITS(y), fw_inputs[], FW_N_INPUTS, FW_N_BENCH and,
 * optionally, FW_AXES() (further models of a several-axis program, printed after the first)
 * and FW_EXTRA() (more output, e.g. a closed-loop run). */
#include <stdint.h>

#include "semihost.h"
#include "fw_config.h"

volatile fw_output_t fw_sink;

/* Instruction counting: the driver counts the instructions executed between these two calls. */
__attribute__((noinline)) void fw_mark_begin(void)
{
    __asm__ volatile("" ::: "memory");
}

__attribute__((noinline)) void fw_mark_end(void)
{
    __asm__ volatile("" ::: "memory");
}

int main(void)
{
    uint32_t i;
    sh_write0("fricgen-fw begin\n");
    for (i = 0; i < FW_N_INPUTS; ++i) {
        const fw_output_t y = FW_EVAL(fw_inputs[i]);
        sh_put_hex(FW_BITS(y));
        sh_write0("\n");
    }
#ifdef FW_AXES
    FW_AXES();
#endif
    fw_mark_begin();
    for (i = 0; i < FW_N_BENCH; ++i) {
        fw_sink = FW_EVAL(fw_inputs[i % FW_N_INPUTS]);
    }
    fw_mark_end();
#ifdef FW_EXTRA
    FW_EXTRA();
#endif
    sh_write0("fricgen-fw end\n");
    return 0;
}
