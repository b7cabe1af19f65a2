/* main.c - example firmware for an 8051 (sdcc -mmcs51 --model-large
 * --stack-auto; e.g. the STC12C5A60S2 of the weighing paper).
 *
 * sdcc's start-up clears the data and xdata memory and calls main.  The
 * large model keeps every global in xdata (the chain's window is 32 int32),
 * --stack-auto keeps the library's locals on the stack in internal RAM
 * instead of sdcc's shared overlay (the chain's call depth needs it). */
#include <stdint.h>

#include "node.h"

volatile uint8_t node_done;

/* Called once the results are in the node_* globals: the simulator (s51)
 * or an in-circuit debugger stops here.  sdcc never inlines it. */
void results_ready(void)
{
    node_done = 1u;
}

void main(void)
{
    (void)node_demo();
    results_ready();
    for (;;) {
        /* a real node goes to idle mode (PCON |= 1) here and wakes on an interrupt */
    }
}
