/* main.c - example firmware for the MSP430F5510 (clang --target=msp430).
 *
 * Start-up (stack, .data copy, .bss clear) is crt0.S; main stops the
 * watchdog again (harmless when crt0 already did: a firmware with another
 * start-up file must not depend on it), runs the node, then sleeps. */
#include <stdint.h>

#include "node.h"

#define WDTCTL (*(volatile uint16_t *)0x015Cu)   /* F5xx watchdog control */
#define WDTPW_HOLD 0x5A80u                       /* password | WDTHOLD */

volatile uint8_t node_done;

/* Called once the results are in the node_* globals: a debugger or the
 * simulator stops here.  Not inlined: it must exist as a symbol. */
__attribute__((noinline)) void results_ready(void)
{
    node_done = 1u;
}

int main(void)
{
    WDTCTL = WDTPW_HOLD;
    (void)node_demo();
    results_ready();
    for (;;) {
        /* a real node enters a low-power mode here and wakes on the ADC */
    }
}
