/* sig_tcomp.h - temperature compensation of 1..3 sensor axes by a polynomial
 * offset model (the magnetometer paper's correction, done as a product):
 *
 *     out = in - delta(T),   delta(T) = f(T) - f(T0)
 *
 * where f is the least-squares polynomial of order 1..8 fitted by pysig.tcomp._poly_fit
 * per axis.  The polynomial is stored in a centred, scaled temperature u in
 * [-1, 1] (well conditioned) with f(T0) already folded into c[0], so one
 * Horner pass per axis gives delta directly.
 *
 * Temperature outside the calibrated range [t_lo, t_hi] is clamped to it (the
 * model is evaluated at the limit, flat, as PX4 does) and the call returns
 * SIG_WARN_CLAMPED: never a silent extrapolation.
 *
 * ---- Fixed-point form (sig_tcomp_q) ------------------------------------
 *   temperature  int16_t in centi-degrees Celsius (0.01 °C per count,
 *                -327.68 .. 327.67 °C): SIG_TCOMP_T_PER_DEGC counts per °C.
 *                t_lo, t_hi, t_center and t0 are in the same unit.
 *   scaling      d = clamp(t) - t_center (|d| <= 32767),
 *                u = floor((d * u_mul + 2^(u_shift-1)) / 2^u_shift)   (rounded;
 *                no rounding term when u_shift == 0),
 *                int16_t Q0.15; one 16x16->32 product.  The float model uses
 *                exactly u = (T - t_center) * u_mul / 2^(u_shift + 15), so both
 *                forms share one abscissa (pysig.tcomp._quant chooses u_mul, u_shift
 *                so that |u| <= 32767 over [t_lo, t_hi]).
 *   coefficients int32_t, axis a in Q(q[a]) reading LSB (value = c / 2^q[a]),
 *                ascending powers of u, f(T0) folded into c[0].  pysig.tcomp._quant
 *                picks q[a] as large as possible with sum |c| < 2^31, so no
 *                partial Horner sum can overflow for |u| <= 1.
 *   delta        int32_t Q(q[a]) from sig_poly_horner_q15.
 *   output       out = sat16(in - round(delta / 2^q[a])), round half up
 *                (floor((delta + 2^(q-1)) / 2^q)); SIG_WARN_SATURATED if the
 *                output hit an int16 rail or a Horner sum saturated.
 *   Cost of sig_tcomp_apply_q, order 2, 3 axes: 2 + 3 * 2 * 2 = 14 products
 *   of at most 16x16 bits, no division, no int64, no variable 32-bit shift
 *   when q >= 16 (the rounding shifts and scale factors are precomputed by
 *   sig_tcomp_init_q, and a model whose sums cannot overflow skips the
 *   saturation tests: pysig.tcomp._quant always produces such a model).
 *
 * ---- Float form (sig_tcomp_f) ------------------------------------------
 *   temperature  sig_real °C; u = (clamp(T) - center) * inv_scale;
 *   delta        Horner in sig_real with the float64 fit's coefficients
 *                (f(T0) folded into c[0]); out = in - delta.
 *
 * The coefficient image (sig_image.h, section SIG_SECTION_OFFSET_POLY) stores
 * the fixed-point form; sig_tcomp_load_image parses it.
 */
#ifndef SIG_TCOMP_H
#define SIG_TCOMP_H

#include "sig_types.h"
#include "sig_poly.h"

#define SIG_TCOMP_MAX_AXES   3u
#define SIG_TCOMP_MIN_ORDER  1u
#define SIG_TCOMP_MAX_ORDER  SIG_POLY_MAX_ORDER   /* 8 */
#define SIG_TCOMP_T_PER_DEGC 100                  /* temperature unit: 0.01 °C */
#define SIG_TCOMP_MAX_Q      30u                  /* coefficient fraction bits */
#define SIG_TCOMP_MAX_U_SHIFT 15u                 /* pysig.tcomp._quant never needs more than 14 */

typedef struct {
    int32_t coef[SIG_TCOMP_MAX_AXES][SIG_TCOMP_MAX_ORDER + 1u]; /* Q(q[a]) LSB, ascending powers of u */
    uint8_t q[SIG_TCOMP_MAX_AXES];  /* fraction bits of each axis' coefficients, 0..30 */
    int16_t t_lo, t_hi;             /* calibrated range, 0.01 °C, t_lo < t_hi */
    int16_t t_center;               /* u = 0 here, t_lo <= t_center <= t_hi */
    int16_t t0;                     /* reference temperature (documentary: folded into c[0]) */
    int16_t u_mul;                  /* > 0 */
    uint8_t u_shift;                /* 0..15 */
    uint8_t order;                  /* 1..8 */
    uint8_t n_axes;                 /* 1..3 */
    /* derived by sig_tcomp_init_q, so the hot path has no variable 32-bit shift: */
    int32_t u_mul32;                /* u_mul * 2^(16 - u_shift): u from a high-word select */
    int32_t q_round[SIG_TCOMP_MAX_AXES]; /* 2^(q-1), 0 when q == 0 */
    bool no_overflow;               /* sum |c| + order + 2^(q-1) <= INT32_MAX on every axis:
                                       Horner without saturation checks (same result) */
} sig_tcomp_q;

typedef struct {
    sig_real coef[SIG_TCOMP_MAX_AXES][SIG_TCOMP_MAX_ORDER + 1u]; /* reading units, ascending powers of u */
    sig_real t_lo, t_hi;            /* calibrated range, °C */
    sig_real center, inv_scale;     /* u = (T - center) * inv_scale */
    uint8_t order;                  /* 1..8 */
    uint8_t n_axes;                 /* 1..3 */
} sig_tcomp_f;

/* Check and store a fixed-point model.  coef holds n_axes * (order + 1)
 * values, axis-major; q holds n_axes fraction counts.  SIG_ERR_ARG (and *m
 * untouched) for NULL pointers, n_axes outside 1..3, order outside 1..8,
 * q > 30, t_lo >= t_hi, t_center outside [t_lo, t_hi], u_mul <= 0,
 * u_shift > 15, or a scaling under which |u| would exceed 32767 in range. */
sig_status sig_tcomp_init_q(sig_tcomp_q *m, uint8_t n_axes, uint8_t order,
                            const int32_t *coef, const uint8_t *q,
                            int16_t t_lo, int16_t t_hi, int16_t t_center, int16_t t0,
                            int16_t u_mul, uint8_t u_shift);

/* The scaled temperature u (Q0.15) after clamping; SIG_WARN_CLAMPED when t
 * was outside [t_lo, t_hi].  SIG_ERR_ARG for NULL pointers. */
sig_status sig_tcomp_scale_q(const sig_tcomp_q *m, int16_t t, int16_t *u_q15);

/* delta of one axis at temperature t, in Q(q[axis]) reading LSB (before the
 * final rounding): for tests and for modules that combine corrections.
 * Status as sig_tcomp_apply_q; SIG_ERR_ARG for axis >= n_axes. */
sig_status sig_tcomp_delta_q(const sig_tcomp_q *m, uint8_t axis, int16_t t, int32_t *delta);

/* THE firmware entry point: compensate all n_axes readings taken at one
 * temperature t (0.01 °C).  in and out hold n_axes int16 readings (they may
 * be the same array).  Returns SIG_OK, or an OR of SIG_WARN_CLAMPED (t was
 * outside the calibrated range) and SIG_WARN_SATURATED (an output hit an
 * int16 rail); SIG_ERR_ARG (out untouched) for NULL pointers. */
sig_status sig_tcomp_apply_q(const sig_tcomp_q *m, int16_t t, const int16_t *in, int16_t *out);

/* Float model.  coef as for sig_tcomp_init_q (axis-major, reading units).
 * SIG_ERR_ARG for NULL pointers, bad n_axes/order, t_lo >= t_hi, center
 * outside the range, inv_scale <= 0; SIG_ERR_NONFINITE for a non-finite
 * parameter or coefficient.  *m untouched on error. */
sig_status sig_tcomp_init_f(sig_tcomp_f *m, uint8_t n_axes, uint8_t order, const sig_real *coef,
                            sig_real t_lo, sig_real t_hi, sig_real center, sig_real inv_scale);

/* Float twin of sig_tcomp_apply_q (T in °C).  SIG_WARN_CLAMPED outside the
 * range; SIG_ERR_NONFINITE (out untouched) for a NaN temperature or a
 * non-finite reading. */
sig_status sig_tcomp_apply_f(const sig_tcomp_f *m, sig_real t, const sig_real *in, sig_real *out);

/* Parse and check the SIG_SECTION_OFFSET_POLY section of a coefficient image
 * (format in sig_image.h) into *m.  The image must pass sig_image_validate
 * (else its status: SIG_ERR_FORMAT / SIG_ERR_CRC); SIG_ERR_EMPTY if it has no
 * offset section; SIG_ERR_FORMAT for a malformed payload.  *m untouched on
 * error. */
sig_status sig_tcomp_load_image(sig_tcomp_q *m, const uint8_t *image, size_t len);

#endif /* SIG_TCOMP_H */
