/* bench_avr.h - cycle counting on the ATmega328P with Timer 1, the method
 * that works the same in simavr and on a real chip (bench_avr.c).
 *
 * Timer 1 runs at clk/1; its overflow interrupt extends it to 32 bits.  A
 * figure is the difference of two clock reads minus what the reads
 * themselves and the overflow interrupts in between cost, both measured by
 * the program at start (calibrate() in bench_avr.c): cycles of the code
 * between the reads, nothing else.  Results stay in RAM: per BENCH_CALL()
 * bench_call_cycles[] and bench_call_stack[]; per marker of bench_marks.h
 * bench_mark_cycles[id], the clock when it was called (overflow interrupts
 * taken out, one marker call's own cost subtracted per marker), so a region
 * between two markers is the difference.  bench_done() dumps RAM on the
 * UART and stops the simulator (sleep with interrupts off). */
#ifndef BENCH_AVR_H
#define BENCH_AVR_H

#include <stdint.h>
#include <avr/io.h>

#define BENCH_AVR_MAX_CALLS 4u
#define BENCH_AVR_STACK_FILL 0xA5u

extern uint32_t bench_call_cycles[BENCH_AVR_MAX_CALLS];
extern uint16_t bench_call_stack[BENCH_AVR_MAX_CALLS];
extern uint8_t bench_calls;
#define BENCH_AVR_MARKS 8u
extern uint32_t bench_mark_cycles[BENCH_AVR_MARKS];

uint32_t bench_avr_clock(void);
void bench_avr_mark(uint8_t id);
void bench_avr_call_begin(void);
void bench_avr_call_end(uint16_t stack_top);
void bench_avr_dump_and_stop(void);

extern uint8_t __heap_start;          /* first byte above .bss (avr-libc linker script) */

/* Fill the free stack below the caller's frame with the pattern; inline so
 * that nothing of the painting is left on the stack it paints. */
static inline __attribute__((always_inline)) uint16_t bench_avr_paint(void)
{
    uint8_t *p = &__heap_start;
    uint16_t top = SP;
    while ((uint16_t)p < top - 1u)
        *p++ = BENCH_AVR_STACK_FILL;
    return top;
}

/* One statement measured: cycles from the clock read before it to the one
 * after (the call with its argument set-up and result store), and the
 * stack it used below the caller's stack pointer (return address included). */
#define BENCH_AVR_CALL(stmt) do {                       \
        uint16_t bench_top_ = bench_avr_paint();        \
        bench_avr_call_begin();                         \
        stmt;                                           \
        bench_avr_call_end(bench_top_);                 \
    } while (0)

#endif
