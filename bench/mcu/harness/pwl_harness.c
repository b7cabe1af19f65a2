/* pwl_harness.c - the uniform-table lookup on the target: sig_pwl_eval_q16,
 * or with PW_PORT_HEADER / PW_EVAL a port-layer form of it
 * (csrc/port/msp430/sig_pwl_msp430.S).
 *
 * main() initialises three tables (one per output-scaling branch) from the
 * generated pwl_vectors.h, makes ONE direct call (table 0, an interior
 * temperature: the runner counts it from entry to return), then evaluates
 * every table at every test temperature between bench_start/bench_stop and
 * stores each output and status for the bit-exactness test.  With
 * PW_EVAL_AXES (a function evaluating the three tables of one image at one
 * temperature, csrc/port/msp430/sig_pwl_msp430.S) the direct call and the
 * batch use it instead: outputs in vec_out3[i][axis]. */
#include <stdint.h>
#include "sig_pwl.h"
#include "pwl_vectors.h"

#include "bench_marks.h"

#ifdef PW_PORT_HEADER
#include PW_PORT_HEADER
#endif
#ifndef PW_EVAL
#define PW_EVAL sig_pwl_eval_q16
#endif

sig_pwl_q16 tab[3];
uint8_t vfrac[3] = PW_VFRAC;
sig_status init_status[3];
sig_status one_status;
int32_t one_out;
int32_t vec_out[3][PW_N];
sig_status vec_status[3][PW_N];

#ifdef PW_EVAL_AXES
int32_t one_out3[3];
int32_t vec_out3[PW_N][3];
sig_status vec_status3[PW_N];
#endif

int main(void)
{
    uint8_t a;
    for (a = 0; a < 3; a++)
        init_status[a] = sig_pwl_init_q16(&tab[a], pw_tables[a], PW_KNOTS, PW_T_LO, PW_T_HI,
                                          PW_RECIP, vfrac[a]);
#ifdef PW_EVAL_AXES
    (void)a;
    BENCH_CALL(one_status = PW_EVAL_AXES(tab, 3, PW_ONE_T, one_out3));
#define VECTOR(i) PW_EVAL_AXES(tab, 3, pw_temps[i], vec_out3[i])
    BENCH_VECTORS(PW_N, vec_status3, VECTOR);
#else
    uint16_t i;
    BENCH_CALL(one_status = PW_EVAL(&tab[0], PW_ONE_T, &one_out));
    bench_start();
    for (a = 0; a < 3; a++)
        for (i = 0; i < PW_N; i++)
            vec_status[a][i] = PW_EVAL(&tab[a], pw_temps[i], &vec_out[a][i]);
    bench_stop();
    bench_done();
#endif
    return 0;
}
