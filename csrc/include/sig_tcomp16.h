/* sig_tcomp16.h - compact fixed-point temperature compensation of 1..3 axes:
 * the offset polynomial of sig_tcomp.h (same model, same clamping), spelt
 * for a 16x16 hardware multiplier.  Every product is an UNSIGNED 16x16->32
 * product, no shift is variable except one per call, no int64.
 * (Name: "16" is the multiplicand width, not a Q format; see docs/c-api.md.)
 *
 *     out = sat16(in - round(delta(t))),   delta(t) = f(t) - f(T0)
 *
 * ---- Fixed-point form (sig_tcomp16_q) -----------------------------------
 *   temperature  int16_t, 0.01 °C (as sig_tcomp.h), clamped to [t_lo, t_hi]
 *                (the model is flat beyond; SIG_WARN_CLAMPED is returned).
 *   abscissa     v = clamp(t) - t_lo, 0 .. t_hi - t_lo (uint16, exact: no
 *                scaling, no rounding), and w = v * 2^w_shift <= 65535
 *                (w_shift fixed at init, >= 1 when order >= 2 so that w is
                even: the calibrated range is then at most 327.67 °C wide).
 *   polynomial   delta(v) = sum_k c_k v^k (LSB, v in 0.01 °C), Horner with
 *                a fixed 16-bit shift per level:
 *                  h[order]  = top                          int16
 *                  h[k]      = floor((h[k+1] * w + add_k) / 2^16)   int16,
 *                              k = order-1 .. 1             (add_k int32)
 *                  corr      = floor((h[1] * v + add_0) / 2^16)     int16
 *                h[k] ~ p_k(v) * 2^E_k with p_k(v) = sum_{i>=k} c_i v^(i-k),
 *                E_1 = 16, E_(k+1) = E_k + 16 - w_shift; add_k holds
 *                c_k * 2^(E_k + 16) + 2^15 (the rounding of the level) and
 *                add_0 = c_0 * 2^16 + 2^15 (so corr = round(delta)).
 *   output       out = sat16(in - corr); SIG_WARN_SATURATED at a rail.
 *   No overflow: init accepts coefficients only when a bound through the
 *   levels (|h[k]| <= 32767, |h*w + add| < 2^31) holds for every v in
 *   range; the hot path then needs no saturation test.  pysig.tcomp._quant
 *   (quantize_compact) chooses the coefficients under the same test.
 *   How the products are formed: every level is the high word of a 32-bit
 *   multiply-accumulate, acc + a * b (mod 2^32), the operation of a 16x16
 *   hardware multiplier (sig_port.h: SIG_MULADD_HI_U16 / _S16, plain C by
 *   default, a firmware may map them onto its MAC).  Inner levels carry
 *   U = h + 2^15 (offset binary) and form the UNSIGNED product U * w =
 *   h * w + 2^15 * w; w is even, so the 2^15 * w term is w/2 in the high
 *   word, subtracted after (one 16-bit subtract).  The last inner level
 *   (constant stored without the 2^31 offset) hands the last level h_1
 *   itself, and the last level is a SIGNED 16x16 product h_1 * v (v <=
 *   32767 whenever order >= 2).  Order 1 (v up to 65535) multiplies top
 *   by v - 2^15 instead; init folds top * 2^15 into its constant.  The
 *   last constant carries + 2^31, so its high word is corr + 2^15, the
 *   operand of the offset-binary saturating subtract.
 *   Cost of one call: order * n_axes 16x16 multiply-accumulates (order 2,
 *   3 axes: 6), one variable 16-bit shift (w), no division.
 *
 * Compared with sig_tcomp_q (int32 coefficients, Q15 abscissa, any slope):
 * this form covers slopes |p_1(v)| < 0.5 LSB per 0.01 °C (50 LSB/°C) and
 * rounds each level to 2^-16 of its unit, so it adds up to ~0.5 * n_levels *
 * (t_hi - t_lo) / 65536 LSB of quantisation error (pysig.tcomp._quant measures the
 * exact figure over every temperature of the range).
 */
#ifndef SIG_TCOMP16_H
#define SIG_TCOMP16_H

#include "sig_types.h"

#define SIG_TCOMP16_MAX_AXES  3u
#define SIG_TCOMP16_MIN_ORDER 1u
#define SIG_TCOMP16_MAX_ORDER 5u

typedef struct {
    /* per axis, packed (axis a from coef[a * (1 + 2 * order)]): top, then
     * add_(order-1) .. add_0 as (low, high) uint16 words.  Offset binary
     * (top + 2^15, add + 2^31, mod 2^16 / 2^32) except the input of the last
     * level, which is signed: top when order == 1, add_1 otherwise. */
    uint16_t coef[SIG_TCOMP16_MAX_AXES * (1u + 2u * SIG_TCOMP16_MAX_ORDER)];
    int16_t t_lo, t_hi;                   /* calibrated range, 0.01 °C, t_lo < t_hi */
    uint8_t w_shift;                      /* (t_hi - t_lo) << w_shift <= 65535 */
    uint8_t order;                        /* 1..5 */
    uint8_t n_axes;                       /* 1..3 */
} sig_tcomp16_q;

/* Check and store a compact model.  top: n_axes values; add: n_axes * order
 * values, axis-major, each axis in evaluation order add_(order-1) .. add_0
 * (add_0 last).  SIG_ERR_ARG (and *m untouched) for NULL pointers, n_axes
 * outside 1..3, order outside 1..5, t_lo >= t_hi, (t_hi - t_lo) << w_shift
 * above 65535, w_shift outside 1..15 (0..15 for order 1), or coefficients for which an intermediate could leave its
 * range (see the header comment). */
sig_status sig_tcomp16_init(sig_tcomp16_q *m, uint8_t n_axes, uint8_t order,
                            const int16_t *top, const int32_t *add,
                            int16_t t_lo, int16_t t_hi, uint8_t w_shift);

/* THE firmware entry point: compensate the n_axes int16 readings in[] taken
 * at temperature t (0.01 °C) into out[] (may be the same array).  SIG_OK, or
 * an OR of SIG_WARN_CLAMPED (t outside [t_lo, t_hi]) and SIG_WARN_SATURATED
 * (an output hit an int16 rail); SIG_ERR_ARG (out untouched) for NULL. */
sig_status sig_tcomp16_apply_q(const sig_tcomp16_q *m, int16_t t, const int16_t *in, int16_t *out);

/* Load the compact model from a coefficient image in image[0..len) (its
 * SIG_SECTION_COMPACT_POLY section, payload in sig_image.h), in
 * sig_tcomp16_image.c so that firmware which never reads an image links
 * none of it.  Argument order as sig_tcomp_load_image.  SIG_OK; the
 * statuses of sig_image_find_section (SIG_ERR_FORMAT, SIG_ERR_CRC,
 * SIG_ERR_EMPTY when there is no compact section, SIG_ERR_ARG for NULL);
 * SIG_ERR_FORMAT for a payload of the wrong length, a non-zero reserved
 * byte, or fields sig_tcomp16_init rejects.  *m untouched on any error. */
sig_status sig_tcomp16_load_image(sig_tcomp16_q *m, const uint8_t *image, size_t len);

#endif /* SIG_TCOMP16_H */
