/* sig_antipulse.h - stage 2 of the weighing chain: the anti-pulse filter.
 *
 * A window of the last N samples (default 12, 3 <= N <= 32); the output is
 * the mean of the window without one maximum and one minimum.  While the
 * window fills (k < N samples held) the same rule uses what it holds:
 * k = 1: the sample itself; k = 2: the mean of the two; k >= 3: the mean of
 * the k samples without one maximum and one minimum.
 *
 * The window sum and its extremes are kept up to date as samples come and
 * go (an evicted maximum or minimum makes the stage rescan the window), so a
 * step costs a few operations, not a pass over N samples.
 *
 * Float form (_f): sum = (sum - evicted) + x, recomputed in storage order
 * (index 0 up) whenever the write position wraps to 0, so rounding never
 * accumulates over more than N samples.  Output (sum - max - min) * (1/(N-2))
 * for a full window (reciprocal from _init), (sum - max - min) / (k - 2)
 * while filling, sum * 0.5 for two samples.  If a sum overflows (huge
 * samples) the mean is taken as the sum of v / d over the trimmed samples,
 * which cannot overflow.
 *
 * Fixed form (_q): int32 ADC codes, Q0.  Inputs are clamped to
 * [-SIG_CODE_MAX, SIG_CODE_MAX] (25-bit signed, wider than any 24-bit ADC;
 * status SIG_WARN_CLAMPED) so a sum of 32 never overflows and a mean in
 * Q24.7 fits in int32.  The output is round-half-up(trimmed sum / d) in
 * codes, i.e. floor((s + d / 2) / d), computed exactly with a reciprocal
 * multiply and one correction (sig_antipulse.c): the MCU never divides.
 */
#ifndef SIG_ANTIPULSE_H
#define SIG_ANTIPULSE_H

#include "sig_types.h"

#define SIG_ANTIPULSE_MAX 32u
#define SIG_ANTIPULSE_DEFAULT 12u
#define SIG_CODE_MAX INT32_C(16777215)   /* 2^24 - 1 */

typedef struct {
    sig_real buf[SIG_ANTIPULSE_MAX];
    sig_real sum, mx, mn;   /* of the samples held */
    sig_real inv;           /* 1 / (n - 2) */
    uint8_t n;       /* window length */
    uint8_t count;   /* samples held, <= n */
    uint8_t head;    /* next slot to write */
} sig_antipulse_f;

typedef struct {
    int32_t buf[SIG_ANTIPULSE_MAX];   /* codes, |v| <= SIG_CODE_MAX */
    int32_t sum, mx, mn;              /* of the samples held; |sum| < 2^29 */
    uint8_t n;
    uint8_t count;
    uint8_t head;
} sig_antipulse_q;

sig_status sig_antipulse_init_f(sig_antipulse_f *s, uint8_t n);
sig_status sig_antipulse_reset_f(sig_antipulse_f *s);   /* empty window */
sig_status sig_antipulse_step_f(sig_antipulse_f *s, sig_real x, sig_real *out);

sig_status sig_antipulse_init_q(sig_antipulse_q *s, uint8_t n);
sig_status sig_antipulse_reset_q(sig_antipulse_q *s);
sig_status sig_antipulse_step_q(sig_antipulse_q *s, int32_t x, int32_t *out);

#endif /* SIG_ANTIPULSE_H */
