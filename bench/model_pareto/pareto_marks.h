/* pareto_marks.h - the markers and the measured sequence of the
 * harness_poly.c / harness_pwl.c harnesses (bench/lab/mcu/model_cost.py sets
 * its breakpoints on these symbols).  Between bench_start and bench_stop
 * each of the three axes evaluates all N_TEMPS temperatures, one marker
 * between axes; the same loop around a no-op (the harness's run_null)
 * between bench_null_start and bench_null_stop measures the loop's own
 * overhead.  The harness defines run_axis and run_null.  Included once, by
 * the harness's main file. */
#ifndef PARETO_MARKS_H
#define PARETO_MARKS_H

#include "../mcu/harness/bench_marks.h"

/* bench_axis1, bench_axis2, bench_null_start, bench_null_stop: bench_marks.h */

NOINLINE static void run_axis(uint8_t a);
NOINLINE static void run_null(uint8_t a);

static void measure_three_axes(void)
{
    bench_start();
    run_axis(0);
    bench_axis1();
    run_axis(1);
    bench_axis2();
    run_axis(2);
    bench_stop();
    bench_null_start();
    run_null(0);
    bench_null_stop();
    bench_done();
}

#endif
