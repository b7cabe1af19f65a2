/* sig_lag.c - the first-order lag on the device (thermal lag, creep state); see sig_effects.h. */
#include "sig_effects.h"
#include "sig_effects_rail.h"

sig_status sig_lag_init_q(sig_lag_q *s, int32_t alpha_q16, uint8_t frac)
{
    if (s == NULL || alpha_q16 < 1 || alpha_q16 > SIG_Q16_ONE || frac > SIG_LAG_MAX_FRAC)
        return SIG_ERR_ARG;
    s->alpha_q16 = alpha_q16;
    s->frac = frac;
    s->z = 0;
    s->primed = false;
    return SIG_OK;
}

sig_status sig_lag_reset_q(sig_lag_q *s)
{
    if (s == NULL) return SIG_ERR_ARG;
    s->z = 0;
    s->primed = false;
    return SIG_OK;
}

sig_status sig_lag_step_q(sig_lag_q *s, int32_t x, int32_t *out)
{
    sig_status st = SIG_OK;
    int32_t xs, d, z;
    if (s == NULL || out == NULL) return SIG_ERR_ARG;
    xs = sig_shl32_sat(x, s->frac);
    st = sig_flag_rail(st, xs);
    if (!s->primed) {
        z = xs;
    } else {
        d = sig_sat_sub32(xs, s->z);
        st = sig_flag_rail(st, d);
        z = sig_sat_add32(s->z, sig_mul_q16_sat(d, s->alpha_q16));
        st = sig_flag_rail(st, z);
    }
    s->z = z;
    s->primed = true;
    *out = sig_round_shift(z, s->frac);
    return st;
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_lag_init_f(sig_lag_f *s, sig_real alpha)
{
    if (s == NULL || !sig_real_isfinite(alpha) || !(alpha > SIG_REAL(0.0)) || alpha > SIG_REAL(1.0))
        return SIG_ERR_ARG;
    s->alpha = alpha;
    s->z = SIG_REAL(0.0);
    s->primed = false;
    return SIG_OK;
}

sig_status sig_lag_reset_f(sig_lag_f *s)
{
    if (s == NULL) return SIG_ERR_ARG;
    s->z = SIG_REAL(0.0);
    s->primed = false;
    return SIG_OK;
}

sig_status sig_lag_step_f(sig_lag_f *s, sig_real x, sig_real *out)
{
    if (s == NULL || out == NULL) return SIG_ERR_ARG;
    if (!sig_real_isfinite(x)) return SIG_ERR_NONFINITE;
    if (!s->primed) {
        s->z = x;
        s->primed = true;
    } else {
        /* convex combination: never overflows for finite z and x (the
         * form z + alpha*(x - z) did, for x - z beyond the range) */
        s->z = (SIG_REAL(1.0) - s->alpha) * s->z + s->alpha * x;
    }
    *out = s->z;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */
