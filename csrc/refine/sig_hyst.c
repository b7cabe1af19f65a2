/* sig_hyst.c - hysteresis on the device: the play operator on the temperature; see sig_effects.h. */
#include "sig_effects.h"
#include "sig_effects_rail.h"

sig_status sig_hyst_init_q(sig_hyst_q *s, int16_t width, int32_t k_q16, int8_t start)
{
    if (s == NULL || width < 1 || start < -1 || start > 1) return SIG_ERR_ARG;
    s->width = width;
    s->start = start;
    s->k_q16 = k_q16;
    s->p = 0;
    s->primed = false;
    return SIG_OK;
}

sig_status sig_hyst_reset_q(sig_hyst_q *s)
{
    if (s == NULL) return SIG_ERR_ARG;
    s->p = 0;
    s->primed = false;
    return SIG_OK;
}

sig_status sig_hyst_step_q(sig_hyst_q *s, int16_t t, int16_t *branch, int32_t *contribution)
{
    sig_status st = SIG_OK;
    int32_t tt = (int32_t)t, p, b, c;
    if (s == NULL || branch == NULL || contribution == NULL) return SIG_ERR_ARG;
    if (!s->primed) {
        p = tt - (int32_t)s->start * (int32_t)s->width;
    } else {
        p = s->p;
        if (tt - p > (int32_t)s->width) {
            p = tt - (int32_t)s->width;
        } else if (p - tt > (int32_t)s->width) {
            p = tt + (int32_t)s->width;
        }
    }
    b = tt - p;                                   /* |b| <= width <= 32767 */
    c = sig_mul_q16_sat(b * SIG_Q16_ONE, s->k_q16);
    st = sig_flag_rail(st, c);
    s->p = p;
    s->primed = true;
    *branch = (int16_t)b;
    *contribution = c;
    return st;
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_hyst_init_f(sig_hyst_f *s, sig_real width, sig_real k, int8_t start)
{
    if (s == NULL || !sig_real_isfinite(width) || !sig_real_isfinite(k) || !(width > SIG_REAL(0.0))
        || start < -1 || start > 1) return SIG_ERR_ARG;
    s->width = width;
    s->start = start;
    s->k = k;
    s->p = SIG_REAL(0.0);
    s->primed = false;
    return SIG_OK;
}

sig_status sig_hyst_reset_f(sig_hyst_f *s)
{
    if (s == NULL) return SIG_ERR_ARG;
    s->p = SIG_REAL(0.0);
    s->primed = false;
    return SIG_OK;
}

sig_status sig_hyst_step_f(sig_hyst_f *s, sig_real t, sig_real *branch, sig_real *contribution)
{
    sig_real p;
    if (s == NULL || branch == NULL || contribution == NULL) return SIG_ERR_ARG;
    if (!sig_real_isfinite(t)) return SIG_ERR_NONFINITE;
    if (!s->primed) {
        p = t - (sig_real)s->start * s->width;
    } else {
        p = s->p;
        if (t - p > s->width) {
            p = t - s->width;
        } else if (p - t > s->width) {
            p = t + s->width;
        }
    }
    s->p = p;
    s->primed = true;
    *branch = t - p;
    *contribution = (t - p) * s->k;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */
