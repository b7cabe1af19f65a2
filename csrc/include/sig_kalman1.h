/* sig_kalman1.h - stage 3 of the weighing chain: a scalar Kalman filter
 * with A = 1, B = 0, H = 1 (a constant observed in noise).
 *
 *   predict  P- = P + Q
 *   gain     K  = P- / (P- + R)
 *   update   x  = x + K (z - x),   P = (1 - K) P-
 *
 * computed as P = R K (equal to (1 - K) P-, without its cancellation).
 * Float form: once P stops changing (P after an update equals P before),
 * the gain is constant and its update is skipped; this changes no result.
 * Overflow guards keep the state finite for any finite input: if P- + R
 * overflows, K = 1 / (1 + R / P-); if z - x overflows, x = (1 - K) x + K z.
 *
 * Paper defaults Q = 1e-7, R = 0.05, x0 = 1, P0 = 10 (kg units).  With
 * seed_first the state starts from the first measurement instead of x0 (a
 * textbook filter that needs no guess).  sig_kalman1_restart_* sets P back
 * to P0 and keeps x: the motion-aware chain calls it when the load moved.
 *
 * Fixed form (_q).  The gain depends only on q = Q/R and p0 = P0/R, so the
 * filter runs on P/R: after an update P/R equals K, and the next gain is
 * K' = 1 - y with y = 1 / (1 + K + q).  Formats:
 *   x, z, x0   int32 Q24.7   (ADC codes * 128)
 *   q          uint32 Q2.30  (Q/R, 0 <= q <= 1)
 *   y, K       uint32 Q2.30  (0 < y <= 1)
 *   p0         uint32 Q16.16 (P0/R, 0 <= p0 <= 16384)
 * y is computed without dividing: two Newton steps y <- y (2 - D y) from
 * the previous y (from the seed 1.5 - D/2 on the second step after a
 * restart; the first step's y1 = floor(2^46 / (1 + p0 + q in Q16)) is
 * computed once by sig_kalman1_init_q with a shift-and-subtract loop).
 * Once y stops changing (an exact fixed point), the gain update is skipped:
 * the steady-state step is one 32x32 multiply.  All products are Q30 with
 * round-half-up (sig_kalman1.c), no int64.
 */
#ifndef SIG_KALMAN1_H
#define SIG_KALMAN1_H

#include "sig_types.h"

typedef struct {
    sig_real q, r, p0, x0;   /* parameters */
    sig_real x, p;           /* state estimate and its variance */
    sig_real k, innov;       /* last gain and innovation z - x- */
    bool seed_first;
    bool seeded;
    bool converged;          /* P reached its fixed point: gain update skipped */
} sig_kalman1_f;

typedef struct {
    int32_t x;        /* Q24.7 */
    int32_t x0;       /* Q24.7 */
    int32_t innov;    /* Q24.7, last z - x- (saturated) */
    uint32_t q;       /* Q2.30  Q/R */
    uint32_t p0;      /* Q16.16 P0/R */
    uint32_t y1;      /* Q2.30  1/(1 + p0 + q): y of the first step after a restart */
    uint32_t y;       /* Q2.30  1 - K of the last step */
    uint8_t phase;    /* 0: next step is the first after (re)start, 1: second, 2: tracking, 3: converged */
    bool seed_first;
    bool seeded;
} sig_kalman1_q;

#define SIG_KALMAN1_Q_MAX UINT32_C(1073741824)    /* q <= 1.0 in Q30 */
#define SIG_KALMAN1_P0_MAX UINT32_C(1073741824)   /* p0 <= 16384 in Q16 */

sig_status sig_kalman1_init_f(sig_kalman1_f *s, sig_real q, sig_real r, sig_real p0,
                              sig_real x0, bool seed_first);
sig_status sig_kalman1_reset_f(sig_kalman1_f *s);     /* x = x0, P = P0, unseeded */
sig_status sig_kalman1_restart_f(sig_kalman1_f *s);   /* P = P0, x kept */
sig_status sig_kalman1_step_f(sig_kalman1_f *s, sig_real z, sig_real *out);

sig_status sig_kalman1_init_q(sig_kalman1_q *s, uint32_t q_q30, uint32_t p0_q16,
                              int32_t x0_q7, bool seed_first);
sig_status sig_kalman1_reset_q(sig_kalman1_q *s);
sig_status sig_kalman1_restart_q(sig_kalman1_q *s);
sig_status sig_kalman1_step_q(sig_kalman1_q *s, int32_t z_q7, int32_t *out_q7);

#endif /* SIG_KALMAN1_H */
