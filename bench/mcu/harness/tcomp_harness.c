/* tcomp_harness.c - runs sig_tcomp (csrc/tcomp/) on the target.
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

/* the two numeric forms differ only in these names */
#ifdef BENCH_FLOAT
typedef sig_tcomp_f model_t;
typedef sig_real value_t;
#define MODEL_INIT(m) sig_tcomp_init_f((m), TC_AXES, TC_ORDER, tc_coef_f, \
                                       TC_T_LO_F, TC_T_HI_F, TC_CENTER_F, TC_INV_SCALE_F)
#define MODEL_APPLY sig_tcomp_apply_f
#define ONE_IN TC_ONE_IN_F
#define ONE_T TC_ONE_T_F
#define VEC_T tc_t_f
#define VEC_IN tc_in_f
#else
typedef sig_tcomp_q model_t;
typedef int16_t value_t;
#define MODEL_INIT(m) sig_tcomp_init_q((m), TC_AXES, TC_ORDER, tc_coef_q, tc_q, \
                                       TC_T_LO, TC_T_HI, TC_CENTER, TC_T0, TC_U_MUL, TC_U_SHIFT)
#define MODEL_APPLY sig_tcomp_apply_q
#define ONE_IN TC_ONE_IN_Q
#define ONE_T TC_ONE_T_Q
#define VEC_T tc_t_q
#define VEC_IN tc_in_q
#endif

BENCH_MODEL_GLOBALS(model_t, value_t, TC_AXES, TC_N, ONE_IN, ONE_T);

#define VECTOR(i) MODEL_APPLY(&model, VEC_T[i], VEC_IN[i], vec_out[i])

int main(void)
{
    init_status = MODEL_INIT(&model);
    BENCH_CALL(one_status = MODEL_APPLY(&model, one_t, one_in, one_out));
    BENCH_VECTORS(TC_N, vec_status, VECTOR);
    return 0;
}
