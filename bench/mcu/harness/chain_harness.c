/* chain_harness.c - runs sig_chain (csrc/weigh/, limit -> anti-pulse -> Kalman ->
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

/* the two numeric forms differ only in these names */
#ifdef BENCH_FLOAT
typedef sig_chain_f chain_t;
typedef sig_chain_params_f params_t;
typedef sig_real value_t;
#define CHAIN_INIT sig_chain_init_f
#define CHAIN_STEP sig_chain_step_f
#define PARAMS CH_PARAMS_F
#define ONE_X CH_ONE_X_F
#define VEC_X ch_x_f
#else
typedef sig_chain_q chain_t;
typedef sig_chain_params_q params_t;
typedef int32_t value_t;
#define CHAIN_INIT sig_chain_init_q
#define CHAIN_STEP sig_chain_step_q
#define PARAMS CH_PARAMS_Q
#define ONE_X CH_ONE_X_Q
#define VEC_X ch_x_q
#endif

chain_t chain;
params_t params = PARAMS;
value_t one_x = ONE_X;
value_t one_out;
value_t vec_out[CH_N];

NOINLINE void run_batch(void)
{
    uint16_t i;
    bench_start();
    for (i = 0; i < CH_N; i++)
        vec_status[i] = CHAIN_STEP(&chain, VEC_X[i], &vec_out[i], &vec_stable[i]);
    bench_stop();
}

int main(void)
{
    init_status = CHAIN_INIT(&chain, &params);
    run_batch();
    BENCH_CALL(one_status = CHAIN_STEP(&chain, one_x, &one_out, &one_stable));
    bench_done();
    return 0;
}
