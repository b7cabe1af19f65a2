/* bench_avr.c - Timer 1 cycle clock, stack high-water and RAM dump for the
 * ATmega328P harnesses (bench_avr.h says what each figure is). */
#include <avr/io.h>
#include <avr/interrupt.h>
#include <avr/sleep.h>
#include "bench_avr.h"

uint32_t bench_call_cycles[BENCH_AVR_MAX_CALLS];
uint16_t bench_call_stack[BENCH_AVR_MAX_CALLS];
uint8_t bench_calls;
uint32_t bench_mark_cycles[BENCH_AVR_MARKS];
/* measured at start (read back with the results): what one overflow
 * interrupt costs, and what an empty BENCH_CALL() and two markers back to
 * back count - the measuring code itself */
uint16_t bench_isr_cycles;
uint16_t bench_call_overhead;
uint16_t bench_mark_overhead;
/* the stack this measuring code uses itself: a call's stack_bytes is the
 * larger of its own and this */
uint16_t bench_call_stack_floor;
static uint8_t calibrating;

static volatile uint16_t overflows;
static uint16_t marks;                 /* markers called so far */
static uint32_t mark_at_first;         /* calibration: the first of two back-to-back markers */
static uint32_t mark;
static uint16_t mark_overflows;

ISR(TIMER1_OVF_vect)
{
    overflows++;
}

uint32_t bench_avr_clock(void)
{
    uint8_t sreg = SREG;
    uint16_t lo, hi;
    cli();
    lo = TCNT1;
    hi = overflows;
    if ((TIFR1 & _BV(TOV1)) && lo < 0x8000u)    /* wrapped, interrupt not yet served */
        hi++;
    SREG = sreg;
    return ((uint32_t)hi << 16) | lo;
}

static uint32_t elapsed(void)
{
    uint32_t now = bench_avr_clock();
    uint16_t isr = (uint16_t)(overflows - mark_overflows);
    return now - mark - (uint32_t)isr * bench_isr_cycles;
}

static void start(void)
{
    mark_overflows = overflows;
    mark = bench_avr_clock();
}

/* A known delay measured across an overflow and without one: the
 * difference is the interrupt's cost.  Then the measuring code around an
 * empty statement, through the very functions a measurement calls. */
static void calibrate(void)
{
    uint32_t with_isr, without;
    uint16_t top;
    TCCR1A = 0;
    TCCR1B = _BV(CS10);                 /* clk/1 */
    TIMSK1 = _BV(TOIE1);
    sei();
    TCNT1 = 0;
    start();
    __builtin_avr_delay_cycles(1000);
    without = bench_avr_clock() - mark;
    TCNT1 = 0xFFFFu - 400u;
    start();
    __builtin_avr_delay_cycles(1000);
    with_isr = bench_avr_clock() - mark;
    bench_isr_cycles = (uint16_t)(with_isr - without);
    bench_avr_mark(0);
    bench_avr_mark(0);
    bench_mark_overhead = (uint16_t)(bench_mark_cycles[0] - mark_at_first);
    marks = 0;
    calibrating = 1;
    top = bench_avr_paint();
    bench_avr_call_begin();
    bench_avr_call_end(top);
    calibrating = 0;
}

/* before main (.init8): the clock runs from the first harness line on */
void bench_avr_init(void) __attribute__((naked, used, section(".init8")));
void bench_avr_init(void)
{
    calibrate();
}

/* the clock with the overflow interrupts taken out, and per marker called
 * before this one, its own cost */
void bench_avr_mark(uint8_t id)
{
    uint32_t now = bench_avr_clock() - (uint32_t)overflows * bench_isr_cycles
                   - (uint32_t)marks * bench_mark_overhead;
    if (marks == 0u)
        mark_at_first = now;
    marks++;
    if (id < BENCH_AVR_MARKS)
        bench_mark_cycles[id] = now;
}

void bench_avr_call_begin(void) { start(); }

void bench_avr_call_end(uint16_t stack_top)
{
    uint32_t cycles = elapsed() - bench_call_overhead;
    const uint8_t *p = &__heap_start;
    uint16_t stack;
    while (*p == BENCH_AVR_STACK_FILL && (uint16_t)p < stack_top)
        p++;
    stack = (uint16_t)(stack_top - (uint16_t)p + 1u);
    if (calibrating) {
        bench_call_overhead = (uint16_t)cycles;
        bench_call_stack_floor = stack;
        return;
    }
    if (bench_calls < BENCH_AVR_MAX_CALLS) {
        bench_call_cycles[bench_calls] = cycles;
        bench_call_stack[bench_calls] = stack;
        bench_calls++;
    }
}

/* ---- results out: every byte of RAM from the start of .data to the end
 * of .bss as "@ADDR hex..." lines on USART0, then stop ---- */
extern uint8_t __data_start;

static void put(char c)
{
    while (!(UCSR0A & _BV(UDRE0)))
        ;
    UDR0 = (uint8_t)c;
}

static void put_hex(uint8_t v)
{
    static const char digits[] = "0123456789abcdef";
    put(digits[v >> 4]);
    put(digits[v & 15u]);
}

void bench_avr_dump_and_stop(void)
{
    const uint8_t *p = &__data_start;
    uint8_t i;
    cli();
    UBRR0 = 0;
    UCSR0A = _BV(U2X0);
    UCSR0B = _BV(TXEN0);
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
    while (p < &__heap_start) {
        put('@');
        put_hex((uint8_t)((uint16_t)p >> 8));
        put_hex((uint8_t)(uint16_t)p);
        put(' ');
        for (i = 0; i < 32u && p < &__heap_start; i++)
            put_hex(*p++);
        put('\n');
    }
    put('$');
    put('\n');
    while (!(UCSR0A & _BV(TXC0)))       /* last byte out before the stop */
        ;
    sleep_enable();
    sleep_cpu();                        /* interrupts off: simavr exits */
    for (;;)
        ;
}
