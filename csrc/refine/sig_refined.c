/* sig_refined.c - the refined temperature model of one axis on the device
 * (lagged temperature, offset polynomial, hysteresis, gain); see sig_effects.h. */
#include "sig_effects.h"
#include "sig_effects_rail.h"

sig_status sig_refined_init_q(sig_refined_q *r, const sig_tcomp_q *tcomp, uint8_t axis,
                              const sig_lag_q *lag, const sig_hyst_q *hyst, const sig_gain_q *gain)
{
    if (r == NULL || tcomp == NULL || axis >= tcomp->n_axes) return SIG_ERR_ARG;
    if (lag != NULL && lag->frac != SIG_LAG_MAX_FRAC) return SIG_ERR_ARG;
    r->tcomp = tcomp;
    r->axis = axis;
    r->use_lag = lag != NULL;
    r->use_hyst = hyst != NULL;
    r->use_gain = gain != NULL;
    if (lag != NULL) r->lag = *lag;
    if (hyst != NULL) r->hyst = *hyst;
    if (gain != NULL) r->gain = *gain;
    return sig_refined_reset_q(r);
}

sig_status sig_refined_reset_q(sig_refined_q *r)
{
    if (r == NULL) return SIG_ERR_ARG;
    if (r->use_lag) (void)sig_lag_reset_q(&r->lag);
    if (r->use_hyst) (void)sig_hyst_reset_q(&r->hyst);
    return SIG_OK;
}

/* The lag and hysteresis step on copies, stored back only once every stage
 * has succeeded: an error return leaves the caller's state as it was. */
sig_status sig_refined_step_q(sig_refined_q *r, int16_t t, int16_t y, int32_t *out_q16)
{
    sig_status st = SIG_OK, s2;
    int32_t lagged, delta, d16, acc, c;
    int16_t tl = t, branch, u;
    uint8_t q;
    sig_lag_q lag;
    sig_hyst_q hyst;
    if (r == NULL || out_q16 == NULL || r->tcomp == NULL) return SIG_ERR_ARG;
    if (r->use_lag) {
        lag = r->lag;
        st = (sig_status)(st | sig_lag_step_q(&lag, (int32_t)t, &lagged));
        tl = sig_sat16(lagged);
    }
    s2 = sig_tcomp_delta_q(r->tcomp, r->axis, tl, &delta);
    if (s2 < 0) return s2;
    st = (sig_status)(st | s2);
    q = r->tcomp->q[r->axis];
    d16 = q >= 16u ? sig_round_shift(delta, (uint8_t)(q - 16u)) : sig_shl32_sat(delta, (uint8_t)(16u - q));
    st = sig_flag_rail(st, d16);
    acc = sig_sat_sub32((int32_t)y * SIG_Q16_ONE, d16);
    st = sig_flag_rail(st, acc);
    if (r->use_hyst) {
        hyst = r->hyst;
        st = (sig_status)(st | sig_hyst_step_q(&hyst, tl, &branch, &c));
        acc = sig_sat_sub32(acc, c);
        st = sig_flag_rail(st, acc);
    }
    if (r->use_gain) {
        s2 = sig_tcomp_scale_q(r->tcomp, tl, &u);
        if (s2 < 0) return s2;
        s2 = sig_gain_apply_q(&r->gain, u, acc, &acc);
        if (s2 < 0) return s2;
        st = (sig_status)(st | s2);
    }
    if (r->use_lag) r->lag = lag;
    if (r->use_hyst) r->hyst = hyst;
    *out_q16 = acc;
    return st;
}
