/* sig_poly.c - Horner's rule, fixed (Q15 abscissa) and float (sig_poly.h). */
#include "sig_poly.h"

int32_t sig_mul_q15_32x16(int32_t a, int16_t u)
{
    /* a = hi * 2^16 + lo with lo in [0, 65535], so
     * floor(a*u / 2^15) = 2*hi*u + floor(lo*u / 2^15) exactly.
     * |hi*u| <= 2^15 * 32767, so 2*hi*u fits in int32; the sum is the true
     * result, whose magnitude is below 2^31 because |u| < 2^15. */
    int16_t hi = (int16_t)sig_asr32(a, 16);
    uint32_t lo = (uint32_t)a & UINT32_C(0xFFFF);
    int32_t high_part;
    uint32_t p;
    if (u == INT16_MIN) u = (int16_t)-INT16_MAX;
    high_part = (int32_t)hi * (int32_t)u;
    high_part = high_part * 2;
    if (u >= 0) {
        p = lo * (uint32_t)(uint16_t)u;
        return high_part + (int32_t)(p >> 15);
    }
    p = lo * (uint32_t)(uint16_t)(-u);
    return high_part - (int32_t)((p + UINT32_C(0x7FFF)) >> 15);
}

sig_status sig_poly_horner_q15(const int32_t *c, uint8_t order, int16_t u, int32_t *out)
{
    sig_status st = SIG_OK;
    int32_t acc, prod;
    uint8_t k;
    if (c == NULL || out == NULL || order > SIG_POLY_MAX_ORDER) return SIG_ERR_ARG;
    acc = c[order];
    for (k = order; k > 0u; k--) {
        prod = sig_mul_q15_32x16(acc, u);
        if ((c[k - 1u] > 0 && prod > INT32_MAX - c[k - 1u]) ||
            (c[k - 1u] < 0 && prod < INT32_MIN - c[k - 1u]))
            st = SIG_WARN_SATURATED;
        acc = sig_sat_add32(c[k - 1u], prod);
    }
    *out = acc;
    return st;
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_poly_horner_f(const sig_real *c, uint8_t order, sig_real u, sig_real *out)
{
    sig_real acc;
    uint8_t k;
    if (c == NULL || out == NULL || order > SIG_POLY_MAX_ORDER) return SIG_ERR_ARG;
    if (!sig_real_isfinite(u)) return SIG_ERR_NONFINITE;
    acc = c[order];
    for (k = order; k > 0u; k--) acc = c[k - 1u] + acc * u;
    if (!sig_real_isfinite(acc)) return SIG_ERR_NONFINITE;
    *out = acc;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */
