/* sig_noise.h - the per-sample noise sigma of a signal, measured on the fly.
 *
 * A quantile tracker on d = |x_k - x_{k-1}|: when d > sigma, sigma grows by
 * sigma / 2^s; when d < sigma it shrinks by (7/8) sigma / 2^s (s = 2 for the
 * first 8 updates, 3 up to SIG_NOISE_WARMUP, 4 up to 56, then 5: the spread
 * of the estimate is then about +-20 %, 5th to 95th percentile; the chain
 * sets count back to 8 when the noise has changed).  It settles where
 * P(d > sigma) = 0.48, which for Gaussian noise is sigma = 0.996 x its
 * standard deviation (d is N(0, 2 sigma^2)).  A glitch or a load step moves
 * it by one step only, whatever its size; the caller skips the update while
 * the load moves (sig_chain.c).  The first update seeds sigma = d.
 * Constant work per sample: a compare, a shift and an add (no multiply in
 * the fixed form, no division, no square root).
 *
 * Floor (a sensor stuck on one code still gets usable thresholds):
 *   fixed  sigma >= SIG_NOISE_FLOOR_Q7, a quarter code;
 *   float  sigma >= a quarter of the smallest non-zero |d| seen so far (one
 *          code of a quantised signal, in any unit; tiny for a continuous
 *          one), >= 2^-24 |x| (half a float ulp of the sample), >= 1e-30.
 * Ceiling: SIG_NOISE_MAX_Q7 (2^20 codes, so 6 sigma fits int32) and
 * SIG_NOISE_MAX_F.  A non-finite float sample changes nothing.
 *
 * Fixed form: x int32 codes within +-SIG_CODE_MAX, sigma Q24.7 (codes * 128).
 */
#ifndef SIG_NOISE_H
#define SIG_NOISE_H

#include "sig_types.h"

#define SIG_NOISE_FLOOR_Q7 INT32_C(32)
#define SIG_NOISE_MAX_Q7   INT32_C(134217728)           /* 2^27 */
#define SIG_NOISE_WARMUP   24u
#ifdef SIG_REAL_DOUBLE
#define SIG_NOISE_MAX_F    SIG_REAL(1e300)
#else
#define SIG_NOISE_MAX_F    SIG_REAL(1e36)
#endif
#define SIG_NOISE_FLOOR_ABS SIG_REAL(1e-30)
#define SIG_NOISE_FLOOR_REL SIG_REAL(5.9604644775390625e-8)   /* 2^-24 */

typedef struct {
    sig_real prev;      /* last finite sample */
    sig_real sigma;     /* the estimate, >= the floor */
    sig_real res;       /* smallest non-zero |d| seen (the code size), 0 = none yet */
    uint8_t count;      /* updates so far (saturates at 255): the step size */
    bool has_prev;
} sig_noise_f;

typedef struct {
    int32_t prev;       /* last code */
    int32_t sigma;      /* Q24.7, SIG_NOISE_FLOOR_Q7..SIG_NOISE_MAX_Q7 */
    uint8_t count;
    bool has_prev;
} sig_noise_q;

sig_status sig_noise_reset_f(sig_noise_f *s);
/* One sample; `update` false only records it as the previous sample. */
sig_status sig_noise_step_f(sig_noise_f *s, sig_real x, bool update);
bool sig_noise_at_floor_f(const sig_noise_f *s);

sig_status sig_noise_reset_q(sig_noise_q *s);
sig_status sig_noise_step_q(sig_noise_q *s, int32_t x, bool update);   /* x clamped to +-SIG_CODE_MAX */
bool sig_noise_at_floor_q(const sig_noise_q *s);

#endif /* SIG_NOISE_H */
