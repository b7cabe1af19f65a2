/* sig_pwl.c - piecewise-linear lookup table with uniform knots (see sig_pwl.h). */
#include "sig_pwl.h"

/* floor(d * recip / 2^16) from two 16x16 -> 32 products: d * recip =
 * d * rh * 2^16 + d * rl.  The callers keep the result below 2^32. */
static uint32_t pwl_position(uint16_t d, uint32_t recip)
{
    uint32_t rh = recip >> 16, rl = recip & 0xFFFFu;
    return (uint32_t)d * rh + (((uint32_t)d * rl) >> 16);
}

sig_status sig_pwl_init_q16(sig_pwl_q16 *p, const int16_t *table, uint8_t n_knots,
                            int16_t t_lo, int16_t t_hi, uint32_t recip, uint8_t value_frac)
{
    uint32_t span, end_pos;
    if (p == NULL || table == NULL) return SIG_ERR_ARG;
    if (n_knots < SIG_PWL_MIN_KNOTS || t_hi <= t_lo || recip == 0u || value_frac > 15u)
        return SIG_ERR_ARG;
    span = (uint32_t)((int32_t)t_hi - (int32_t)t_lo);
    /* floor(span * recip / 2^16) must not exceed (n-1) * 2^16 <= 254 * 2^16:
     * test span * (recip >> 16) first so that nothing below overflows. */
    if ((recip >> 16) > (UINT32_C(255) << 16) / span) return SIG_ERR_ARG;
    end_pos = pwl_position((uint16_t)span, recip);
    if ((end_pos >> 16) < (uint32_t)(n_knots - 2u)
        || end_pos > ((uint32_t)(n_knots - 1u) << 16)) return SIG_ERR_ARG;
    p->table = table;
    p->recip = recip;
    p->t_lo = t_lo;
    p->t_hi = t_hi;
    if (value_frac > 4u) p->out_mul = (uint16_t)(1u << (20u - value_frac));
    else if (value_frac < 4u) p->out_mul = (uint16_t)(1u << (4u - value_frac));
    else p->out_mul = 0u;
    p->n_knots = n_knots;
    p->value_frac = value_frac;
    return SIG_OK;
}

sig_status sig_pwl_eval_q16(const sig_pwl_q16 *p, int16_t t, int32_t *out_q16)
{
    sig_status st;
    uint32_t pos, seg;
    int32_t acc, lo, hi_word;
    if (p == NULL || out_q16 == NULL || p->table == NULL) return SIG_ERR_ARG;
    st = sig_clamp_i16(&t, p->t_lo, p->t_hi);
    pos = pwl_position((uint16_t)((int32_t)t - (int32_t)p->t_lo), p->recip);
    seg = pos >> 16;
    if (seg >= (uint32_t)(p->n_knots - 1u)) {
        /* exactly on (or, by the reciprocal's rounding, a hair past) the last knot */
        acc = (int32_t)p->table[p->n_knots - 1u] * (INT32_C(1) << SIG_PWL_FRAC_BITS);
    } else {
        lo = p->table[seg];
        acc = lo * (INT32_C(1) << SIG_PWL_FRAC_BITS)
            + ((int32_t)p->table[seg + 1u] - lo) * (int32_t)((uint16_t)pos >> 4);
    }
    /* acc has value_frac + 12 fraction bits; Q16.16 wants 16. */
    if (p->value_frac > 4u) {
        /* floor(acc / 2^(vf-4)) = floor(acc * 2^(20-vf) / 2^16), split into
         * the high (signed) and low (unsigned) halves of acc */
        hi_word = sig_asr32(acc, 16);
        *out_q16 = hi_word * (int32_t)p->out_mul
                 + (int32_t)((((uint32_t)acc & 0xFFFFu) * p->out_mul) >> 16);
    } else if (p->value_frac < 4u) {
        *out_q16 = acc * (int32_t)p->out_mul;     /* |acc| <= 32767 * 2^12: fits */
    } else {
        *out_q16 = acc;
    }
    return st;
}
