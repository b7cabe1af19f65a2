/* sig_noise_stages.h - private to csrc/weigh: the float noise estimator's
 * step (sig_noise.h), written once and used by sig_noise_step_f and by the
 * chain's batch path (sig_chain_batch.c), which inlines it on a copy of the
 * state held in locals.  static inline (sdcc: plain static, as in
 * sig_chain_stages.h). */
#ifndef SIG_NOISE_STAGES_H
#define SIG_NOISE_STAGES_H

#include "sig_noise.h"

#ifdef __SDCC
#define SIG_NOISE_STAGE static
#else
#define SIG_NOISE_STAGE static inline
#endif

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
SIG_NOISE_STAGE sig_real sig_noise_floor_f(sig_real x, sig_real res)
{
    sig_real f = (x < SIG_REAL(0.0) ? -x : x) * SIG_NOISE_FLOOR_REL;
    sig_real q = res * SIG_REAL(0.25);
    if (q > f) f = q;
    return f > SIG_NOISE_FLOOR_ABS ? f : SIG_NOISE_FLOOR_ABS;
}

/* the step's shift: large steps while the estimate is new */
SIG_NOISE_STAGE uint8_t sig_noise_shift(uint8_t count)
{
    return count < 8u ? 2u : (count < SIG_NOISE_WARMUP ? 3u : (count < 56u ? 4u : 5u));
}

/* sig_noise_step_f on a valid s */
SIG_NOISE_STAGE sig_status sig_noise_next_f(sig_noise_f *s, sig_real x, bool update)
{
    sig_real d, nd, a, up, lo, change;
    uint8_t sh;
    if (!sig_real_isfinite(x)) return SIG_WARN_REJECTED;    /* on the bits: the same on every target */
    d = x - s->prev;                            /* may overflow to inf: counts as large */
    nd = s->prev - x;                           /* -d exactly: |d| as a max, not a branch on the sign */
    d = d > nd ? d : nd;
    if (s->has_prev && d > SIG_REAL(0.0) && d < SIG_NOISE_MAX_F && (d < s->res || s->res == SIG_REAL(0.0)))
        s->res = d;                             /* the code size of a quantised signal */
    if (s->has_prev && update) {
        if (s->count == 0u) {
            s->sigma = d < SIG_NOISE_MAX_F ? d : SIG_NOISE_MAX_F;
        } else {
            sh = sig_noise_shift(s->count);
            a = sh == 2u ? SIG_REAL(0.25) : (sh == 3u ? SIG_REAL(0.125)
                : (sh == 4u ? SIG_REAL(0.0625) : SIG_REAL(0.03125)));
            /* grow by up = sigma a, shrink by (7/8) up, or stay; sigma a
             * and sigma a / 8 are exact (powers of two), so sigma (7/8) a
             * is up - up / 8 rounded once, as written in the spec, with
             * both products side by side.  One add of the selected change
             * (sigma + -c is sigma - c exactly) and no branch: d > sigma is
             * a coin toss on noise, a branch on it would be mispredicted
             * half the time. */
            up = s->sigma * a;
            change = d > s->sigma ? up : SIG_REAL(0.0);
            change = d < s->sigma ? -(s->sigma * (a - a * SIG_REAL(0.125))) : change;
            change = s->sigma + change;
            s->sigma = change > SIG_NOISE_MAX_F ? SIG_NOISE_MAX_F : change;
        }
        if (s->count < 255u) s->count++;
    }
    lo = sig_noise_floor_f(x, s->res);
    if (s->sigma < lo) s->sigma = lo;
    s->prev = x;
    s->has_prev = true;
    return SIG_OK;
}

#endif /* SIG_NO_FLOAT */

#endif /* SIG_NOISE_STAGES_H */
