/* sig_chain_math.h - exact 32-bit helpers of the fixed-point weighing chain.
 *
 * No int64 and no division anywhere: a 32x32 product is built from four
 * 16x16 products (what the 8051 and the MSP430 hardware multiplier do
 * anyway), and the one division the chain needs (the anti-pulse mean, by a
 * divisor 1..30) is a reciprocal multiply plus one exact correction.
 * Each helper states the exact integer result it returns; the Python twin
 * (pysig/reference/chain.py) computes the same expression with Python ints.
 */
#ifndef SIG_CHAIN_MATH_H
#define SIG_CHAIN_MATH_H

#include "sig_types.h"

#define SIG_Q30_ONE UINT32_C(1073741824)

/* floor(a * b / 2^32), exact for all uint32 a, b. */
static inline uint32_t sig_mulhi_u32(uint32_t a, uint32_t b)
{
    uint32_t al = a & 0xFFFFu, ah = a >> 16, bl = b & 0xFFFFu, bh = b >> 16;
    uint32_t ll = al * bl, lh = al * bh, hl = ah * bl, hh = ah * bh;
    uint32_t mid = (ll >> 16) + (lh & 0xFFFFu) + (hl & 0xFFFFu);   /* < 3 * 2^16 */
    return hh + (lh >> 16) + (hl >> 16) + (mid >> 16);
}

/* floor((a * b + 2^29) / 2^30): a Q30 product rounded half up.  The caller
 * guarantees the result fits in 32 bits (a * b < 2^62 - 2^29). */
static inline uint32_t sig_mul_q30_u32(uint32_t a, uint32_t b)
{
    uint32_t al = a & 0xFFFFu, ah = a >> 16, bl = b & 0xFFFFu, bh = b >> 16;
    uint32_t ll = al * bl, lh = al * bh, hl = ah * bl, hh = ah * bh;
    uint32_t lo, hi, t;
    /* 64-bit product as hi:lo, each addition's carry propagated */
    lo = ll;
    hi = hh + (lh >> 16) + (hl >> 16);
    t = (lh & 0xFFFFu) << 16;
    lo += t; if (lo < t) hi++;
    t = (hl & 0xFFFFu) << 16;
    lo += t; if (lo < t) hi++;
    t = UINT32_C(0x20000000);                        /* + 2^29: round half up */
    lo += t; if (lo < t) hi++;
    return (hi << 2) | (lo >> 30);
}

/* Signed a times Q30 gain k (0 <= k <= 2^30), rounded half away from zero:
 * sign(a) * floor((|a| * k + 2^29) / 2^30).  |result| <= |a|. */
static inline int32_t sig_mul_q30_gain(int32_t a, uint32_t k)
{
    uint32_t mag = a < 0 ? (uint32_t)0 - (uint32_t)a : (uint32_t)a;
    uint32_t r = sig_mul_q30_u32(mag, k);
    if (a >= 0) return (int32_t)r;                   /* r <= |a| <= INT32_MAX */
    return r >= UINT32_C(0x80000000) ? INT32_MIN : -(int32_t)r;
}

/* floor(u / d) for u < 2^31 and 1 <= d <= 30, exactly, without dividing:
 * m = floor((2^32 - 1) / d) from the table; q0 = floor(u * m / 2^32) is
 * floor(u / d) or one less (u * m / 2^32 > u / d - 1 because u < 2^32), so
 * one correction makes it exact. */
static inline uint32_t sig_udiv_small(uint32_t u, uint8_t d, const uint32_t *recip)
{
    uint32_t q = sig_mulhi_u32(u, recip[d]);
    uint32_t r = u - q * (uint32_t)d;
    if (r >= (uint32_t)d) q++;
    return q;
}

/* round-half-up(s / d) = floor((s + floor(d / 2)) / d) for |s| < 2^30 and
 * 1 <= d <= 30, exact (Python: (s + d // 2) // d). */
static inline int32_t sig_div_round_small(int32_t s, uint8_t d, const uint32_t *recip)
{
    int32_t t = s + (int32_t)(d >> 1);
    if (t >= 0) return (int32_t)sig_udiv_small((uint32_t)t, d, recip);
    /* floor(t / d) = -floor((-t + d - 1) / d) for t < 0 */
    return -(int32_t)sig_udiv_small((uint32_t)(-t) + (uint32_t)d - 1u, d, recip);
}

#endif /* SIG_CHAIN_MATH_H */
