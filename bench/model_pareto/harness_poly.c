/* harness_poly.c - sig_tcomp_delta_q (polynomial offset of one axis: clamp,
 * scale to u, Horner) on the MSP430 for bench/model_pareto.py.
 *
 * pareto_case.h (generated per case) defines N_AXES (3), ORDER, N_TEMPS,
 * POLY_COEF (N_AXES x (ORDER+1) int32, axis-major), POLY_Q, the scaling
 * POLY_T_LO, POLY_T_HI, POLY_T_CENTER, POLY_U_MUL, POLY_U_SHIFT and TEMPS.
 * Same layout as harness_pwl.c: between the markers each axis evaluates all
 * N_TEMPS temperatures; the same loop around bench_null measures the loop's
 * own overhead. */
#include <stdint.h>
#include "../mcu/harness/bench_marks.h"   /* NOINLINE and the marker functions */
#include "sig_tcomp.h"
#include "pareto_case.h"
#include "pareto_marks.h"

int32_t coef[N_AXES * (ORDER + 1)] = POLY_COEF;
uint8_t qs[N_AXES] = POLY_Q;
int16_t temps[N_TEMPS] = TEMPS;
int32_t out[N_AXES][N_TEMPS];
int16_t status[N_AXES][N_TEMPS];
int32_t null_out[N_AXES][N_TEMPS];
int16_t null_status[N_AXES][N_TEMPS];
int16_t init_status;
int32_t first_out;
sig_tcomp_q model;

/* same signature and loop as the function under test, no work */
NOINLINE sig_status bench_null(const sig_tcomp_q *m, uint8_t axis, int16_t t, int32_t *o)
{
    (void)m;
    (void)axis;
    *o = t;
    return SIG_OK;
}

NOINLINE static void run_axis(uint8_t a)
{
    uint8_t k;
    for (k = 0; k < N_TEMPS; k++) status[a][k] = sig_tcomp_delta_q(&model, a, temps[k], &out[a][k]);
}

NOINLINE static void run_null(uint8_t a)
{
    uint8_t k;
    for (k = 0; k < N_TEMPS; k++) null_status[a][k] = bench_null(&model, a, temps[k], &null_out[a][k]);
}

int main(void)
{
    init_status = sig_tcomp_init_q(&model, N_AXES, ORDER, coef, qs, POLY_T_LO, POLY_T_HI,
                                   POLY_T_CENTER, POLY_T_CENTER, POLY_U_MUL, POLY_U_SHIFT);
    (void)sig_tcomp_delta_q(&model, 0, temps[N_TEMPS / 2], &first_out);
    measure_three_axes();
    return 0;
}
