/* avr_clock_harness.c - the Timer 1 cycle clock of bench/mcu/avr checked
 * against code of known length: __builtin_avr_delay_cycles(n) takes exactly
 * n cycles, so two calls differing only in n must measure n apart, across
 * Timer 1 overflows too (the long one wraps the 16-bit counter 3 times). */
#include <stdint.h>
#include "bench_marks.h"

#define SHORT_CYCLES 1000UL
#define LONG_CYCLES 200000UL

NOINLINE void delay_short(void) { __builtin_avr_delay_cycles(SHORT_CYCLES); }
NOINLINE void delay_long(void) { __builtin_avr_delay_cycles(LONG_CYCLES); }

int main(void)
{
    BENCH_CALL(delay_short());
    BENCH_CALL(delay_long());
    bench_start();
    delay_long();
    bench_stop();
    bench_done();
    return 0;
}
