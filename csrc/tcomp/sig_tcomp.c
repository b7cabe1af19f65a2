/* sig_tcomp.c - temperature compensation by a polynomial offset model, fixed
 * point and float (sig_tcomp.h), and its coefficient-image section. */
#include "sig_tcomp.h"
#include "sig_image.h"

/* floor(x / 2^16) for any int32 x, by selecting the high word of x + 2^31
 * (unsigned: no shift of a negative value, no signed overflow). */
static int32_t floor_div_2p16(int32_t x)
{
    return (int32_t)(((uint32_t)x + UINT32_C(0x80000000)) >> 16) - INT32_C(32768);
}

/* u for a temperature already inside the range (|t - t_center| <= 32767):
 * floor((d * u_mul32 + 2^15) / 2^16) = d * Mh + floor((d * Ml + 2^15) / 2^16)
 * with u_mul32 = Mh * 2^16 + Ml, which equals the documented
 * floor((d * u_mul + 2^(u_shift-1)) / 2^u_shift) because
 * u_mul32 = u_mul * 2^(16 - u_shift).  Two 16x16 products, no shift loop. */
static int16_t scale_in_range(const sig_tcomp_q *m, int16_t t)
{
    int16_t d = (int16_t)((int32_t)t - (int32_t)m->t_center);
    int32_t hi = (int32_t)d * (int32_t)(m->u_mul32 >> 16);
    int32_t lo = (int32_t)d * (int32_t)(m->u_mul32 & INT32_C(0xFFFF)) + INT32_C(32768);
    return (int16_t)(hi + floor_div_2p16(lo));
}

static int32_t scale_wide(int32_t d, int16_t u_mul, uint8_t u_shift)
{
    int32_t prod = d * (int32_t)u_mul;
    if (u_shift > 0u) prod += (int32_t)1 << (u_shift - 1u);
    return sig_asr32(prod, u_shift);
}

/* floor(acc * u / 2^15), |u| <= 32767, exact (as sig_mul_q15_32x16):
 * acc = hi * 2^16 + lo, lo in [0, 65535]; x = hi * u; y = lo * u;
 * floor(acc*u / 2^15) = 2 * (x + floor(y / 2^16)) + bit 15 of y. */
static int32_t mul_q15_fast(int32_t acc, int16_t u)
{
    int32_t hi = floor_div_2p16(acc);
    int32_t lo = (int32_t)((uint32_t)acc & UINT32_C(0xFFFF));
    int32_t x = hi * (int32_t)u;
    int32_t y = lo * (int32_t)u;
    return 2 * (x + floor_div_2p16(y)) + (((uint32_t)y & UINT32_C(0x8000)) != 0u ? 1 : 0);
}

/* delta(u) of one axis.  When init proved that no partial sum can leave
 * int32 (m->no_overflow) the additions are plain; otherwise they saturate
 * (sig_poly_horner_q15).  Both give the same value when nothing saturates. */
static sig_status axis_delta(const sig_tcomp_q *m, const int32_t *c, int16_t u, int32_t *delta)
{
    int32_t acc;
    uint8_t k;
    if (!m->no_overflow) return sig_poly_horner_q15(c, m->order, u, delta);
    acc = c[m->order];
    for (k = m->order; k > 0u; k--) acc = c[k - 1u] + mul_q15_fast(acc, u);
    *delta = acc;
    return SIG_OK;
}

/* floor((delta + 2^(q-1)) / 2^q): for q >= 16 a high-word select and a
 * 16-bit shift, no 32-bit shift loop. */
static int32_t round_shift(const sig_tcomp_q *m, uint8_t q, int32_t q_round, int32_t delta)
{
    int16_t h;
    if (m->no_overflow) delta += q_round;
    else delta = sig_sat_add32(delta, q_round);
    if (q < 16u) return sig_asr32(delta, q);
    h = (int16_t)floor_div_2p16(delta);
    q = (uint8_t)(q - 16u);
    return h >= 0 ? (int32_t)(h >> q) : (int32_t)~((int16_t)~h >> q);
}

/* Sum over axes of |c_k| + order + 2^(q-1) <= INT32_MAX: then no Horner
 * partial sum (bounded by the suffix sums of |c_k| plus one floor per step)
 * and no rounding add can overflow. */
static bool cannot_overflow(const sig_tcomp_q *m)
{
    uint8_t a, k;
    int32_t sum;
    for (a = 0; a < m->n_axes; a++) {
        sum = sig_sat_add32((int32_t)m->order, m->q_round[a]);
        for (k = 0; k <= m->order; k++) sum = sig_sat_add32(sum, sig_abs32_sat(m->coef[a][k]));
        if (sum == INT32_MAX) return false;
    }
    return true;
}

/* Axis-major coef[n_axes][order + 1] into the fixed-size table, zero-filled.
 * A walking pointer keeps few values live (sdcc spills to internal RAM). */
static void copy_coef_q(sig_tcomp_q *m, uint8_t n_axes, uint8_t order, const int32_t *src)
{
    uint8_t a, k;
    int32_t *dst;
    for (a = 0; a < SIG_TCOMP_MAX_AXES; a++) {
        dst = m->coef[a];
        for (k = 0; k <= SIG_TCOMP_MAX_ORDER; k++) dst[k] = 0;
        if (a < n_axes)
            for (k = 0; k <= order; k++) dst[k] = *src++;
    }
}

/* The checks of sig_tcomp_init_q that do not depend on the coefficients. */
static sig_status check_params(uint8_t n_axes, uint8_t order, int16_t t_lo, int16_t t_hi,
                               int16_t t_center, int16_t u_mul, uint8_t u_shift)
{
    int32_t d_hi, d_lo;
    if (n_axes < 1u || n_axes > SIG_TCOMP_MAX_AXES) return SIG_ERR_ARG;
    if (order < SIG_TCOMP_MIN_ORDER || order > SIG_TCOMP_MAX_ORDER) return SIG_ERR_ARG;
    if (t_lo >= t_hi || t_center < t_lo || t_center > t_hi) return SIG_ERR_ARG;
    if (u_mul <= 0 || u_shift > SIG_TCOMP_MAX_U_SHIFT) return SIG_ERR_ARG;
    d_hi = (int32_t)t_hi - (int32_t)t_center;
    d_lo = (int32_t)t_lo - (int32_t)t_center;
    if (d_hi > INT16_MAX || d_lo < -(int32_t)INT16_MAX) return SIG_ERR_ARG;
    if (scale_wide(d_hi, u_mul, u_shift) > INT16_MAX ||
        scale_wide(d_lo, u_mul, u_shift) < -(int32_t)INT16_MAX)
        return SIG_ERR_ARG;
    return SIG_OK;
}

/* Everything but the coefficients (already in m->coef) and q (in m->q). */
static void store_params(sig_tcomp_q *m, uint8_t n_axes, uint8_t order, int16_t t_lo, int16_t t_hi,
                         int16_t t_center, int16_t t0, int16_t u_mul, uint8_t u_shift)
{
    uint8_t a;
    for (a = 0; a < SIG_TCOMP_MAX_AXES; a++) {
        if (a >= n_axes) m->q[a] = 0u;
        m->q_round[a] = m->q[a] > 0u ? (int32_t)1 << (m->q[a] - 1u) : 0;
    }
    m->u_mul32 = (int32_t)u_mul << (16u - u_shift);
    m->t_lo = t_lo;
    m->t_hi = t_hi;
    m->t_center = t_center;
    m->t0 = t0;
    m->u_mul = u_mul;
    m->u_shift = u_shift;
    m->order = order;
    m->n_axes = n_axes;
    m->no_overflow = cannot_overflow(m);
}

sig_status sig_tcomp_init_q(sig_tcomp_q *m, uint8_t n_axes, uint8_t order,
                            const int32_t *coef, const uint8_t *q,
                            int16_t t_lo, int16_t t_hi, int16_t t_center, int16_t t0,
                            int16_t u_mul, uint8_t u_shift)
{
    uint8_t a;
    if (m == NULL || coef == NULL || q == NULL) return SIG_ERR_ARG;
    if (check_params(n_axes, order, t_lo, t_hi, t_center, u_mul, u_shift) != SIG_OK) return SIG_ERR_ARG;
    for (a = 0; a < n_axes; a++)
        if (q[a] > SIG_TCOMP_MAX_Q) return SIG_ERR_ARG;
    copy_coef_q(m, n_axes, order, coef);
    for (a = 0; a < n_axes; a++) m->q[a] = q[a];
    store_params(m, n_axes, order, t_lo, t_hi, t_center, t0, u_mul, u_shift);
    return SIG_OK;
}

sig_status sig_tcomp_scale_q(const sig_tcomp_q *m, int16_t t, int16_t *u_q15)
{
    sig_status st;
    if (m == NULL || u_q15 == NULL) return SIG_ERR_ARG;
    st = sig_clamp_i16(&t, m->t_lo, m->t_hi);
    *u_q15 = scale_in_range(m, t);
    return st;
}

sig_status sig_tcomp_delta_q(const sig_tcomp_q *m, uint8_t axis, int16_t t, int32_t *delta)
{
    sig_status st, st_poly;
    int16_t u;
    int32_t value;
    if (m == NULL || delta == NULL || axis >= m->n_axes) return SIG_ERR_ARG;
    st = sig_tcomp_scale_q(m, t, &u);
    st_poly = axis_delta(m, m->coef[axis], u, &value);
    if (st_poly < 0) return st_poly;
    *delta = value;
    return (sig_status)(st | st_poly);
}

sig_status sig_tcomp_apply_q(const sig_tcomp_q *m, int16_t t, const int16_t *in, int16_t *out)
{
    sig_status st;
    int16_t u;
    int32_t delta, corrected;
    uint8_t a;
    if (m == NULL || in == NULL || out == NULL) return SIG_ERR_ARG;
    st = sig_tcomp_scale_q(m, t, &u);
    for (a = 0; a < m->n_axes; a++) {
        /* each row through its own index: a pointer stepped from coef[0]
         * into the next row leaves its array (C99 6.5.6p8) */
        st = (sig_status)(st | axis_delta(m, m->coef[a], u, &delta));   /* never an error after init */
        delta = round_shift(m, m->q[a], m->q_round[a], delta);
        corrected = sig_sat_sub32((int32_t)in[a], delta);
        if (corrected > INT16_MAX || corrected < INT16_MIN) st = (sig_status)(st | SIG_WARN_SATURATED);
        out[a] = sig_sat16(corrected);
    }
    return st;
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_tcomp_init_f(sig_tcomp_f *m, uint8_t n_axes, uint8_t order, const sig_real *coef,
                            sig_real t_lo, sig_real t_hi, sig_real center, sig_real inv_scale)
{
    uint8_t a, k;
    sig_real *dst;
    if (m == NULL || coef == NULL) return SIG_ERR_ARG;
    if (n_axes < 1u || n_axes > SIG_TCOMP_MAX_AXES) return SIG_ERR_ARG;
    if (order < SIG_TCOMP_MIN_ORDER || order > SIG_TCOMP_MAX_ORDER) return SIG_ERR_ARG;
    if (!sig_real_isfinite(t_lo) || !sig_real_isfinite(t_hi) || !sig_real_isfinite(center) || !sig_real_isfinite(inv_scale))
        return SIG_ERR_NONFINITE;
    if (!(t_lo < t_hi) || center < t_lo || center > t_hi || !(inv_scale > SIG_REAL(0.0)))
        return SIG_ERR_ARG;
    if (!sig_real_all_finite(coef, (uint16_t)(n_axes * (order + 1u)))) return SIG_ERR_NONFINITE;
    for (a = 0; a < SIG_TCOMP_MAX_AXES; a++) {
        dst = m->coef[a];
        for (k = 0; k <= SIG_TCOMP_MAX_ORDER; k++) dst[k] = SIG_REAL(0.0);
        if (a < n_axes)
            for (k = 0; k <= order; k++) dst[k] = *coef++;
    }
    m->t_lo = t_lo;
    m->t_hi = t_hi;
    m->center = center;
    m->inv_scale = inv_scale;
    m->order = order;
    m->n_axes = n_axes;
    return SIG_OK;
}

sig_status sig_tcomp_apply_f(const sig_tcomp_f *m, sig_real t, const sig_real *in, sig_real *out)
{
    sig_status st, st_poly;
    sig_real u, delta[SIG_TCOMP_MAX_AXES];
    uint8_t a;
    if (m == NULL || in == NULL || out == NULL) return SIG_ERR_ARG;
    if (sig_real_isnan(t)) return SIG_ERR_NONFINITE;   /* +-inf clamps */
    if (!sig_real_all_finite(in, m->n_axes)) return SIG_ERR_NONFINITE;
    st = sig_clamp_real(&t, m->t_lo, m->t_hi);
    u = (t - m->center) * m->inv_scale;
    for (a = 0; a < m->n_axes; a++) {
        st_poly = sig_poly_horner_f(m->coef[a], m->order, u, &delta[a]);
        if (st_poly < 0) return st_poly;
    }
    for (a = 0; a < m->n_axes; a++) out[a] = in[a] - delta[a];
    return st;
}
#endif /* SIG_NO_FLOAT */

sig_status sig_tcomp_load_image(sig_tcomp_q *m, const uint8_t *image, size_t len)
{
    /* Checked in full before anything is written, then parsed straight into
     * *m: no copy of the coefficients on the stack (the 8051's is small). */
    const uint8_t *p;
    uint16_t plen, pos, stride;
    uint8_t n_axes, order, a, k;
    int32_t *dst;
    sig_status st;
    if (m == NULL) return SIG_ERR_ARG;
    st = sig_image_find_section(image, len, SIG_SECTION_OFFSET_POLY, &p, &plen);
    if (st != SIG_OK) return st;
    if (plen < SIG_OFFSET_POLY_FIXED_LEN) return SIG_ERR_FORMAT;
    n_axes = p[0];
    order = p[1];
    if (n_axes < 1u || n_axes > SIG_TCOMP_MAX_AXES || order < SIG_TCOMP_MIN_ORDER ||
        order > SIG_TCOMP_MAX_ORDER || p[3] != 0u)
        return SIG_ERR_FORMAT;
    stride = (uint16_t)(1u + 4u * (uint16_t)(order + 1u));
    if (plen != (uint16_t)(SIG_OFFSET_POLY_FIXED_LEN + (uint16_t)n_axes * stride))
        return SIG_ERR_FORMAT;
    if (check_params(n_axes, order, sig_image_get_i16(p + 4), sig_image_get_i16(p + 6),
                     sig_image_get_i16(p + 8), sig_image_get_i16(p + 12), p[2]) != SIG_OK)
        return SIG_ERR_FORMAT;
    for (a = 0; a < n_axes; a++)
        if (p[SIG_OFFSET_POLY_FIXED_LEN + (uint16_t)a * stride] > SIG_TCOMP_MAX_Q) return SIG_ERR_FORMAT;
    for (a = 0; a < SIG_TCOMP_MAX_AXES; a++) {
        dst = m->coef[a];
        for (k = 0; k <= SIG_TCOMP_MAX_ORDER; k++) dst[k] = 0;
        if (a >= n_axes) continue;
        pos = (uint16_t)(SIG_OFFSET_POLY_FIXED_LEN + (uint16_t)a * stride);
        m->q[a] = p[pos++];
        for (k = 0; k <= order; k++, pos = (uint16_t)(pos + 4u)) dst[k] = sig_image_get_i32(p + pos);
    }
    store_params(m, n_axes, order, sig_image_get_i16(p + 4), sig_image_get_i16(p + 6),
                 sig_image_get_i16(p + 8), sig_image_get_i16(p + 10), sig_image_get_i16(p + 12), p[2]);
    return SIG_OK;
}
