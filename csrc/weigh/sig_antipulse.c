/* sig_antipulse.c - drop-max-and-min window mean; see sig_antipulse.h. */
#include "sig_antipulse.h"
#include "sig_mul_wide.h"

/* Exact 32-bit helpers of the fixed form: no int64, no division (a 32x32
 * product from four 16x16 products).  Plain static functions, not inline
 * header helpers: sdcc emits every static inline function of a header in each
 * file that includes it, each with its own spill area in the 8051's RAM. */
/* floor((2^32 - 1) / d) for d = 1..30 (index 0 unused): the reciprocals of
 * the trimmed-mean divisors. */
static const uint32_t recip_table[31] = {
    0u, 4294967295u, 2147483647u, 1431655765u, 1073741823u, 858993459u,
    715827882u, 613566756u, 536870911u, 477218588u, 429496729u, 390451572u,
    357913941u, 330382099u, 306783378u, 286331153u, 268435455u, 252645135u,
    238609294u, 226050910u, 214748364u, 204522252u, 195225786u, 186737708u,
    178956970u, 171798691u, 165191049u, 159072862u, 153391689u, 148102320u,
    143165576u
};

/* round-half-up(s / d) = floor((s + floor(d/2)) / d) for |s| < 2^30 and
 * 1 <= d <= 30, exact (Python: (s + d // 2) // d), without dividing:
 * q0 = floor(u * floor((2^32-1)/d) / 2^32), the high word of the product, is
 * floor(u / d) or one less (since u < 2^32), so one correction makes it
 * exact.  One function calling sig_mul_wide directly: on the 8051 the chain's
 * call depth is limited by the --stack-auto stack in internal RAM. */
static int32_t div_round_small(int32_t s, uint8_t d)
{
    int32_t t;
    uint32_t u, q, lo;
    if (d == 0u || d > 30u) return 0;              /* outside the contract: defined, not used */
    t = s + (int32_t)(d >> 1);
    /* floor(t / d) = -floor((-t + d - 1) / d) for t < 0 */
    u = t >= 0 ? (uint32_t)t : (uint32_t)(-t) + (uint32_t)d - 1u;
    q = sig_mul_wide(u, recip_table[d], &lo);
    if (u - q * (uint32_t)d >= (uint32_t)d) q++;
    return t >= 0 ? (int32_t)q : -(int32_t)q;
}


#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_antipulse_init_f(sig_antipulse_f *s, uint8_t n)
{
    if (!s || n < 3u || n > SIG_ANTIPULSE_MAX) return SIG_ERR_ARG;
    s->n = n;
    s->inv = SIG_REAL(1.0) / (sig_real)(n - 2u);
    return sig_antipulse_reset_f(s);
}

sig_status sig_antipulse_reset_f(sig_antipulse_f *s)
{
    if (!s) return SIG_ERR_ARG;
    s->count = 0u;
    s->head = 0u;
    s->sum = s->mx = s->mn = SIG_REAL(0.0);
    return SIG_OK;
}

/* Trimmed mean without overflow: sum of v / d over the held samples, one
 * maximum and one minimum left out, clamped to [mn, mx]. */
static sig_real safe_mean_f(const sig_antipulse_f *s)
{
    sig_real acc = SIG_REAL(0.0), d;
    bool skip_mx = s->count >= 3u, skip_mn = s->count >= 3u;
    uint8_t i;
    d = s->count >= 3u ? (sig_real)(s->count - 2u) : (sig_real)s->count;
    for (i = 0u; i < s->count; i++) {
        sig_real v = s->buf[i];
        if (skip_mx && v == s->mx) { skip_mx = false; continue; }
        if (skip_mn && v == s->mn) { skip_mn = false; continue; }
        acc += v / d;
    }
    /* the rounded terms can still sum past the largest finite value (three
     * times DBL_MAX / 3); the trimmed mean lies within [mn, mx] */
    if (acc > s->mx) acc = s->mx;
    if (acc < s->mn) acc = s->mn;
    return acc;
}
#endif /* SIG_NO_FLOAT */

/* Maximum and minimum of the window into mx, mn, after the sample leaving
 * a full window was one of them (both forms; mx, mn locals: in registers). */
#define WINDOW_EXTREMES(s, mx, mn) do {                     \
        uint8_t i_;                                         \
        (mx) = (mn) = (s)->buf[0];                          \
        for (i_ = 1u; i_ < (s)->count; i_++) {              \
            (mx) = (s)->buf[i_] > (mx) ? (s)->buf[i_] : (mx); \
            (mn) = (s)->buf[i_] < (mn) ? (s)->buf[i_] : (mn); \
        }                                                   \
    } while (0)

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
static void rescan_f(sig_antipulse_f *s)
{
    sig_real mx, mn;
    WINDOW_EXTREMES(s, mx, mn);
    s->mx = mx;
    s->mn = mn;
}

static void resum_f(sig_antipulse_f *s)
{
    sig_real sum = s->buf[0];
    uint8_t i;
    for (i = 1u; i < s->count; i++) sum += s->buf[i];
    s->sum = sum;
}

sig_status sig_antipulse_step_f(sig_antipulse_f *s, sig_real x, sig_real *out)
{
    sig_real old, t;
    uint8_t head;
    if (!s || !out) return SIG_ERR_ARG;
    if (!sig_real_isfinite(x)) return SIG_ERR_NONFINITE;
    head = s->head;
    if (s->count == s->n) {
        /* the steady state: a full window, one sample in, one out */
        old = s->buf[head];
        s->buf[head] = x;
        head++;
        if (head >= s->n) head = 0u;
        s->head = head;
        if (old == s->mx || old == s->mn) {
            rescan_f(s);
        } else {
            s->mx = x > s->mx ? x : s->mx;
            s->mn = x < s->mn ? x : s->mn;
        }
        s->sum = (s->sum - old) + x;
        if (head == 0u || !sig_real_isfinite(s->sum)) resum_f(s);
        t = s->sum - s->mx - s->mn;
        *out = sig_real_isfinite(t) ? t * s->inv : safe_mean_f(s);
        return SIG_OK;
    }
    /* filling */
    s->buf[head] = x;
    head++;
    if (head >= s->n) head = 0u;
    s->head = head;
    s->count++;
    if (s->count == 1u) {
        s->mx = s->mn = x;
    } else {
        if (x > s->mx) s->mx = x;
        if (x < s->mn) s->mn = x;
    }
    s->sum = s->sum + x;
    if (head == 0u || !sig_real_isfinite(s->sum)) resum_f(s);
    if (s->count == 1u) {
        *out = x;
    } else if (s->count == 2u) {
        t = s->sum * SIG_REAL(0.5);
        *out = sig_real_isfinite(t) ? t : safe_mean_f(s);
    } else {
        t = s->sum - s->mx - s->mn;
        if (!sig_real_isfinite(t)) *out = safe_mean_f(s);
        else if (s->count == s->n) *out = t * s->inv;
        else *out = t / (sig_real)(s->count - 2u);
    }
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */

sig_status sig_antipulse_init_q(sig_antipulse_q *s, uint8_t n)
{
    if (!s || n < 3u || n > SIG_ANTIPULSE_MAX) return SIG_ERR_ARG;
    s->n = n;
    return sig_antipulse_reset_q(s);
}

sig_status sig_antipulse_reset_q(sig_antipulse_q *s)
{
    if (!s) return SIG_ERR_ARG;
    s->count = 0u;
    s->head = 0u;
    s->sum = s->mx = s->mn = 0;
    return SIG_OK;
}

sig_status sig_antipulse_step_q(sig_antipulse_q *s, int32_t x, int32_t *out)
{
    sig_status st = SIG_OK;
    int32_t old, t;
    bool full;
    uint8_t d;
    if (!s || !out) return SIG_ERR_ARG;
    if (x > SIG_CODE_MAX) { x = SIG_CODE_MAX; st = SIG_WARN_CLAMPED; }
    else if (x < -SIG_CODE_MAX) { x = -SIG_CODE_MAX; st = SIG_WARN_CLAMPED; }
    full = s->count == s->n;
    old = s->buf[s->head];
    s->buf[s->head] = x;
    s->head++;
    if (s->head >= s->n) s->head = 0u;
    if (!full) s->count++;
    if (s->count == 1u) {
        s->mx = s->mn = x;
    } else if (full && (old == s->mx || old == s->mn)) {
        int32_t mx, mn;
        WINDOW_EXTREMES(s, mx, mn);
        s->mx = mx;
        s->mn = mn;
    } else {
        if (x > s->mx) s->mx = x;
        if (x < s->mn) s->mn = x;
    }
    /* exact: every term is within +-(2^24 - 1), at most 32 of them */
    s->sum = full ? s->sum - old + x : s->sum + x;
    if (s->count >= 3u) {
        t = s->sum - s->mx - s->mn;
        d = (uint8_t)(s->count - 2u);
    } else {
        t = s->sum;
        d = s->count;
    }
    *out = d == 1u ? t : div_round_small(t, d);
    return st;
}
