/* bench_marks.h - the markers every harness calls around what it measures:
 * runner.py sets its breakpoints on these symbols.  Included once, by the
 * harness's main file (each harness is its own program). */
#ifndef BENCH_MARKS_H
#define BENCH_MARKS_H

#include <stdint.h>

#if defined(__clang__) || defined(__GNUC__)
#define NOINLINE __attribute__((noinline))
#else
#define NOINLINE            /* sdcc never inlines a function without 'inline' */
#endif

/* The simulators of the MSP430 and the 8051 count between breakpoints on
 * these functions.  simavr has no scripted breakpoints: on the AVR the
 * program counts itself with Timer 1 (bench/mcu/avr/bench_avr.h) and
 * bench_done() hands the results over. */
#ifdef __AVR__
#include "bench_avr.h"
#define BENCH_AVR_HOOK(h) h
#else
#define BENCH_AVR_HOOK(h)
#endif

/* Markers need a side effect: clang deletes calls to empty functions.
 * Each one's bench_mark value is its id (sim_avr reads them from here). */
volatile uint8_t bench_mark;
#define BENCH_MARKER(name, id) \
    NOINLINE void name(void) { bench_mark = id; BENCH_AVR_HOOK(bench_avr_mark(id)); }
BENCH_MARKER(bench_start, 1)
BENCH_MARKER(bench_stop, 2)
NOINLINE void bench_done(void) { bench_mark = 3; BENCH_AVR_HOOK(bench_avr_dump_and_stop()); }
/* Per-axis and empty-loop markers (the Pareto harnesses: axis 0 runs from
 * bench_start, axis 1 from bench_axis1, axis 2 from bench_axis2 to
 * bench_stop; the loop's own overhead between bench_null_start/_stop). */
BENCH_MARKER(bench_axis1, 4)
BENCH_MARKER(bench_axis2, 5)
BENCH_MARKER(bench_null_start, 6)
BENCH_MARKER(bench_null_stop, 7)

/* The one call of a function the runner measures (the MSP430 and 8051
 * runners find it as the first direct call in main). */
#ifdef __AVR__
#define BENCH_CALL(stmt) BENCH_AVR_CALL(stmt)
#else
#define BENCH_CALL(stmt) stmt
#endif

/* The batch of test vectors between the start and stop markers:
 * status[i] = CALL(i) for i in 0 .. n-1; then the end marker, after which
 * the simulator script reads every output and status back. */
#define BENCH_VECTORS(n, status, CALL) do {             \
        uint16_t bench_i;                               \
        bench_start();                                  \
        for (bench_i = 0; bench_i < (n); bench_i++)     \
            (status)[bench_i] = CALL(bench_i);          \
        bench_stop();                                   \
        bench_done();                                   \
    } while (0)

/* The globals the runner reads back by name from a compensation harness:
 * the model, one reading compensated once (one_*), the vector outputs and
 * every status. */
#define BENCH_MODEL_GLOBALS(model_type, value_type, axes, n, one_in_init, one_t_init) \
    sig_status init_status;                                                         \
    sig_status one_status;                                                          \
    sig_status vec_status[n];                                                       \
    model_type model;                                                               \
    value_type one_in[axes] = one_in_init;                                          \
    value_type one_out[axes];                                                       \
    value_type one_t = one_t_init;                                                  \
    value_type vec_out[n][axes]

#endif
