/* sig_pwl.c - piecewise-linear lookup table with uniform knots (see sig_pwl.h). */
#include "sig_pwl.h"
#include "sig_image.h"

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
    sig_status st = SIG_OK;
    uint32_t pos, seg;
    int32_t acc, lo, hi_word;
    if (p == NULL || out_q16 == NULL || p->table == NULL) return SIG_ERR_ARG;
    if (t < p->t_lo) {
        t = p->t_lo;
        st = SIG_WARN_CLAMPED;
    } else if (t > p->t_hi) {
        t = p->t_hi;
        st = SIG_WARN_CLAMPED;
    }
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

sig_status sig_pwl_load_image(sig_pwl_q16 *tables, uint8_t max_axes, uint8_t *n_axes,
                              int16_t *storage, uint16_t storage_len,
                              const uint8_t *image, size_t len)
{
    const uint8_t *pay = NULL;
    uint16_t pay_len = 0u, k, stride;
    uint8_t axes, knots, a;
    int16_t t_lo, t_hi;
    uint32_t recip;
    sig_pwl_q16 check;
    sig_status st;
    if (tables == NULL || n_axes == NULL || storage == NULL || image == NULL) return SIG_ERR_ARG;
    st = sig_image_find_section(image, len, SIG_SECTION_PWL_TABLE, &pay, &pay_len);
    if (st != SIG_OK) return st;
    if (pay_len < SIG_PWL_IMAGE_FIXED_LEN) return SIG_ERR_FORMAT;
    axes = pay[0];
    knots = pay[1];
    if (axes < 1u || axes > SIG_PWL_MAX_AXES || knots < SIG_PWL_MIN_KNOTS) return SIG_ERR_FORMAT;
    stride = (uint16_t)(1u + 2u * (uint16_t)knots);
    if ((uint32_t)pay_len != (uint32_t)SIG_PWL_IMAGE_FIXED_LEN + (uint32_t)axes * stride)
        return SIG_ERR_FORMAT;
    if (axes > max_axes || (uint32_t)axes * knots > storage_len) return SIG_ERR_ARG;
    t_lo = sig_image_get_i16(pay + 2);
    t_hi = sig_image_get_i16(pay + 4);
    recip = sig_image_get_u32(pay + 6);
    for (a = 0u; a < axes; ++a) {     /* check everything before writing anything */
        st = sig_pwl_init_q16(&check, storage, knots, t_lo, t_hi, recip,
                              pay[SIG_PWL_IMAGE_FIXED_LEN + (uint16_t)a * stride]);
        if (st != SIG_OK) return SIG_ERR_FORMAT;
    }
    for (a = 0u; a < axes; ++a) {
        const uint8_t *src = pay + SIG_PWL_IMAGE_FIXED_LEN + (uint16_t)a * stride;
        int16_t *dst = storage + (uint16_t)a * knots;
        for (k = 0u; k < knots; ++k) dst[k] = sig_image_get_i16(src + 1u + 2u * k);
        (void)sig_pwl_init_q16(&tables[a], dst, knots, t_lo, t_hi, recip, src[0]);
    }
    *n_axes = axes;
    return SIG_OK;
}

static bool pwl_finite(sig_real x)
{
    /* NaN fails the comparison; inf exceeds the largest finite value. */
    return x == x && x - x == SIG_REAL(0.0);
}

sig_status sig_pwl_init_f(sig_pwl_f *p, const sig_real *table, uint8_t n_knots,
                          sig_real t_lo, sig_real t_hi, sig_real inv_step)
{
    uint8_t k;
    sig_real end_pos;
    if (p == NULL || table == NULL) return SIG_ERR_ARG;
    if (n_knots < SIG_PWL_MIN_KNOTS || !pwl_finite(t_lo) || !pwl_finite(t_hi)
        || !pwl_finite(inv_step) || !(t_hi > t_lo) || !(inv_step > SIG_REAL(0.0)))
        return SIG_ERR_ARG;
    end_pos = (t_hi - t_lo) * inv_step;
    if (!pwl_finite(end_pos) || end_pos < (sig_real)(n_knots - 2u)
        || end_pos > (sig_real)(n_knots - 1u) * SIG_REAL(1.0001)) return SIG_ERR_ARG;
    for (k = 0u; k < n_knots; ++k) {
        if (!pwl_finite(table[k])) return SIG_ERR_NONFINITE;
    }
    p->table = table;
    p->t_lo = t_lo;
    p->t_hi = t_hi;
    p->inv_step = inv_step;
    p->n_knots = n_knots;
    return SIG_OK;
}

sig_status sig_pwl_eval_f(const sig_pwl_f *p, sig_real t, sig_real *out)
{
    sig_status st = SIG_OK;
    sig_real pos, lo, hi, frac, y;
    int32_t seg;
    if (p == NULL || out == NULL || p->table == NULL) return SIG_ERR_ARG;
    if (!(t < p->t_lo) && !(t >= p->t_lo)) return SIG_ERR_NONFINITE;   /* NaN */
    if (t < p->t_lo) {
        t = p->t_lo;
        st = SIG_WARN_CLAMPED;
    } else if (t > p->t_hi) {
        t = p->t_hi;
        st = SIG_WARN_CLAMPED;
    }
    pos = (t - p->t_lo) * p->inv_step;
    seg = (int32_t)pos;                      /* pos >= 0: truncation is floor */
    if (seg >= (int32_t)(p->n_knots - 1u)) {
        *out = p->table[p->n_knots - 1u];
    } else {
        /* (1-f)*lo + f*hi cannot overflow (hi - lo can); the clamp keeps a
         * last-bit rounding from stepping outside the two knots. */
        lo = p->table[seg];
        hi = p->table[seg + 1];
        frac = pos - (sig_real)seg;
        y = (SIG_REAL(1.0) - frac) * lo + frac * hi;
        if (y < (lo < hi ? lo : hi)) y = lo < hi ? lo : hi;
        if (y > (lo < hi ? hi : lo)) y = lo < hi ? hi : lo;
        *out = y;
    }
    return st;
}
