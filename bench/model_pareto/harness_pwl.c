/* harness_pwl.c - sig_pwl_eval_q16 on the MSP430 for bench/model_pareto.py.
 *
 * pareto_case.h (generated per case) defines N_AXES, N_KNOTS, N_TEMPS,
 * PWL_TABLES, PWL_PARAMS ({t_lo, t_hi, recip, shift, value_frac} per axis)
 * and TEMPS.  Inputs live in RAM (.data) so nothing is constant-folded; the
 * code under test is a separate unit (csrc/tcomp/sig_pwl.c).  Between the markers,
 * each axis evaluates all N_TEMPS temperatures; the same loop around
 * bench_null measures the loop's own overhead. */
#include <stdint.h>
#include "../mcu/harness/bench_marks.h"   /* NOINLINE and the marker functions */
#include "sig_pwl.h"
#include "pareto_case.h"
#include "pareto_marks.h"

int16_t tables[N_AXES][N_KNOTS] = PWL_TABLES;
int16_t ranges[N_AXES][2] = PWL_RANGES;
uint32_t recips[N_AXES] = PWL_RECIPS;
uint8_t vfs[N_AXES] = PWL_VFS;
int16_t temps[N_TEMPS] = TEMPS;
int32_t out[N_AXES][N_TEMPS];
int16_t status[N_AXES][N_TEMPS];
int16_t init_status[N_AXES];
int32_t first_out;
int32_t null_out[N_AXES][N_TEMPS];
int16_t null_status[N_AXES][N_TEMPS];
sig_pwl_q16 pwl[N_AXES];

/* same signature and loop as the function under test, no work */
NOINLINE sig_status bench_null(const sig_pwl_q16 *p, int16_t t, int32_t *o)
{
    (void)p;
    *o = t;
    return SIG_OK;
}

NOINLINE static void run_axis(uint8_t a)
{
    uint8_t k;
    for (k = 0; k < N_TEMPS; k++) status[a][k] = sig_pwl_eval_q16(&pwl[a], temps[k], &out[a][k]);
}

NOINLINE static void run_null(uint8_t a)
{
    uint8_t k;
    for (k = 0; k < N_TEMPS; k++) null_status[a][k] = bench_null(&pwl[a], temps[k], &null_out[a][k]);
}

int main(void)
{
    uint8_t a;
    for (a = 0; a < N_AXES; a++) {
        init_status[a] = sig_pwl_init_q16(&pwl[a], tables[a], N_KNOTS, ranges[a][0], ranges[a][1],
                                          recips[a], vfs[a]);
    }
    (void)sig_pwl_eval_q16(&pwl[0], temps[N_TEMPS / 2], &first_out);
    measure_three_axes();
    return 0;
}
