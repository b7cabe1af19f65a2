/* chain_harness.c - runs csrc/sig_chain (limit -> anti-pulse -> Kalman ->
 * stability) on the target.
 *
 * main() initialises the chain from the generated chain_vectors.h, runs the
 * batch of samples in run_batch() between the bench_start/bench_stop markers
 * (every output, stability flag and status is stored for the bit-exactness
 * test), then makes ONE more step on the settled chain: the only direct call
 * of the step function in main, which the runner counts from entry to return.
 * BENCH_FLOAT selects the float form (sig_real = float on both MCUs). */
#include <stdint.h>
#include <stdbool.h>
#include "sig_chain.h"
#include "chain_vectors.h"

#include "bench_marks.h"

sig_status init_status;
sig_status one_status;
bool one_stable;
sig_status vec_status[CH_N];
bool vec_stable[CH_N];

#ifdef BENCH_FLOAT
sig_chain_f chain;
sig_chain_params_f params = CH_PARAMS_F;
sig_real one_x = CH_ONE_X_F;
sig_real one_out;
sig_real vec_out[CH_N];

NOINLINE void run_batch(void)
{
    uint16_t i;
    bench_start();
    for (i = 0; i < CH_N; i++)
        vec_status[i] = sig_chain_step_f(&chain, ch_x_f[i], &vec_out[i], &vec_stable[i]);
    bench_stop();
}

int main(void)
{
    init_status = sig_chain_init_f(&chain, &params);
    run_batch();
    one_status = sig_chain_step_f(&chain, one_x, &one_out, &one_stable);
    bench_done();
    return 0;
}
#else
sig_chain_q chain;
sig_chain_params_q params = CH_PARAMS_Q;
int32_t one_x = CH_ONE_X_Q;
int32_t one_out;
int32_t vec_out[CH_N];

NOINLINE void run_batch(void)
{
    uint16_t i;
    bench_start();
    for (i = 0; i < CH_N; i++)
        vec_status[i] = sig_chain_step_q(&chain, ch_x_q[i], &vec_out[i], &vec_stable[i]);
    bench_stop();
}

int main(void)
{
    init_status = sig_chain_init_q(&chain, &params);
    run_batch();
    one_status = sig_chain_step_q(&chain, one_x, &one_out, &one_stable);
    bench_done();
    return 0;
}
#endif
