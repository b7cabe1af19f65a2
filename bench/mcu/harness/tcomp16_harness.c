/* tcomp16_harness.c - runs sig_tcomp16 (csrc/tcomp/, the compact compensation) on
 * the target, like tcomp_harness.c: main() initialises the model from the
 * generated tcomp16_vectors.h, makes ONE direct call of sig_tcomp16_apply_q
 * (the runner counts it from entry to return), then runs the batch of test
 * vectors between bench_start/bench_stop and stores every output and status
 * for the bit-exactness test. */
#include <stdint.h>
#include "sig_tcomp16.h"
#include "tcomp16_vectors.h"

#include "bench_marks.h"

/* TC16_PORT_HEADER / TC16_APPLY: run a port-layer form of the entry point
 * instead (bench/mcu_cost.py: csrc/port/msp430/sig_tcomp16_msp430.S) */
#ifdef TC16_PORT_HEADER
#include TC16_PORT_HEADER
#endif
#ifndef TC16_APPLY
#define TC16_APPLY sig_tcomp16_apply_q
#endif

BENCH_MODEL_GLOBALS(sig_tcomp16_q, int16_t, TC16_AXES, TC16_N, TC16_ONE_IN, TC16_ONE_T);

#define VECTOR(i) TC16_APPLY(&model, tc16_t[i], tc16_in[i], vec_out[i])

int main(void)
{
    init_status = sig_tcomp16_init(&model, TC16_AXES, TC16_ORDER, tc16_top, tc16_add,
                                   TC16_T_LO, TC16_T_HI, TC16_W_SHIFT);
    BENCH_CALL(one_status = TC16_APPLY(&model, one_t, one_in, one_out));
    BENCH_VECTORS(TC16_N, vec_status, VECTOR);
    return 0;
}
