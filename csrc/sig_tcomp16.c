/* sig_tcomp16.c - compact fixed-point temperature compensation (sig_tcomp16.h). */
#include "sig_tcomp16.h"

#define OFFSET16 UINT16_C(0x8000)
#define OFFSET32 UINT32_C(0x80000000)

static uint32_t magnitude32(int32_t x)
{
    return x < 0 ? (uint32_t)0 - (uint32_t)x : (uint32_t)x;
}

/* The bound of the header comment, for one axis: b bounds |h| level by level
 * (b * w_max <= 32768 * 65535 and + |add| <= 2^31 never wrap a uint32). */
static bool axis_fits(int16_t top, const int32_t *add, uint8_t order, uint32_t v_max, uint32_t w_max)
{
    uint32_t b = magnitude32((int32_t)top), x;
    uint8_t k;
    for (k = 0; k + 1u < order; k++) {
        x = b * w_max + magnitude32(add[k]);
        if (x > (uint32_t)INT32_MAX) return false;
        b = (x + UINT32_C(0xFFFF)) >> 16;          /* ceil: |floor(x / 2^16)| <= b */
        if (b > UINT32_C(32767)) return false;
    }
    x = b * v_max + magnitude32(add[order - 1u]);
    return x <= (uint32_t)INT32_MAX;
}

sig_status sig_tcomp16_init(sig_tcomp16_q *m, uint8_t n_axes, uint8_t order,
                            const int16_t *top, const int32_t *add,
                            int16_t t_lo, int16_t t_hi, uint8_t w_shift)
{
    uint32_t v_max, w_max;
    uint8_t a, k;
    if (m == NULL || top == NULL || add == NULL) return SIG_ERR_ARG;
    if (n_axes < 1u || n_axes > SIG_TCOMP16_MAX_AXES) return SIG_ERR_ARG;
    if (order < SIG_TCOMP16_MIN_ORDER || order > SIG_TCOMP16_MAX_ORDER) return SIG_ERR_ARG;
    if (t_lo >= t_hi || w_shift > 15u || (order > 1u && w_shift < 1u)) return SIG_ERR_ARG;
    v_max = (uint32_t)((int32_t)t_hi - (int32_t)t_lo);
    w_max = v_max << w_shift;
    if (w_max > UINT32_C(0xFFFF)) return SIG_ERR_ARG;
    for (a = 0; a < n_axes; a++)
        if (!axis_fits(top[a], add + (uint16_t)a * order, order, v_max, w_max)) return SIG_ERR_ARG;
    for (a = 0; a < SIG_TCOMP16_MAX_AXES; a++) {
        m->top[a] = a < n_axes ? (uint16_t)((uint16_t)top[a] ^ OFFSET16) : OFFSET16;
        for (k = 0; k < SIG_TCOMP16_MAX_ORDER; k++)
            m->add[a][k] = (a < n_axes && k < order)
                ? (uint32_t)add[(uint16_t)a * order + k] + OFFSET32 : OFFSET32;
    }
    m->t_lo = t_lo;
    m->t_hi = t_hi;
    m->w_shift = w_shift;
    m->order = order;
    m->n_axes = n_axes;
    return SIG_OK;
}

/* High word of U * x - 2^15 * x + add (mod 2^32) for an even x, i.e.
 * U' = h' + 2^15 for h' = floor((h * x + add) / 2^16), h = U - 2^15 (add is
 * stored + 2^31).  For even x, 2^15 * x = 2^16 * (x >> 1) only touches the
 * high word: x_half is subtracted after the shift.  Kept apart so that the
 * compiler cannot fold U * x - 2^15 * x back into a signed product (clang 14
 * turns that into a full 32x32 multiply). */
static uint16_t level(uint16_t u, uint16_t x, uint16_t x_half, uint32_t add)
{
    return (uint16_t)((uint16_t)(((uint32_t)u * x + add) >> 16) - x_half);
}

/* level() for x = v, which may be odd: the high word of P - 2^15 v with
 * P = U * v + add and 2^15 v = 2^16 (v >> 1) + v_odd, i.e. hi(P) - (v >> 1)
 * less the borrow of lo(P) - v_odd. */
static uint16_t last_level(uint16_t u, uint16_t v, uint16_t v_odd, uint32_t add)
{
    uint32_t p = (uint32_t)u * v + add;
    uint16_t r = (uint16_t)((uint16_t)(p >> 16) - (uint16_t)(v >> 1));
    if ((uint16_t)p < v_odd) r--;
    return r;
}

/* in - corr for in and corr + 2^15 = u, saturated: the difference of two
 * offset values, in 16 bits (an int32 difference costs twice the code on a
 * 16-bit CPU).  *st gets SIG_WARN_SATURATED at a rail. */
static int16_t subtract_sat(int16_t in, uint16_t u, sig_status *st)
{
    uint16_t in_off = (uint16_t)((uint16_t)in ^ 0x8000u);
    uint16_t d;
    if (in_off >= u) {                          /* in - corr >= 0 */
        d = (uint16_t)(in_off - u);
        if (d <= 0x7FFFu) return (int16_t)d;
        *st = (sig_status)(*st | SIG_WARN_SATURATED);
        return INT16_MAX;
    }
    d = (uint16_t)(u - in_off);                 /* corr - in > 0 */
    if (d <= 0x8000u) return (int16_t)(-(int16_t)(d - 1u) - 1);
    *st = (sig_status)(*st | SIG_WARN_SATURATED);
    return INT16_MIN;
}

sig_status sig_tcomp16_apply_q(const sig_tcomp16_q *m, int16_t t, const int16_t *in, int16_t *out)
{
    sig_status st = SIG_OK;
    uint16_t v, w, u, v_odd;
    const uint32_t *c;
    const uint16_t *top;
    uint8_t a, k;
    if (m == NULL || in == NULL || out == NULL) return SIG_ERR_ARG;
    if (t < m->t_lo) { t = m->t_lo; st = SIG_WARN_CLAMPED; }
    else if (t > m->t_hi) { t = m->t_hi; st = SIG_WARN_CLAMPED; }
    v = (uint16_t)((uint16_t)t - (uint16_t)m->t_lo);        /* 0 .. t_hi - t_lo, exact */
    w = (uint16_t)(v << m->w_shift);                        /* init: fits, and even when used */
    v_odd = (uint16_t)((uint16_t)(0u - (v & 1u)) & 0x8000u);   /* 2^15 (v & 1), no shift loop */
    c = &m->add[0][0];
    top = m->top;
    for (a = m->n_axes; a > 0u; a--) {
        u = *top++;
        for (k = m->order; k > 1u; k--)                     /* w even: no odd part */
            u = level(u, w, (uint16_t)(w >> 1), *c++);
        u = last_level(u, v, v_odd, *c);                    /* corr + 2^15 */
        c += SIG_TCOMP16_MAX_ORDER + 1u - m->order;
        *out++ = subtract_sat(*in++, u, &st);
    }
    return st;
}
