/* sig_scale.c - linear scale calibration, fixed point and float.
 * See sig_scale.h for the Q formats. */
#include "sig_scale.h"

/* floor(a * b / 2^n) saturated to int32, 0 <= n <= 62, 32-bit arithmetic
 * only.  *saturated is set when the result hit a rail. */
static int32_t mul_shift_sat(int32_t a, int32_t b, uint8_t n, bool *saturated)
{
    bool neg = (a < 0) != (b < 0);
    uint32_t ua = a < 0 ? (uint32_t)0 - (uint32_t)a : (uint32_t)a;
    uint32_t ub = b < 0 ? (uint32_t)0 - (uint32_t)b : (uint32_t)b;
    uint32_t ah = ua >> 16, al = ua & 0xFFFFu, bh = ub >> 16, bl = ub & 0xFFFFu;
    uint32_t lo = al * bl, hi = ah * bh;          /* product = hi * 2^32 + lo */
    uint32_t m1 = al * bh, m2 = ah * bl, mid, lo_new, qhi, qlo;
    bool rem;

    mid = m1 + m2;
    if (mid < m1) hi += UINT32_C(0x10000);         /* carry of the middle sum */
    lo_new = lo + (mid << 16);
    if (lo_new < lo) hi += 1u;
    lo = lo_new;
    hi += mid >> 16;

    if (n == 0u) {
        qhi = hi; qlo = lo; rem = false;
    } else if (n < 32u) {
        qlo = (lo >> n) | (hi << (32u - n));
        qhi = hi >> n;
        rem = (lo << (32u - n)) != 0u;
    } else if (n == 32u) {
        qhi = 0u; qlo = hi; rem = lo != 0u;
    } else {
        qhi = 0u;
        qlo = hi >> (uint8_t)(n - 32u);
        rem = lo != 0u || (hi << (uint8_t)(64u - n)) != 0u;
    }

    if (!neg) {
        if (qhi != 0u || qlo > UINT32_C(0x7FFFFFFF)) { *saturated = true; return INT32_MAX; }
        return (int32_t)qlo;
    }
    /* negative: floor(-(q + frac)) = -q - (frac != 0) */
    if (qhi != 0u || qlo > UINT32_C(0x80000000)
        || (qlo == UINT32_C(0x80000000) && rem)) { *saturated = true; return INT32_MIN; }
    if (rem) qlo += 1u;
    return qlo == UINT32_C(0x80000000) ? INT32_MIN : -(int32_t)qlo;
}

sig_status sig_scale_init_q16(sig_scale_q16 *s, int32_t offset, int32_t gain_mant, uint8_t gain_shift)
{
    if (s == NULL || gain_mant == 0 || gain_shift > SIG_SCALE_MAX_SHIFT) return SIG_ERR_ARG;
    s->offset = offset;
    s->gain_mant = gain_mant;
    s->gain_shift = gain_shift;
    return SIG_OK;
}

sig_status sig_scale_apply_q16(const sig_scale_q16 *s, int32_t counts, int32_t *mass_q16)
{
    bool saturated = false;
    int32_t d;
    if (s == NULL || mass_q16 == NULL) return SIG_ERR_ARG;
    d = sig_sat_sub32(counts, s->offset);
    /* d is exact unless counts - offset leaves int32 (a rail value may be exact);
     * INT32_MAX + offset and INT32_MIN + offset cannot overflow on these sides */
    saturated = (s->offset < 0 && counts > INT32_MAX + s->offset)
             || (s->offset > 0 && counts < INT32_MIN + s->offset);
    *mass_q16 = mul_shift_sat(d, s->gain_mant, s->gain_shift, &saturated);
    return saturated ? SIG_WARN_SATURATED : SIG_OK;
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_scale_init_f(sig_scale_f *s, sig_real offset, sig_real gain)
{
    if (s == NULL) return SIG_ERR_ARG;
    if (!sig_real_isfinite(offset) || !sig_real_isfinite(gain)) return SIG_ERR_NONFINITE;
    if (gain == SIG_REAL(0.0)) return SIG_ERR_ARG;
    s->offset = offset;
    s->gain = gain;
    return SIG_OK;
}

sig_status sig_scale_apply_f(const sig_scale_f *s, sig_real counts, sig_real *mass)
{
    if (s == NULL || mass == NULL) return SIG_ERR_ARG;
    if (!sig_real_isfinite(counts)) return SIG_ERR_NONFINITE;
    *mass = (counts - s->offset) * s->gain;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */
