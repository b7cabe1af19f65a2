/* sig_antipulse.c - drop-max-and-min window mean; see sig_antipulse.h. */
#include "sig_antipulse.h"
#include "sig_chain_math.h"

/* floor((2^32 - 1) / d) for d = 1..30 (index 0 unused): the reciprocals of
 * the trimmed-mean divisors, so the fixed form never divides. */
static const uint32_t recip_table[31] = {
    0u, 4294967295u, 2147483647u, 1431655765u, 1073741823u, 858993459u,
    715827882u, 613566756u, 536870911u, 477218588u, 429496729u, 390451572u,
    357913941u, 330382099u, 306783378u, 286331153u, 268435455u, 252645135u,
    238609294u, 226050910u, 214748364u, 204522252u, 195225786u, 186737708u,
    178956970u, 171798691u, 165191049u, 159072862u, 153391689u, 148102320u,
    143165576u
};

static bool is_finite(sig_real x)
{
    return x - x == SIG_REAL(0.0);
}

sig_status sig_antipulse_init_f(sig_antipulse_f *s, uint8_t n)
{
    if (!s || n < 3u || n > SIG_ANTIPULSE_MAX) return SIG_ERR_ARG;
    s->n = n;
    return sig_antipulse_reset_f(s);
}

sig_status sig_antipulse_reset_f(sig_antipulse_f *s)
{
    if (!s) return SIG_ERR_ARG;
    s->count = 0u;
    s->head = 0u;
    return SIG_OK;
}

sig_status sig_antipulse_step_f(sig_antipulse_f *s, sig_real x, sig_real *out)
{
    sig_real sum, mx, mn, v;
    uint8_t i;
    if (!s || !out) return SIG_ERR_ARG;
    if (!is_finite(x)) return SIG_ERR_NONFINITE;
    s->buf[s->head] = x;
    s->head++;
    if (s->head >= s->n) s->head = 0u;
    if (s->count < s->n) s->count++;
    sum = mx = mn = s->buf[0];
    for (i = 1u; i < s->count; i++) {
        v = s->buf[i];
        sum += v;
        if (v > mx) mx = v;
        if (v < mn) mn = v;
    }
    if (s->count == 1u) *out = sum;
    else if (s->count == 2u) *out = sum * SIG_REAL(0.5);
    else *out = (sum - mx - mn) / (sig_real)(s->count - 2u);
    return SIG_OK;
}

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
    return SIG_OK;
}

sig_status sig_antipulse_step_q(sig_antipulse_q *s, int32_t x, int32_t *out)
{
    sig_status st = SIG_OK;
    int32_t sum, mx, mn, v;
    uint8_t i, d;
    if (!s || !out) return SIG_ERR_ARG;
    if (x > SIG_CODE_MAX) { x = SIG_CODE_MAX; st = SIG_WARN_CLAMPED; }
    else if (x < -SIG_CODE_MAX) { x = -SIG_CODE_MAX; st = SIG_WARN_CLAMPED; }
    s->buf[s->head] = x;
    s->head++;
    if (s->head >= s->n) s->head = 0u;
    if (s->count < s->n) s->count++;
    sum = mx = mn = s->buf[0];
    for (i = 1u; i < s->count; i++) {    /* |sum| <= 32 * (2^24 - 1) < 2^29 */
        v = s->buf[i];
        sum += v;
        if (v > mx) mx = v;
        if (v < mn) mn = v;
    }
    if (s->count >= 3u) {
        sum = sum - mx - mn;
        d = (uint8_t)(s->count - 2u);
    } else {
        d = s->count;
    }
    *out = d == 1u ? sum : sig_div_round_small(sum, d, recip_table);
    return st;
}
