/* sig_pwl.h - piecewise-linear lookup table with uniform knots.
 *
 * The on-board alternative to a polynomial for a drift curve f(T) (the
 * MatrixPilot firmware stores its gyro offsets this way): n knot values at
 * uniformly spaced temperatures, linear interpolation between them, flat
 * (and flagged SIG_WARN_CLAMPED) outside [t_lo, t_hi].  No division on the
 * hot path: the segment position comes from one multiply by a precomputed
 * reciprocal and constant shifts.
 *
 * Fixed-point form (sig_pwl_q16; "q16" names the Q16.16 output):
 *   temperature   int16_t, the unit of the temperature-compensation module
 *                 (sig_tcomp.h: 0.01 °C); the table only needs it linear in T.
 *   d             t - t_lo after clamping to [t_lo, t_hi], 0 <= d <= 65535.
 *   position      pos = floor(d * recip / 2^16), unsigned Q16.16 segment
 *                 position (recip = segments per temperature unit in Q0.32):
 *                 segment = pos >> 16, frac = (pos & 0xFFFF) >> 4 (Q0.12).
 *                 Knot k therefore sits at d_k = k * 2^32 / recip (a real
 *                 number): the knots are uniform by construction.
 *   table         int16_t entries, value = entry * 2^-value_frac
 *                 (0 <= value_frac <= 15), one per knot.
 *   interpolation acc = table[i] * 2^12 + (table[i+1] - table[i]) * frac,
 *                 int32, |acc| <= 32767 * 2^12, unit 2^-(value_frac + 12).
 *   output        int32_t Q16.16 = floor(acc * 2^(4 - value_frac)), exact
 *                 (|output| <= 32767 * 2^16: it never saturates).
 * Every shift is by a constant and every product is 16x16 -> 32 bits (five
 * per call; the value_frac rescaling is a multiply by a precomputed power of
 * two), so the MSP430 never runs a variable-shift loop; no int64, no division.
 *
 * Float form (sig_pwl_f): the same table in sig_real, temperature in any
 * linear unit (°C in pysig), pos = (t - t_lo) * inv_step.
 */
#ifndef SIG_PWL_H
#define SIG_PWL_H

#include "sig_types.h"

#define SIG_PWL_FRAC_BITS 12       /* fraction bits used in the interpolation */
#define SIG_PWL_MIN_KNOTS 2u
#define SIG_PWL_MAX_KNOTS 255u

typedef struct {
    const int16_t *table;  /* n_knots entries, caller-owned, value = entry * 2^-value_frac */
    uint32_t recip;        /* segments per temperature unit, Q0.32, >= 1 */
    int16_t t_lo;          /* temperature of knot 0 and lower end of the valid range */
    int16_t t_hi;          /* upper end of the valid range (> t_lo) */
    uint16_t out_mul;      /* derived by init: 2^(20 - value_frac) for value_frac > 4,
                              2^(4 - value_frac) for value_frac < 4, unused at 4 */
    uint8_t n_knots;       /* 2..255 */
    uint8_t value_frac;    /* 0..15 */
} sig_pwl_q16;

typedef struct {
    const sig_real *table; /* n_knots entries, caller-owned */
    sig_real t_lo;         /* temperature of knot 0 */
    sig_real t_hi;         /* upper end of the valid range (> t_lo) */
    sig_real inv_step;     /* 1 / knot spacing (> 0) */
    uint8_t n_knots;       /* 2..255 */
} sig_pwl_f;

/* Checks and stores the parameters.  SIG_ERR_ARG (and *p untouched) for a
 * NULL pointer, n_knots outside 2..255, t_hi <= t_lo, recip == 0,
 * value_frac > 15, or a position mapping under which [t_lo, t_hi] does not
 * end in the last segment (floor(span * recip / 2^16) must lie in
 * [(n_knots - 2) * 2^16, (n_knots - 1) * 2^16], span = t_hi - t_lo). */
sig_status sig_pwl_init_q16(sig_pwl_q16 *p, const int16_t *table, uint8_t n_knots,
                            int16_t t_lo, int16_t t_hi, uint32_t recip, uint8_t value_frac);

/* f(t) in Q16.16.  SIG_WARN_CLAMPED when t was outside [t_lo, t_hi] (the
 * value at the nearer end is returned); SIG_ERR_ARG for NULL pointers. */
sig_status sig_pwl_eval_q16(const sig_pwl_q16 *p, int16_t t, int32_t *out_q16);

/* ---- coefficient image: payload of SIG_SECTION_PWL_TABLE (sig_image.h) ----
 *   0  u8  n_axes (1..3)    1  u8 n_knots (2..255)
 *   2  i16 t_lo   4  i16 t_hi   6  u32 recip        (shared by every axis)
 *   10 per axis: u8 value_frac, then n_knots x i16 entries
 *   length = 10 + n_axes * (1 + 2 * n_knots), little-endian, unaligned.
 * Written by pysig.tcomp._table_fit.pwl_payload. */
#define SIG_PWL_MAX_AXES       3u
#define SIG_PWL_IMAGE_FIXED_LEN 10u

/* Load the tables of a coefficient image: validates the image (sig_image.h),
 * finds its SIG_SECTION_PWL_TABLE section, checks the payload and every
 * axis' parameters (as sig_pwl_init_q16), then copies the entries into the
 * caller's `storage` (int16, aligned; at least n_axes * n_knots entries,
 * `storage_len` given in entries) and initialises tables[0 .. n_axes-1],
 * which point into it.  *n_axes receives the count.  Errors: the image's
 * validation status (SIG_ERR_FORMAT, SIG_ERR_CRC), SIG_ERR_EMPTY when there is
 * no table section, SIG_ERR_FORMAT for a malformed payload or parameters,
 * SIG_ERR_ARG for NULL pointers or too little room (n_axes > max_axes or
 * storage too short).  On any error nothing is written. */
sig_status sig_pwl_load_image(sig_pwl_q16 *tables, uint8_t max_axes, uint8_t *n_axes,
                              int16_t *storage, uint16_t storage_len,
                              const uint8_t *image, size_t len);

/* SIG_ERR_ARG for a NULL pointer, n_knots outside 2..255, a non-finite or
 * empty range, inv_step <= 0 or a range not ending in the last segment;
 * SIG_ERR_NONFINITE for a non-finite table entry. */
sig_status sig_pwl_init_f(sig_pwl_f *p, const sig_real *table, uint8_t n_knots,
                          sig_real t_lo, sig_real t_hi, sig_real inv_step);

/* f(t); SIG_WARN_CLAMPED outside [t_lo, t_hi]; SIG_ERR_NONFINITE for a NaN
 * temperature (*out untouched). */
sig_status sig_pwl_eval_f(const sig_pwl_f *p, sig_real t, sig_real *out);

#endif /* SIG_PWL_H */
