/* sig_gain.c - gain drift on the device: a polynomial in the scaled temperature; see sig_effects.h. */
#include "sig_effects.h"
#include "sig_effects_rail.h"

sig_status sig_gain_init_q(sig_gain_q *g, const int32_t *coef, uint8_t order)
{
    uint8_t k;
    if (g == NULL || coef == NULL || order > SIG_POLY_MAX_ORDER) return SIG_ERR_ARG;
    for (k = 0u; k <= order; ++k) g->coef[k] = coef[k];
    g->order = order;
    return SIG_OK;
}

sig_status sig_gain_apply_q(const sig_gain_q *g, int16_t u_q15, int32_t x, int32_t *out)
{
    sig_status st;
    int32_t gain, y;
    if (g == NULL || out == NULL) return SIG_ERR_ARG;
    st = sig_poly_horner_q15(g->coef, g->order, u_q15, &gain);
    if (st < 0) return st;
    y = sig_mul_q16_sat(x, gain);
    *out = y;
    return sig_flag_rail(st, y);
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_gain_init_f(sig_gain_f *g, const sig_real *coef, uint8_t order)
{
    uint8_t k;
    if (g == NULL || coef == NULL || order > SIG_POLY_MAX_ORDER) return SIG_ERR_ARG;
    if (!sig_real_all_finite(coef, (uint16_t)(order + 1u))) return SIG_ERR_NONFINITE;
    for (k = 0u; k <= order; ++k) g->coef[k] = coef[k];
    g->order = order;
    return SIG_OK;
}

sig_status sig_gain_apply_f(const sig_gain_f *g, sig_real u, sig_real x, sig_real *out)
{
    sig_status st;
    sig_real gain;
    if (g == NULL || out == NULL) return SIG_ERR_ARG;
    if (!sig_real_isfinite(x)) return SIG_ERR_NONFINITE;
    st = sig_poly_horner_f(g->coef, g->order, u, &gain);
    if (st != SIG_OK) return st;
    *out = x * gain;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */
