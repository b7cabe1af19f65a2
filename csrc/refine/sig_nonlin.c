/* sig_nonlin.c - nonlinearity on the device: a polynomial in the scaled reading; see sig_effects.h. */
#include "sig_effects.h"
#include "sig_effects_rail.h"

sig_status sig_nonlin_init_q(sig_nonlin_q *m, const int32_t *coef, uint8_t order,
                             int32_t center, int32_t k_q16, uint8_t shift)
{
    uint8_t k;
    if (m == NULL || coef == NULL || order > SIG_POLY_MAX_ORDER || k_q16 < 1 || shift > 30u)
        return SIG_ERR_ARG;
    for (k = 0u; k <= order; ++k) m->coef[k] = coef[k];
    m->order = order;
    m->center = center;
    m->k_q16 = k_q16;
    m->shift = shift;
    return SIG_OK;
}

sig_status sig_nonlin_apply_q(const sig_nonlin_q *m, int32_t x, int32_t *out)
{
    sig_status st = SIG_OK, hs;
    int32_t d, v, p, y;
    int16_t u;
    if (m == NULL || out == NULL) return SIG_ERR_ARG;
    d = sig_sat_sub32(x, m->center);
    st = sig_flag_rail(st, d);
    v = sig_mul_q16_sat(d, m->k_q16);
    st = sig_flag_rail(st, v);
    v = sig_asr32(v, m->shift);
    if (v > INT16_MAX) {
        u = INT16_MAX;
        st = (sig_status)(st | SIG_WARN_CLAMPED);
    } else if (v < -INT16_MAX) {
        u = (int16_t)-INT16_MAX;
        st = (sig_status)(st | SIG_WARN_CLAMPED);
    } else {
        u = (int16_t)v;
    }
    hs = sig_poly_horner_q15(m->coef, m->order, u, &p);
    if (hs < 0) return hs;
    st = (sig_status)(st | hs);
    y = sig_sat_add32(x, p);
    *out = y;
    return sig_flag_rail(st, y);
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_nonlin_init_f(sig_nonlin_f *m, const sig_real *coef, uint8_t order,
                             sig_real center, sig_real inv_scale)
{
    uint8_t k;
    if (m == NULL || coef == NULL || order > SIG_POLY_MAX_ORDER) return SIG_ERR_ARG;
    if (!sig_real_isfinite(center) || !sig_real_isfinite(inv_scale) || !(inv_scale > SIG_REAL(0.0)))
        return SIG_ERR_ARG;
    if (!sig_real_all_finite(coef, (uint16_t)(order + 1u))) return SIG_ERR_NONFINITE;
    for (k = 0u; k <= order; ++k) m->coef[k] = coef[k];
    m->order = order;
    m->center = center;
    m->inv_scale = inv_scale;
    return SIG_OK;
}

sig_status sig_nonlin_apply_f(const sig_nonlin_f *m, sig_real x, sig_real *out)
{
    sig_status st, hs;
    sig_real u, p;
    if (m == NULL || out == NULL) return SIG_ERR_ARG;
    if (!sig_real_isfinite(x)) return SIG_ERR_NONFINITE;
    u = (x - m->center) * m->inv_scale;
    st = sig_clamp_real(&u, SIG_REAL(-1.0), SIG_REAL(1.0));
    hs = sig_poly_horner_f(m->coef, m->order, u, &p);
    if (hs != SIG_OK) return hs;
    *out = x + p;
    return st;
}
#endif /* SIG_NO_FLOAT */
