/* sig_creep.c - creep on the device: a lag on the reading and its coefficient; see sig_effects.h. */
#include "sig_effects.h"
#include "sig_effects_rail.h"

sig_status sig_creep_init_q(sig_creep_q *s, int32_t alpha_q16, uint8_t frac, int32_t k_q16)
{
    /* the lag's init checks before it writes: an error leaves *s as it was */
    if (s == NULL || sig_lag_init_q(&s->lag, alpha_q16, frac) != SIG_OK) return SIG_ERR_ARG;
    s->k_q16 = k_q16;
    return SIG_OK;
}

sig_status sig_creep_reset_q(sig_creep_q *s)
{
    if (s == NULL) return SIG_ERR_ARG;
    return sig_lag_reset_q(&s->lag);
}

sig_status sig_creep_step_q(sig_creep_q *s, int32_t x, int32_t *contribution, int32_t *corrected)
{
    sig_status st;
    int32_t lagged, xs, d, v, c, y;
    if (s == NULL || contribution == NULL || corrected == NULL) return SIG_ERR_ARG;
    st = sig_lag_step_q(&s->lag, x, &lagged);
    xs = sig_shl32_sat(x, s->lag.frac);
    d = sig_sat_sub32(s->lag.z, xs);
    st = sig_flag_rail(st, d);
    v = sig_mul_q16_sat(d, s->k_q16);
    st = sig_flag_rail(st, v);
    c = sig_round_shift(v, s->lag.frac);
    y = sig_sat_sub32(x, c);
    st = sig_flag_rail(st, y);
    *contribution = c;
    *corrected = y;
    return st;
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_creep_init_f(sig_creep_f *s, sig_real alpha, sig_real k)
{
    if (s == NULL || !sig_real_isfinite(k) || sig_lag_init_f(&s->lag, alpha) != SIG_OK)
        return SIG_ERR_ARG;
    s->k = k;
    return SIG_OK;
}

sig_status sig_creep_reset_f(sig_creep_f *s)
{
    if (s == NULL) return SIG_ERR_ARG;
    return sig_lag_reset_f(&s->lag);
}

sig_status sig_creep_step_f(sig_creep_f *s, sig_real x, sig_real *contribution, sig_real *corrected)
{
    sig_status st;
    sig_real lagged, c;
    if (s == NULL || contribution == NULL || corrected == NULL) return SIG_ERR_ARG;
    st = sig_lag_step_f(&s->lag, x, &lagged);
    if (st != SIG_OK) return st;
    c = s->k * lagged - s->k * x;     /* finite or +-inf, never NaN (lagged - x could overflow) */
    *contribution = c;
    *corrected = x - c;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */
