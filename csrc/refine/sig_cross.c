/* sig_cross.c - cross-axis leak on the device: the other axes' readings; see sig_effects.h. */
#include "sig_effects.h"
#include "sig_effects_rail.h"

sig_status sig_cross_init_q(sig_cross_q *c, const int32_t *k_q16, uint8_t n)
{
    uint8_t j;
    if (c == NULL || k_q16 == NULL || n < 1u || n > SIG_CROSS_MAX_AXES) return SIG_ERR_ARG;
    for (j = 0u; j < n; ++j) c->k_q16[j] = k_q16[j];
    c->n = n;
    return SIG_OK;
}

sig_status sig_cross_apply_q(const sig_cross_q *c, int32_t x, const int32_t *others, int32_t *out)
{
    sig_status st = SIG_OK;
    int32_t acc = 0, v, y;
    uint8_t j;
    if (c == NULL || others == NULL || out == NULL) return SIG_ERR_ARG;
    for (j = 0u; j < c->n; ++j) {
        v = sig_mul_q16_sat(others[j], c->k_q16[j]);
        st = sig_flag_rail(st, v);
        acc = sig_sat_add32(acc, v);
        st = sig_flag_rail(st, acc);
    }
    y = sig_sat_sub32(x, acc);
    *out = y;
    return sig_flag_rail(st, y);
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_cross_init_f(sig_cross_f *c, const sig_real *k, uint8_t n)
{
    uint8_t j;
    if (c == NULL || k == NULL || n < 1u || n > SIG_CROSS_MAX_AXES) return SIG_ERR_ARG;
    if (!sig_real_all_finite(k, n)) return SIG_ERR_NONFINITE;
    for (j = 0u; j < n; ++j) c->k[j] = k[j];
    c->n = n;
    return SIG_OK;
}

sig_status sig_cross_apply_f(const sig_cross_f *c, sig_real x, const sig_real *others, sig_real *out)
{
    sig_real acc = SIG_REAL(0.0);
    uint8_t j;
    if (c == NULL || others == NULL || out == NULL) return SIG_ERR_ARG;
    if (!sig_real_isfinite(x)) return SIG_ERR_NONFINITE;
    for (j = 0u; j < c->n; ++j) {
        if (!sig_real_isfinite(others[j])) return SIG_ERR_NONFINITE;
        acc += c->k[j] * others[j];
    }
    *out = x - acc;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */
