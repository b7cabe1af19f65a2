/* sig_stable.h - stage 4 of the weighing chain: the stability detector.
 *
 * The output is stable when successive filter outputs differ by at most
 * `step` for `count` successive samples (paper: count 1).  The first sample
 * has no predecessor and is never stable.
 * Fixed form (_q): values and step in Q24.7 (codes * 128), like the Kalman
 * output.
 */
#ifndef SIG_STABLE_H
#define SIG_STABLE_H

#include "sig_types.h"

typedef struct {
    sig_real step;    /* >= 0 */
    sig_real prev;
    uint8_t count;    /* >= 1 */
    uint8_t run;      /* successive differences within step (saturates at 255) */
    bool has_prev;
} sig_stable_f;

typedef struct {
    int32_t step;     /* Q24.7, >= 0 */
    int32_t prev;
    uint8_t count;
    uint8_t run;
    bool has_prev;
} sig_stable_q;

sig_status sig_stable_init_f(sig_stable_f *s, sig_real step, uint8_t count);
sig_status sig_stable_reset_f(sig_stable_f *s);
sig_status sig_stable_step_f(sig_stable_f *s, sig_real x, bool *stable);

sig_status sig_stable_init_q(sig_stable_q *s, int32_t step_q7, uint8_t count);
sig_status sig_stable_reset_q(sig_stable_q *s);
sig_status sig_stable_step_q(sig_stable_q *s, int32_t x_q7, bool *stable);

#endif /* SIG_STABLE_H */
