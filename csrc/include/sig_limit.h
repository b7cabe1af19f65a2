/* sig_limit.h - stage 1 of the weighing chain: the limit (threshold) filter.
 *
 * A sample farther than A0 from the reference Dc is an impulse: it is
 * replaced by Dc (status SIG_WARN_REJECTED).  The first sample is taken as
 * is and seeds Dc.  Used alone, an accepted sample becomes the new Dc; in the
 * chain, sig_chain sets Dc to the anti-pulse mean after every step (as the
 * weighing paper does) through sig_limit_set_ref_*.
 *
 * Lock-out fix (off when lockout_n == 0, the weighing paper's behaviour): after a
 * real load change larger than A0 every new sample would be rejected for
 * ever.  With lockout_n > 0, the lockout_n-th successive rejection on the
 * same side is accepted, re-seeds Dc and returns SIG_LIMIT_RESEEDED (the
 * chain then refills its window).  A rejection on the other side restarts
 * the count; an accepted sample clears it.
 *
 * Float form: a NaN or inf sample is an impulse too (replaced by Dc,
 * SIG_WARN_REJECTED) and never counts towards the lock-out run; before the
 * first finite sample it returns SIG_ERR_NONFINITE and changes nothing.
 * Fixed form (_q): int32 ADC codes, Q0; A0 in codes.
 */
#ifndef SIG_LIMIT_H
#define SIG_LIMIT_H

#include "sig_types.h"

/* SIG_LIMIT_RESEEDED (lock-out fix accepted and re-seeded): sig_status.h */

/* What both forms track besides the threshold and Dc: whether Dc holds a
 * sample yet, and the lock-out run. */
typedef struct {
    uint8_t lockout_n;  /* 0: off (paper); else rejections on one side before re-seeding */
    uint8_t run;        /* successive rejections on `side` */
    int8_t side;        /* +1 above Dc, -1 below, 0 none */
    bool seeded;        /* Dc holds a sample */
} sig_limit_track;

typedef struct {
    sig_real a0;        /* threshold, > 0, signal units */
    sig_real dc;        /* reference */
    sig_limit_track t;
} sig_limit_f;

typedef struct {
    int32_t a0;         /* threshold, > 0, codes */
    int32_t dc;         /* reference, codes */
    sig_limit_track t;
} sig_limit_q;

sig_status sig_limit_init_f(sig_limit_f *s, sig_real a0, uint8_t lockout_n);
sig_status sig_limit_reset_f(sig_limit_f *s);
sig_status sig_limit_set_ref_f(sig_limit_f *s, sig_real dc);
sig_status sig_limit_step_f(sig_limit_f *s, sig_real x, sig_real *out);
/* x becomes Dc and the rejection run ends: the caller saw a load change in
 * the run (the chain's ramp test) */
sig_status sig_limit_accept_f(sig_limit_f *s, sig_real x);

sig_status sig_limit_init_q(sig_limit_q *s, int32_t a0, uint8_t lockout_n);
sig_status sig_limit_reset_q(sig_limit_q *s);
sig_status sig_limit_set_ref_q(sig_limit_q *s, int32_t dc);
sig_status sig_limit_step_q(sig_limit_q *s, int32_t x, int32_t *out);
sig_status sig_limit_accept_q(sig_limit_q *s, int32_t x);

#endif /* SIG_LIMIT_H */
