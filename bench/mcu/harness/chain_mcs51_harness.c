/* chain_mcs51_harness.c - runs the 8051 form of the fixed chain
 * (csrc/port/mcs51/sig_chain_mcs51.c) in s51.
 *
 * main() initialises it from the generated chain_vectors.h (parameters,
 * samples, the Kalman gain table in code memory), runs the batch between
 * bench_start/bench_stop storing every output, stability flag and status,
 * then makes ONE more direct call of the step on the settled chain (the
 * steady-state step: the runner counts it from entry to return; its output,
 * flag and status are kept for the check, as the restart step's), feeds
 * CH_RESTART_PRE samples of a new level, and makes the step on which the
 * chain detects the motion and restarts inside restart_step() (counted the
 * same way, as its call there). */
#include <stdint.h>
#include <stdbool.h>
#include "chain_vectors.h"
#include "sig_chain_mcs51.h"

#include "bench_marks.h"

sig_status init_status;
sig_status one_status, pre_status, restart_status;
int32_t one_out, restart_out;
bool one_stable;
sig_chain_params_q params = CH_PARAMS_Q;
int32_t vec_out[CH_N];
sig_status vec_status[CH_N];
bool vec_stable[CH_N];

NOINLINE void run_batch(void)
{
    uint16_t i;
    bench_start();
    for (i = 0; i < CH_N; i++) {
        vec_status[i] = sig_chain_mcs51_step(ch_x_q[i]);
        vec_out[i] = sig_chain_mcs51.out;
        vec_stable[i] = sig_chain_mcs51.stable;
    }
    bench_stop();
}

NOINLINE void restart_step(void)
{
    restart_status = sig_chain_mcs51_step(CH_RESTART_X);
    restart_out = sig_chain_mcs51.out;
}

int main(void)
{
    uint8_t i;
    init_status = sig_chain_mcs51_init(&params, ch_gains, CH_N_GAINS);
    run_batch();
    one_status = sig_chain_mcs51_step(CH_ONE_X_Q);
    one_out = sig_chain_mcs51.out;
    one_stable = sig_chain_mcs51.stable;
    for (i = 0; i < CH_RESTART_PRE; i++) pre_status = sig_chain_mcs51_step(CH_RESTART_X);
    restart_step();
    bench_done();
    return 0;
}
