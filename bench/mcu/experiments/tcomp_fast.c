/* tcomp_fast.c - EXPERIMENT, not project code: what sig_tcomp_apply_q would
 * cost on the MSP430 written for the target.  Same model struct, same
 * results bit for bit (tests/test_mcu_sim.py checks it against the host C
 * and the Python reference); only the arithmetic is spelt differently:
 *
 *  1. every product is a 16x16 one, through MUL16S(): on the MSP430 an
 *     inline access to the multiplier registers (no helper call), elsewhere
 *     the portable product;
 *  2. floor(acc * u / 2^15) = 2*hi*u + 2*hi(lo*u) + bit15(lo*u): word
 *     moves, no 32-bit shift by 15;
 *  3. no 32-bit shift by a variable count (u_shift, q): the shifts are done
 *     on 16-bit words, whose variable shifts clang inlines;
 *  4. saturating adds test the sign bits of the wrapped sum.
 *
 * A csrc/ change along these lines (a SIG_MUL16S hook in sig_types.h that a
 * firmware build may map to the multiplier, and word-wise shifts in
 * sig_tcomp.c / sig_poly.c) is what bench/mcu_cost.py measures here. */
#include <stdint.h>
#include "sig_tcomp.h"
#include "tcomp_fast.h"

#if defined(__MSP430__) && defined(TCOMP_FAST_MPY_BASE)
#define MPY_REG(off) (*(volatile uint16_t *)(TCOMP_FAST_MPY_BASE + (off)))
static inline int32_t mul16s(int16_t a, int16_t b)
{
    MPY_REG(0x2) = (uint16_t)a;          /* MPYS */
    MPY_REG(0x8) = (uint16_t)b;          /* OP2: starts the product */
    return (int32_t)(((uint32_t)MPY_REG(0xC) << 16) | MPY_REG(0xA));
}
#else
static inline int32_t mul16s(int16_t a, int16_t b) { return (int32_t)a * (int32_t)b; }
#endif

static inline int16_t as_i16(uint16_t w) { return (int16_t)(w >= 0x8000u ? (int32_t)w - 65536 : (int32_t)w); }

/* floor(w / 2^n) of a signed 16-bit value, 0 <= n <= 15, no shift of a negative */
static inline int16_t asr16(int16_t w, uint8_t n)
{
    return w >= 0 ? (int16_t)((uint16_t)w >> n) : (int16_t)~(int16_t)((uint16_t)~w >> n);
}

/* floor(x / 2^n), 0 <= n <= 31, on 16-bit words */
static int32_t asr32_words(int32_t x, uint8_t n)
{
    uint16_t lo = (uint16_t)x, hi = (uint16_t)((uint32_t)x >> 16);
    int16_t shi = as_i16(hi);
    if (n == 0u) return x;
    if (n >= 16u) return (int32_t)asr16(shi, (uint8_t)(n - 16u));
    lo = (uint16_t)((lo >> n) | (uint16_t)(hi << (16u - n)));
    return (int32_t)(((uint32_t)(uint16_t)asr16(shi, n) << 16) | lo);
}

/* 2^n as int32 for 0 <= n <= 30, without a variable 32-bit shift */
static inline int32_t pow2(uint8_t n)
{
    return n >= 16u ? (int32_t)((uint32_t)(uint16_t)(1u << (n - 16u)) << 16) : (int32_t)(1u << n);
}

static inline int32_t sat_add(int32_t a, int32_t b, bool *sat)
{
    uint32_t s = (uint32_t)a + (uint32_t)b;
    if ((((s ^ (uint32_t)a) & (s ^ (uint32_t)b)) & UINT32_C(0x80000000)) != 0u) {
        *sat = true;
        return a < 0 ? INT32_MIN : INT32_MAX;
    }
    return (int32_t)(s >= UINT32_C(0x80000000) ? -(int32_t)(~s) - 1 : (int32_t)s);
}

static inline int32_t sat_sub(int32_t a, int32_t b)
{
    uint32_t s = (uint32_t)a - (uint32_t)b;
    if ((((uint32_t)a ^ (uint32_t)b) & ((uint32_t)a ^ s) & UINT32_C(0x80000000)) != 0u)
        return a < 0 ? INT32_MIN : INT32_MAX;
    return (int32_t)(s >= UINT32_C(0x80000000) ? -(int32_t)(~s) - 1 : (int32_t)s);
}

/* floor(a * u / 2^15), |u| <= 32767: identical to sig_mul_q15_32x16 */
static inline int32_t mul_q15(int32_t a, int16_t u)
{
    uint16_t lo = (uint16_t)a, hi = (uint16_t)((uint32_t)a >> 16);
    int32_t p1 = mul16s(as_i16(hi), u);
    int32_t p0 = mul16s(as_i16(lo), u);            /* lo taken as signed ... */
    uint16_t p0lo = (uint16_t)p0, p0hi = (uint16_t)((uint32_t)p0 >> 16);
    if (lo & 0x8000u) p0hi = (uint16_t)(p0hi + (uint16_t)u);   /* ... corrected: lo*u */
    return 2 * p1 + 2 * (int32_t)as_i16(p0hi) + (int32_t)(p0lo >> 15);
}

sig_status tcomp_fast_apply_q(const sig_tcomp_q *m, int16_t t, const int16_t *in, int16_t *out)
{
    sig_status st = SIG_OK;
    bool sat = false;
    int16_t u;
    int32_t prod, acc, corrected;
    uint8_t a, k, q;
    if (m == NULL || in == NULL || out == NULL) return SIG_ERR_ARG;
    if (t < m->t_lo) { t = m->t_lo; st = SIG_WARN_CLAMPED; }
    else if (t > m->t_hi) { t = m->t_hi; st = SIG_WARN_CLAMPED; }
    prod = mul16s((int16_t)((int32_t)t - (int32_t)m->t_center), m->u_mul);
    if (m->u_shift > 0u) prod += pow2((uint8_t)(m->u_shift - 1u));
    u = (int16_t)asr32_words(prod, m->u_shift);
    if (u == INT16_MIN) u = (int16_t)-INT16_MAX;
    for (a = 0; a < m->n_axes; a++) {
        const int32_t *c = m->coef[a];
        bool s = false;
        acc = c[m->order];
        for (k = m->order; k > 0u; k--) acc = sat_add(c[k - 1u], mul_q15(acc, u), &s);
        if (s) sat = true;
        q = m->q[a];
        if (q > 0u) {
            bool ignore = false;
            acc = asr32_words(sat_add(acc, pow2((uint8_t)(q - 1u)), &ignore), q);
        }
        corrected = sat_sub((int32_t)in[a], acc);
        if (corrected > INT16_MAX) { out[a] = INT16_MAX; sat = true; }
        else if (corrected < INT16_MIN) { out[a] = INT16_MIN; sat = true; }
        else out[a] = (int16_t)corrected;
    }
    return (sig_status)(st | (sat ? SIG_WARN_SATURATED : 0));
}
