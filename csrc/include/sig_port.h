/* sig_port.h - target hooks of the csrc/ core: operations a firmware build may
 * replace with its hardware's own, the portable C being the default.
 *
 * A firmware build names a target header with
 *     -DSIG_PORT_HEADER='"sig_port_<target>.h"'  (and -I to its directory)
 * and that header defines any hook below before the defaults are seen.  The
 * host (Python) and 8051 builds define nothing and get the plain C.  A hook
 * must compute exactly what its default computes: the bit-exactness tests
 * compare the firmware with the host C.
 *
 *   SIG_MULADD_HI_U16(a, b, c)  uint16 a, b; c: const uint16_t * to a
 *       32-bit constant C as two words, low word first:
 *       high word of (C + a * b) mod 2^32                 (unsigned product)
 *   SIG_MULADD_HI_S16(a, b, c)  the same with a, b holding two's-complement
 *       int16 values                                      (signed product)
 * (the constant is passed by address so that a target reads each word
 * straight into its accumulator: on a 16-bit CPU a uint32 argument costs a
 * register and a move.)
 *
 * Both are the multiply-accumulate of a 16x16 hardware multiplier (preload
 * the 32-bit result, MAC / MACS, read the high result word), which also does
 * the 32-bit carry that a 16-bit CPU otherwise computes in software.
 * Example target: csrc/port/msp430/sig_port_msp430.h. */
#ifndef SIG_PORT_H
#define SIG_PORT_H

#include "sig_types.h"

#ifdef SIG_PORT_HEADER
#include SIG_PORT_HEADER
#endif

/* value of the int16 whose two's-complement bits are x (no implementation-
 * defined conversion of an out-of-range unsigned value) */
static inline int32_t sig_port_s16(uint16_t x)
{
    return (int32_t)x - (int32_t)(x & 0x8000u) * 2;
}

/* the constant of the hooks, from its two words */
static inline uint32_t sig_port_u32(const uint16_t *c)
{
    return (uint32_t)c[0] | (uint32_t)c[1] << 16;
}

#ifndef SIG_MULADD_HI_U16
#define SIG_MULADD_HI_U16(a, b, c) \
    ((uint16_t)((sig_port_u32(c) + (uint32_t)(a) * (uint16_t)(b)) >> 16))
#endif

#ifndef SIG_MULADD_HI_S16
/* as the unsigned product of the bit patterns: s(a) * s(b) = a * b - 2^16 *
 * (a < 0 ? b : 0) - 2^16 * (b < 0 ? a : 0) (mod 2^32), and the corrections
 * only touch the high word (an int32 product would call a 32x32 multiply) */
static inline uint16_t sig_port_muladd_hi_s16(uint16_t a, uint16_t b, const uint16_t *c)
{
    uint16_t hi = SIG_MULADD_HI_U16(a, b, c);
    if (a & 0x8000u) hi = (uint16_t)(hi - b);
    if (b & 0x8000u) hi = (uint16_t)(hi - a);
    return hi;
}
#define SIG_MULADD_HI_S16(a, b, c) sig_port_muladd_hi_s16((a), (b), (c))
#endif

#endif /* SIG_PORT_H */
