/* harness_pwl_f.c - sig_pwl_eval_f (float form, sig_real = float on the
 * MCU) over N_TEMPS temperatures for one table; outputs and statuses are
 * read back by tests/test_pareto.py.  pareto_case.h defines N_KNOTS,
 * N_TEMPS, TABLE_F, T_LO_F, T_HI_F, INV_STEP_F and TEMPS_F. */
#include <stdint.h>
#include "../mcu/harness/bench_marks.h"   /* NOINLINE and the marker functions */
#include "sig_pwl.h"
#include "pareto_case.h"

sig_real table[N_KNOTS] = TABLE_F;
sig_real temps[N_TEMPS] = TEMPS_F;
sig_real t_lo = T_LO_F, t_hi = T_HI_F, inv_step = INV_STEP_F;
sig_real out[N_TEMPS];
int16_t status[N_TEMPS];
int16_t init_status;
sig_real first_out;
sig_pwl_f pwl;

int main(void)
{
    uint8_t k;
    init_status = sig_pwl_init_f(&pwl, table, N_KNOTS, t_lo, t_hi, inv_step);
    (void)sig_pwl_eval_f(&pwl, temps[N_TEMPS / 2], &first_out);
    bench_start();
    for (k = 0; k < N_TEMPS; k++) status[k] = sig_pwl_eval_f(&pwl, temps[k], &out[k]);
    bench_stop();
    bench_done();
    return 0;
}
