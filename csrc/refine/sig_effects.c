/* sig_effects.c - on-device forms of the refinement effects (sig_effects.h).
 *
 * Saturation convention: SIG_WARN_SATURATED is set whenever an
 * intermediate or output value equals an int32 rail (INT32_MIN or
 * INT32_MAX) after a saturating operation, whether or not the exact value
 * was beyond it: one cheap test, the same in the Python reference. */
#include "sig_effects.h"

static bool at_rail(int32_t v)
{
    return v == INT32_MAX || v == INT32_MIN;
}

static sig_status flag_rail(sig_status st, int32_t v)
{
    return at_rail(v) ? (sig_status)(st | SIG_WARN_SATURATED) : st;
}

/* floor((v + 2^(n-1)) / 2^n), v's rail flagged by the caller */
static int32_t round_shift(int32_t v, uint8_t n)
{
    if (n == 0u) return v;
    return sig_asr32(sig_sat_add32(v, (int32_t)(INT32_C(1) << (n - 1u))), n);
}

/* ---- first-order lag ---------------------------------------------------- */

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
    st = flag_rail(st, xs);
    if (!s->primed) {
        z = xs;
    } else {
        d = sig_sat_sub32(xs, s->z);
        st = flag_rail(st, d);
        z = sig_sat_add32(s->z, sig_mul_q16_sat(d, s->alpha_q16));
        st = flag_rail(st, z);
    }
    s->z = z;
    s->primed = true;
    *out = round_shift(z, s->frac);
    return st;
}

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

/* ---- hysteresis (play operator) ---------------------------------------------- */

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
    st = flag_rail(st, c);
    s->p = p;
    s->primed = true;
    *branch = (int16_t)b;
    *contribution = c;
    return st;
}

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

/* ---- creep ---------------------------------------------------------------------- */

sig_status sig_creep_init_q(sig_creep_q *s, int32_t alpha_q16, uint8_t frac, int32_t k_q16)
{
    sig_lag_q lag;
    if (s == NULL) return SIG_ERR_ARG;
    if (sig_lag_init_q(&lag, alpha_q16, frac) != SIG_OK) return SIG_ERR_ARG;
    s->lag = lag;
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
    st = flag_rail(st, d);
    v = sig_mul_q16_sat(d, s->k_q16);
    st = flag_rail(st, v);
    c = round_shift(v, s->lag.frac);
    y = sig_sat_sub32(x, c);
    st = flag_rail(st, y);
    *contribution = c;
    *corrected = y;
    return st;
}

sig_status sig_creep_init_f(sig_creep_f *s, sig_real alpha, sig_real k)
{
    sig_lag_f lag;
    if (s == NULL || !sig_real_isfinite(k)) return SIG_ERR_ARG;
    if (sig_lag_init_f(&lag, alpha) != SIG_OK) return SIG_ERR_ARG;
    s->lag = lag;
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

/* ---- gain drift -------------------------------------------------------------------- */

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
    return flag_rail(st, y);
}

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

/* ---- nonlinearity -------------------------------------------------------------------- */

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
    st = flag_rail(st, d);
    v = sig_mul_q16_sat(d, m->k_q16);
    st = flag_rail(st, v);
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
    return flag_rail(st, y);
}

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

/* ---- cross-axis ------------------------------------------------------------------------ */

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
        st = flag_rail(st, v);
        acc = sig_sat_add32(acc, v);
        st = flag_rail(st, acc);
    }
    y = sig_sat_sub32(x, acc);
    *out = y;
    return flag_rail(st, y);
}

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

/* ---- the refined temperature model of one axis ---------------------------------------- */

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

sig_status sig_refined_step_q(sig_refined_q *r, int16_t t, int16_t y, int32_t *out_q16)
{
    sig_status st = SIG_OK, s2;
    int32_t lagged, delta, d16, acc, c;
    int16_t tl = t, branch, u;
    uint8_t q;
    if (r == NULL || out_q16 == NULL || r->tcomp == NULL) return SIG_ERR_ARG;
    if (r->use_lag) {
        st = (sig_status)(st | sig_lag_step_q(&r->lag, (int32_t)t, &lagged));
        tl = sig_sat16(lagged);
    }
    s2 = sig_tcomp_delta_q(r->tcomp, r->axis, tl, &delta);
    if (s2 < 0) return s2;
    st = (sig_status)(st | s2);
    q = r->tcomp->q[r->axis];
    d16 = q >= 16u ? round_shift(delta, (uint8_t)(q - 16u)) : sig_shl32_sat(delta, (uint8_t)(16u - q));
    st = flag_rail(st, d16);
    acc = sig_sat_sub32((int32_t)y * SIG_Q16_ONE, d16);
    st = flag_rail(st, acc);
    if (r->use_hyst) {
        st = (sig_status)(st | sig_hyst_step_q(&r->hyst, tl, &branch, &c));
        acc = sig_sat_sub32(acc, c);
        st = flag_rail(st, acc);
    }
    if (r->use_gain) {
        s2 = sig_tcomp_scale_q(r->tcomp, tl, &u);
        if (s2 < 0) return s2;
        s2 = sig_gain_apply_q(&r->gain, u, acc, &acc);
        if (s2 < 0) return s2;
        st = (sig_status)(st | s2);
    }
    *out_q16 = acc;
    return st;
}
