/* main.c - example firmware for an 8051 (sdcc -mmcs51 --model-large
 * --stack-auto --xstack; e.g. the STC12C5A60S2 of the weighing paper).
 *
 * sdcc's start-up clears the data and xdata memory and calls main.  The
 * large model keeps every global in xdata (the chain's window is 32 int32);
 * --stack-auto --xstack keeps the library's locals and parameters on the
 * pdata stack, so the internal stack (256 bytes, shared with the register
 * banks and sdcc's direct-RAM variables) holds only return addresses and
 * saved registers, and an interrupt handler has room (README.md, "Memory").
 *
 * The interrupt handler: timer 0 as the sample clock.  It runs during the
 * whole demo, between any two instructions of the library, and the results
 * must still equal the host's (tests/test_examples_firmware.py); its share
 * of the internal stack is measured there too. */
#include <stdint.h>
#include <8051.h>

#include "node.h"

volatile uint8_t node_done;
volatile uint32_t node_ticks;       /* sample-clock ticks since start-up */

/* Called once the results are in the node_* globals: the simulator (s51)
 * or an in-circuit debugger stops here.  sdcc never inlines it. */
void results_ready(void)
{
    node_done = 1u;
}

/* Timer 0 overflow: the sample clock's tick; a real node would start a
 * conversion or read the ADC here, or set a flag for main.  It calls no
 * function: with --xstack, sdcc 4.2 saves R0 of the interrupted code only
 * after using R0 to address the pdata stack, so a handler that calls one
 * corrupts the interrupted library code (seen in s51: the demo's results
 * went wrong).  Calling nothing, it saves only what it uses (ACC, DPL, DPH,
 * PSW, ...) on the internal stack; the example test measures those bytes
 * and requires the deepest point of the demo plus them to leave at least 48
 * bytes of the 256 free. */
void timer0_isr(void) __interrupt(TF0_VECTOR)
{
    node_ticks++;
}

/* Timer 0 in mode 2 (8-bit auto-reload): an overflow every 256 machine
 * cycles, far more often than a real sample clock, so that the handler
 * interrupts the library everywhere during the demo. */
static void sample_clock_start(void)
{
    TMOD = (uint8_t)((TMOD & 0xF0u) | 0x02u);
    TH0 = 0u;
    TL0 = 0u;
    ET0 = 1;
    EA = 1;
    TR0 = 1;
}

void main(void)
{
    sample_clock_start();
    (void)node_demo();
    results_ready();
    for (;;) {
        /* a real node goes to idle mode (PCON |= 1) here and wakes on an interrupt */
    }
}
