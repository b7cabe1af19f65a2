/* sig_tcomp16.c - compact fixed-point temperature compensation (sig_tcomp16.h). */
#include "sig_tcomp16.h"
#include "sig_port.h"

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

/* One axis of the coefficient stream: top, then the level constants in
 * evaluation order as (low, high) words.  Offset binary (+2^15 / +2^31)
 * everywhere except the input of the last level: top when order == 1, the
 * constant of the last inner level (add_1) otherwise.  Order 1 also holds
 * top * 2^15 in add_0 (its abscissa is v - 2^15, see LAST_LEVEL). */
static void store_axis(uint16_t *p, int16_t top, const int32_t *add, uint8_t order)
{
    uint32_t c;
    uint8_t k;
    *p++ = order > 1u ? (uint16_t)((uint16_t)top ^ OFFSET16) : (uint16_t)top;
    for (k = 0; k < order; k++) {
        c = (uint32_t)add[k];
        if (k + 2u != order) c += OFFSET32;
        if (order == 1u) c += (uint32_t)sig_port_s16((uint16_t)top) << 15;
        *p++ = (uint16_t)c;
        *p++ = (uint16_t)(c >> 16);
    }
}

sig_status sig_tcomp16_init(sig_tcomp16_q *m, uint8_t n_axes, uint8_t order,
                            const int16_t *top, const int32_t *add,
                            int16_t t_lo, int16_t t_hi, uint8_t w_shift)
{
    uint32_t v_max, w_max;
    uint8_t a;
    if (m == NULL || top == NULL || add == NULL) return SIG_ERR_ARG;
    if (n_axes < 1u || n_axes > SIG_TCOMP16_MAX_AXES) return SIG_ERR_ARG;
    if (order < SIG_TCOMP16_MIN_ORDER || order > SIG_TCOMP16_MAX_ORDER) return SIG_ERR_ARG;
    if (t_lo >= t_hi || w_shift > 15u || (order > 1u && w_shift < 1u)) return SIG_ERR_ARG;
    v_max = (uint32_t)((int32_t)t_hi - (int32_t)t_lo);
    w_max = v_max << w_shift;
    if (w_max > UINT32_C(0xFFFF)) return SIG_ERR_ARG;
    for (a = 0; a < n_axes; a++)
        if (!axis_fits(top[a], add + (uint16_t)a * order, order, v_max, w_max)) return SIG_ERR_ARG;
    for (a = 0; a < n_axes; a++)          /* packed stream, see sig_tcomp16_q */
        store_axis(m->coef + (uint16_t)a * (1u + 2u * order), top[a],
                   add + (uint16_t)a * order, order);
    m->t_lo = t_lo;
    m->t_hi = t_hi;
    m->w_shift = w_shift;
    m->order = order;
    m->n_axes = n_axes;
    return SIG_OK;
}

/* One inner Horner level: U' = high word of U * w + A - w/2, with U = h + 2^15
 * (offset binary, so the product is unsigned) and A = add_k + 2^31: since w
 * is even, the 2^15 * w of the offset is 2^16 * (w/2), all in the high word.
 * The last inner level stores A = add_1 without the 2^31 and so yields h_1
 * itself (two's-complement bits) for the signed last level. */
#define INNER_LEVEL(u, w, w_half, c) \
    ((uint16_t)(SIG_MULADD_HI_U16((u), (w), (c)) - (w_half)))

/* The last level: u = corr + 2^15 = high word of h * x + A_0, a signed 16x16
 * product.  order >= 2: x = v (<= 32767: w = v * 2^w_shift <= 65535 with
 * w_shift >= 1), h = h_1, A_0 = add_0 + 2^31.  order 1 (v up to 65535):
 * x = v - 2^15 (int16), h = top, and init stored A_0 = add_0 + 2^31 +
 * top * 2^15 (mod 2^32). */
#define LAST_LEVEL(h, x, c) SIG_MULADD_HI_S16((h), (x), (c))

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
    const uint16_t *p;
    uint16_t v, w, w_half, x, u;
    const int16_t *in_end;
    uint16_t k, n_inner;
    if (m == NULL || in == NULL || out == NULL) return SIG_ERR_ARG;
    v = (uint16_t)((uint16_t)t - (uint16_t)m->t_lo);        /* 0 .. t_hi - t_lo, exact */
    if (t < m->t_lo) { v = 0; st = SIG_WARN_CLAMPED; }
    else if (t > m->t_hi) { v = (uint16_t)((uint16_t)m->t_hi - (uint16_t)m->t_lo); st = SIG_WARN_CLAMPED; }
    w = (uint16_t)(v << m->w_shift);                        /* init: fits, and even when used */
    w_half = (uint16_t)(w >> 1);
    x = m->order > 1u ? v : (uint16_t)(v ^ 0x8000u);       /* int16 bits */
    p = m->coef;
    n_inner = (uint16_t)(m->order - 1u);
    in_end = in + m->n_axes;
    while (in != in_end) {
        u = *p++;
        for (k = n_inner; k != 0u; k--, p += 2)
            u = INNER_LEVEL(u, w, w_half, p);
        u = LAST_LEVEL(u, x, p);                            /* corr + 2^15 */
        p += 2;
        *out++ = subtract_sat(*in++, u, &st);
    }
    return st;
}
