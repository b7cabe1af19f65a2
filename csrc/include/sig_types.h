/* sig_types.h - shared types (status codes: sig_status.h) and saturating fixed-point helpers.
 *
 * Portable C99 for hosts, MSP430 (clang) and 8051 (sdcc).  `int` is 16 bits
 * on both MCUs: every width here is explicit.  No libc beyond stdint/stddef/
 * stdbool.  No undefined behaviour: signed overflow is avoided by testing
 * before adding, and negative values are never shifted (sig_asr32 floors a
 * right shift without shifting a negative number).
 *
 * Q formats used across the library (Qm.n: n fractional bits):
 *   Q16.16  int32_t, value = raw / 65536, range [-32768, 32768)
 *   Q0.15   int16_t, value = raw / 32768, range [-1, 1)
 * Each module documents its own Q formats next to its state struct.
 */
#ifndef SIG_TYPES_H
#define SIG_TYPES_H

#include <stdint.h>
#include <stddef.h>
#include <stdbool.h>

#include "sig_status.h"   /* sig_status, SIG_OK, SIG_WARN_*, SIG_ERR_* */

/* Every `_f` function takes sig_real: double on the host, float on the MCUs.
 * Floating-point type of the float builds.  Firmware uses float (the MCUs
 * have no double helpers; sdcc's double is float).  The host Python build
 * defines SIG_REAL_DOUBLE so numpy float64 arrays pass through unconverted. */
#ifdef SIG_REAL_DOUBLE
typedef double sig_real;
typedef uint64_t sig_real_bits;     /* IEEE binary64: sign, 11 exponent bits, 52 fraction */
#define SIG_REAL(x) (x)
#define SIG_REAL_EXP_BITS UINT64_C(0x7FF0000000000000)
#define SIG_REAL_SIGN_BIT UINT64_C(0x8000000000000000)
#else
typedef float sig_real;
typedef uint32_t sig_real_bits;     /* IEEE binary32: sign, 8 exponent bits, 23 fraction */
#define SIG_REAL(x) (x##f)
#define SIG_REAL_EXP_BITS UINT32_C(0x7F800000)
#define SIG_REAL_SIGN_BIT UINT32_C(0x80000000)
#endif
/* Refuses to compile where sig_real is not the width of its bits (sdcc's
 * double is a float: build SIG_REAL_DOUBLE on the host only). */
typedef char sig_real_bits_match[sizeof(sig_real) == sizeof(sig_real_bits) ? 1 : -1];

#define SIG_Q16_ONE INT32_C(65536)

/* SIG_NO_FLOAT: a fixed-only build.  The `_f` functions and the sig_real
 * helpers are left out of every module, so a firmware that uses only the
 * `_q` forms carries no float code (sdcc links whole modules: a fixed-only
 * 8051 firmware would otherwise hold ~20 KB of float code it never calls,
 * and the float library with it).  The structs and prototypes stay. */

/* The length of a run of successive samples that share a property (within
 * the step, outside the band, rejected on one side) after one more sample:
 * one longer when it has the property, else 0; it stops growing at 255.
 * A macro, not a helper: the stages call it every sample and an 8051 call
 * costs more than the compare (`run` is read more than once: pass a plain
 * lvalue). */
#define SIG_RUN_NEXT(run, more) \
    ((uint8_t)((more) ? ((run) < 255u ? (run) + 1u : (run)) : 0u))

/* ---- saturating 32-bit arithmetic ---------------------------------------- */

/* Host compilers and clang (MSP430) inline these helpers.  sdcc (8051) gives
 * every static inline function of a header its own copy in each file that
 * includes it - about 2.4 KB of code per file, with spill temporaries in the
 * 128-byte direct RAM, or on the stack with --stack-auto - and inlines the
 * calls it makes with their locals in the caller's frame.  So for sdcc they
 * are ordinary functions, declared here and defined once in sig_types.c
 * (which defines SIG_TYPES_DEFINE before including this header). */
#if defined(__SDCC) && !defined(SIG_TYPES_DEFINE)
int32_t sig_sat_add32(int32_t a, int32_t b);
int32_t sig_sat_sub32(int32_t a, int32_t b);
int16_t sig_sat16(int32_t x);
int32_t sig_abs32_sat(int32_t x);
int32_t sig_asr32(int32_t x, uint8_t n);
int32_t sig_shl32_sat(int32_t x, uint8_t n);
int32_t sig_mul_q16_sat(int32_t a, int32_t b);
sig_status sig_clamp_i16(int16_t *x, int16_t lo, int16_t hi);
#ifndef SIG_NO_FLOAT
sig_real_bits sig_real_to_bits(sig_real x);
bool sig_real_isfinite(sig_real x);
bool sig_real_isnan(sig_real x);
sig_status sig_clamp_real(sig_real *x, sig_real lo, sig_real hi);
bool sig_real_all_finite(const sig_real *v, uint16_t n);
#endif
#else
#ifdef __SDCC
#define SIG_HELPER              /* sig_types.c: the one external definition */
#else
#define SIG_HELPER static inline
#endif

SIG_HELPER int32_t sig_sat_add32(int32_t a, int32_t b)
{
    if (b > 0 && a > INT32_MAX - b) return INT32_MAX;
    if (b < 0 && a < INT32_MIN - b) return INT32_MIN;
    return a + b;
}

SIG_HELPER int32_t sig_sat_sub32(int32_t a, int32_t b)
{
    if (b < 0 && a > INT32_MAX + b) return INT32_MAX;
    if (b > 0 && a < INT32_MIN + b) return INT32_MIN;
    return a - b;
}

SIG_HELPER int16_t sig_sat16(int32_t x)
{
    if (x > INT16_MAX) return INT16_MAX;
    if (x < INT16_MIN) return INT16_MIN;
    return (int16_t)x;
}

SIG_HELPER int32_t sig_abs32_sat(int32_t x)
{
    return x == INT32_MIN ? INT32_MAX : (x < 0 ? -x : x);
}

/* floor(x / 2^n) for 0 <= n <= 31, without right-shifting a negative value
 * (implementation-defined in C99): ~x is non-negative when x is negative. */
SIG_HELPER int32_t sig_asr32(int32_t x, uint8_t n)
{
    return x >= 0 ? (int32_t)(x >> n) : (int32_t)~((~x) >> n);
}

/* x * 2^n saturated to int32, 0 <= n <= 31, without shifting a negative. */
SIG_HELPER int32_t sig_shl32_sat(int32_t x, uint8_t n)
{
    uint32_t mag;
    if (n == 0 || x == 0) return x;
    if (x > 0) {
        mag = (uint32_t)x;
        if (mag > ((uint32_t)INT32_MAX >> n)) return INT32_MAX;
        return (int32_t)(mag << n);
    }
    mag = (uint32_t)0 - (uint32_t)x;            /* |x|, exact for INT32_MIN */
    if (mag > ((UINT32_C(0x80000000)) >> n)) return INT32_MIN;
    mag <<= n;
    return mag == UINT32_C(0x80000000) ? INT32_MIN : -(int32_t)mag;
}

/* floor(a * b / 2^16), saturated to int32, with 32-bit arithmetic only
 * (no int64: sdcc's 64-bit multiply costs ~800k clocks on an 8051).
 * Identical to (int32_t)sat(((int64_t)a * b) >> 16) for all inputs. */
SIG_HELPER int32_t sig_mul_q16_sat(int32_t a, int32_t b)
{
    /* |a|*|b| = (ah*2^16 + al)(bh*2^16 + bl) on magnitudes, then sign. */
    bool neg = (a < 0) != (b < 0);
    uint32_t ua = a < 0 ? (uint32_t)0 - (uint32_t)a : (uint32_t)a;
    uint32_t ub = b < 0 ? (uint32_t)0 - (uint32_t)b : (uint32_t)b;
    uint32_t ah = ua >> 16, al = ua & 0xFFFFu, bh = ub >> 16, bl = ub & 0xFFFFu;
    uint32_t hh, mid1, mid2, ll, lo16, hi;   /* full product = hi*2^16 + lo16 */
    uint32_t limit = neg ? UINT32_C(0x80000000) : UINT32_C(0x7FFFFFFF);

    hh = ah * bh;                              /* weight 2^32 */
    if (hh > 0xFFFFu) return neg ? INT32_MIN : INT32_MAX;
    mid1 = ah * bl;                            /* weight 2^16 */
    mid2 = al * bh;
    ll = al * bl;                              /* weight 1 */
    lo16 = ll & 0xFFFFu;
    hi = ll >> 16;                             /* product >> 16, built up with overflow checks */
    if (mid1 > UINT32_MAX - hi) return neg ? INT32_MIN : INT32_MAX;
    hi += mid1;
    if (mid2 > UINT32_MAX - hi) return neg ? INT32_MIN : INT32_MAX;
    hi += mid2;
    if ((hh << 16) > UINT32_MAX - hi) return neg ? INT32_MIN : INT32_MAX;
    hi += hh << 16;
    if (!neg) return hi > limit ? INT32_MAX : (int32_t)hi;
    /* negative: floor(-(hi*2^16 + lo16) / 2^16) = -hi - (lo16 != 0) */
    if (lo16 != 0u) {
        if (hi >= limit) return INT32_MIN;
        hi += 1u;
    }
    if (hi > limit) return INT32_MIN;
    return hi == limit ? INT32_MIN : -(int32_t)hi;
}

#ifndef SIG_NO_FLOAT
/* The bits of a sig_real (IEEE 754 binary32 or binary64), read through a
 * union (C99 6.5.2.3: the bytes reinterpreted).  Finiteness is tested on
 * them, not with arithmetic: sdcc folds x - x == 0 to true and its float
 * library compares NaN like a number, so a test built on NaN's arithmetic
 * passes NaN on the 8051.  The exponent field all ones is inf or NaN, the
 * same on every target (no <math.h>: isfinite is not available on every
 * target).  Needs integers and floats of one byte order (true on the host,
 * MSP430 and sdcc's 8051). */
SIG_HELPER sig_real_bits sig_real_to_bits(sig_real x)
{
    union { sig_real r; sig_real_bits b; } u;
    u.r = x;
    return u.b;
}

/* true for a finite x, false for NaN and +-inf: the library's one test */
SIG_HELPER bool sig_real_isfinite(sig_real x)
{
    return (sig_real_to_bits(x) & SIG_REAL_EXP_BITS) != SIG_REAL_EXP_BITS;
}

/* true for NaN only (exponent all ones, fraction not zero): where +-inf has
 * a meaning of its own (a temperature beyond the range clamps) */
SIG_HELPER bool sig_real_isnan(sig_real x)
{
    return (sig_real_to_bits(x) & ~SIG_REAL_SIGN_BIT) > SIG_REAL_EXP_BITS;
}

#endif /* SIG_NO_FLOAT */

/* *x limited to [lo, hi] (lo <= hi): SIG_WARN_CLAMPED when it had to move,
 * else SIG_OK - a temperature outside the calibrated range, a scaled value
 * outside the polynomial's domain. */
SIG_HELPER sig_status sig_clamp_i16(int16_t *x, int16_t lo, int16_t hi)
{
    if (*x < lo) *x = lo;
    else if (*x > hi) *x = hi;
    else return SIG_OK;
    return SIG_WARN_CLAMPED;
}

#ifndef SIG_NO_FLOAT
/* As sig_clamp_i16; +-inf clamps, NaN passes unchanged (callers test it). */
SIG_HELPER sig_status sig_clamp_real(sig_real *x, sig_real lo, sig_real hi)
{
    if (*x < lo) *x = lo;
    else if (*x > hi) *x = hi;
    else return SIG_OK;
    return SIG_WARN_CLAMPED;
}

/* true when v[0..n) are all finite (coefficients, tables, a reading per axis). */
SIG_HELPER bool sig_real_all_finite(const sig_real *v, uint16_t n)
{
    uint16_t i;
    for (i = 0u; i < n; i++)
        if (!sig_real_isfinite(v[i])) return false;
    return true;
}
#endif /* SIG_NO_FLOAT */

#endif /* __SDCC && !SIG_TYPES_DEFINE */

#endif /* SIG_TYPES_H */
