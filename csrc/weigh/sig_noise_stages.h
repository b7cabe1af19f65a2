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
/* 2^60: see sig_noise_move_f */
#define SIG_NOISE_SIDE_GAIN SIG_REAL(1152921504606846976.0)

SIG_NOISE_STAGE sig_real sig_noise_floor_f(sig_real x, sig_real res)
{
    sig_real nx = -x, q = res * SIG_REAL(0.25), f;
    /* |x| REL (= |x REL|, rounding is symmetric), |x| as a max: no branch
     * on the sign, and a caller that has |x| already shares it */
    f = (x > nx ? x : nx) * SIG_NOISE_FLOOR_REL;
    if (q > f) f = q;
    return f > SIG_NOISE_FLOOR_ABS ? f : SIG_NOISE_FLOOR_ABS;
}

/* the step's size 2^-shift: large steps while the estimate is new (the
 * settled estimator's case tested first: one test per sample) */
SIG_NOISE_STAGE sig_real sig_noise_rate_f(uint8_t count)
{
    return count >= 56u ? SIG_REAL(0.03125) : (count >= SIG_NOISE_WARMUP ? SIG_REAL(0.0625)
           : (count >= 8u ? SIG_REAL(0.125) : SIG_REAL(0.25)));
}

/* sigma grown by up = sigma a, shrunk by (7/8) up, or kept, as d lies
 * above, below or at it; sigma a and sigma a / 8 are exact (powers of two),
 * so sigma (7/8) a is up - up / 8 rounded once, as written in the spec.
 * The host form (double, compiled to min/max instructions) chooses without
 * a branch: d > sigma is a coin toss on noise, a branch on it would be
 * mispredicted half the time.  sigma + SIG_NOISE_SIDE_GAIN (d - sigma) lies
 * beyond the grown value when d > sigma, below the shrunk one when d <
 * sigma (d - sigma is then at least an ulp of sigma / 2 in size: times 2^60
 * far more than sigma / 4, or +-inf) and is sigma when d == sigma; clamped
 * between the two it is the chosen value, exactly.  A float in software
 * (the MCUs) pays for each operation instead: the two tests, and the
 * product of the chosen change only. */
SIG_NOISE_STAGE sig_real sig_noise_move_f(sig_real sigma, sig_real d, sig_real a)
{
#ifdef SIG_REAL_DOUBLE
    sig_real grown = sigma + sigma * a, shrunk = sigma - sigma * (a - a * SIG_REAL(0.125));
    sig_real t = sigma + SIG_NOISE_SIDE_GAIN * (d - sigma);
    t = t > shrunk ? t : shrunk;
    return t < grown ? t : grown;
#else
    sig_real change = d > sigma ? sigma * a : SIG_REAL(0.0);
    change = d < sigma ? -(sigma * (a - a * SIG_REAL(0.125))) : change;
    return sigma + change;
#endif
}

/* sig_noise_step_f on a valid s and a finite x (a caller that has tested
 * x already skips the test) */
SIG_NOISE_STAGE void sig_noise_next_finite_f(sig_noise_f *s, sig_real x, bool update)
{
    sig_real d, nd, change, lo;
    d = x - s->prev;                            /* may overflow to inf: counts as large */
    nd = s->prev - x;                           /* -d exactly: |d| as a max, not a branch on the sign */
    d = d > nd ? d : nd;
    /* the code size of a quantised signal (the rarely true test first;
     * res is 0 or a d in (0, MAX): !(res > 0) is res == 0, one test) */
    if ((d < s->res || !(s->res > SIG_REAL(0.0))) && d > SIG_REAL(0.0) && d < SIG_NOISE_MAX_F && s->has_prev)
        s->res = d;
    if (s->has_prev && update) {
        if (s->count == 0u) {
            s->sigma = d < SIG_NOISE_MAX_F ? d : SIG_NOISE_MAX_F;
        } else {
            change = sig_noise_move_f(s->sigma, d, sig_noise_rate_f(s->count));
            s->sigma = change > SIG_NOISE_MAX_F ? SIG_NOISE_MAX_F : change;
        }
        if (s->count < 255u) s->count++;
    }
    lo = sig_noise_floor_f(x, s->res);
    if (s->sigma < lo) s->sigma = lo;
    s->prev = x;
    s->has_prev = true;
}

/* sig_noise_step_f on a valid s */
SIG_NOISE_STAGE sig_status sig_noise_next_f(sig_noise_f *s, sig_real x, bool update)
{
    if (!sig_real_isfinite(x)) return SIG_WARN_REJECTED;    /* on the bits: the same on every target */
    sig_noise_next_finite_f(s, x, update);
    return SIG_OK;
}

#endif /* SIG_NO_FLOAT */

#endif /* SIG_NOISE_STAGES_H */
