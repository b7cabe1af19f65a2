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

/* Markers need a side effect: clang deletes calls to empty functions. */
volatile uint8_t bench_mark;
NOINLINE void bench_start(void) { bench_mark = 1; }
NOINLINE void bench_stop(void) { bench_mark = 2; }
NOINLINE void bench_done(void) { bench_mark = 3; }
/* Per-axis and empty-loop markers (the Pareto harnesses: axis 0 runs from
 * bench_start, axis 1 from bench_axis1, axis 2 from bench_axis2 to
 * bench_stop; the loop's own overhead between bench_null_start/_stop). */
NOINLINE void bench_axis1(void) { bench_mark = 4; }
NOINLINE void bench_axis2(void) { bench_mark = 5; }
NOINLINE void bench_null_start(void) { bench_mark = 6; }
NOINLINE void bench_null_stop(void) { bench_mark = 7; }

#endif
