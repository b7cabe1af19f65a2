/* tcomp_harness.c - runs csrc/sig_tcomp on the target.
 *
 * main() initialises the model from the generated tcomp_vectors.h, makes ONE
 * call of the compensation (the first direct call in main: the runner counts
 * it from entry to return), then runs the batch of test vectors between the
 * bench_start/bench_stop markers and stores every output and status, which
 * the simulator script reads back for the bit-exactness test.
 * BENCH_FLOAT selects the float form (sig_real = float on both MCUs). */
#include <stdint.h>
#include "sig_tcomp.h"
#include "tcomp_vectors.h"

#include "bench_marks.h"

sig_status init_status;
sig_status one_status;
sig_status vec_status[TC_N];

#ifdef BENCH_FLOAT
sig_tcomp_f model;
sig_real one_in[TC_AXES] = TC_ONE_IN_F;
sig_real one_out[TC_AXES];
sig_real one_t = TC_ONE_T_F;
sig_real vec_out[TC_N][TC_AXES];
#else
sig_tcomp_q model;
int16_t one_in[TC_AXES] = TC_ONE_IN_Q;
int16_t one_out[TC_AXES];
int16_t one_t = TC_ONE_T_Q;
int16_t vec_out[TC_N][TC_AXES];
#endif

int main(void)
{
    uint16_t i;
#ifdef BENCH_FLOAT
    init_status = sig_tcomp_init_f(&model, TC_AXES, TC_ORDER, tc_coef_f,
                                   TC_T_LO_F, TC_T_HI_F, TC_CENTER_F, TC_INV_SCALE_F);
    one_status = sig_tcomp_apply_f(&model, one_t, one_in, one_out);
    bench_start();
    for (i = 0; i < TC_N; i++)
        vec_status[i] = sig_tcomp_apply_f(&model, tc_t_f[i], tc_in_f[i], vec_out[i]);
    bench_stop();
#else
    init_status = sig_tcomp_init_q(&model, TC_AXES, TC_ORDER, tc_coef_q, tc_q,
                                   TC_T_LO, TC_T_HI, TC_CENTER, TC_T0, TC_U_MUL, TC_U_SHIFT);
    one_status = sig_tcomp_apply_q(&model, one_t, one_in, one_out);
    bench_start();
    for (i = 0; i < TC_N; i++)
        vec_status[i] = sig_tcomp_apply_q(&model, tc_t_q[i], tc_in_q[i], vec_out[i]);
    bench_stop();
#endif
    bench_done();
    return 0;
}
