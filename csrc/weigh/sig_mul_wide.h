/* sig_mul_wide.h - the exact 32x32 -> 64-bit unsigned product of the fixed
 * chain (anti-pulse mean, Kalman gain), without int64.
 *
 * A static function in a header, on purpose: each of the two files that use
 * it keeps its own copy, as a plain (non-inline) static function, which is
 * what keeps sdcc's 8051 stack and spill RAM small (see sig_types.h); the
 * source exists once.  Include it only where it is called. */
#ifndef SIG_MUL_WIDE_H
#define SIG_MUL_WIDE_H

#include <stdint.h>

/* a * b = hi * 2^32 + lo from four 16x16 products, with few temporaries;
 * returns hi and stores lo. */
static uint32_t sig_mul_wide(uint32_t a, uint32_t b, uint32_t *lo_out)
{
    /* 16-bit halves first: sdcc 4.2 --stack-auto miscompiles (a >> 16) * x
     * of a stack parameter (the high byte of a >> 16 came out as byte 2) */
    uint16_t a0 = (uint16_t)a, a1 = (uint16_t)(a >> 16);
    uint16_t b0 = (uint16_t)b, b1 = (uint16_t)(b >> 16);
    uint32_t lo = (uint32_t)a0 * b0;
    uint32_t mid = (uint32_t)a1 * b0;
    uint32_t t = (uint32_t)a0 * b1;
    uint32_t hi = (uint32_t)a1 * b1;
    mid += t;                                      /* the two middle products, weight 2^16 */
    if (mid < t) hi += UINT32_C(0x10000);          /* their carry has weight 2^48 */
    t = mid << 16;
    lo += t;
    if (lo < t) hi++;
    *lo_out = lo;
    return hi + (mid >> 16);
}

#endif
