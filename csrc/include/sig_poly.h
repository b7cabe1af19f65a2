/* sig_poly.h - polynomial evaluation by Horner's rule, fixed and float.
 *
 * Both forms evaluate p(u) = c[0] + c[1] u + ... + c[order] u^order on a
 * centred and scaled abscissa u in [-1, 1] (the fit conditions the problem
 * this way, see pysig/lsq.py), so every partial sum of Horner's rule is
 * bounded by sum |c[k]| and the fixed-point coefficients can use all 32 bits.
 *
 * Fixed-point form (sig_poly_horner_q15):
 *   u        int16_t Q0.15 (value = u / 32768), |u| <= 32767 (INT16_MIN is
 *            treated as -32767 so that |u| < 1 strictly).
 *   c[k]     int32_t in any Q format Qm.n chosen by the caller (the result is
 *            in the same format).
 *   step     acc = sat32(c[k] + floor(acc * u / 2^15)), k = order-1 .. 0,
 *            starting from acc = c[order].
 *   The 32x16 product is formed from two 16x16->32 products (the high signed
 *   half and the low unsigned half of acc), so there is no int64 and no call
 *   to a 32x32 multiply on the MSP430; floor(acc*u/2^15) never overflows
 *   because |u| < 1.  Only the additions can saturate; they are reported.
 * Float form (sig_poly_horner_f): the same recurrence in sig_real.
 */
#ifndef SIG_POLY_H
#define SIG_POLY_H

#include "sig_types.h"

#define SIG_POLY_MAX_ORDER 8u

/* floor(a * u / 2^15) for any int32 a and |u| <= 32767, exact, 16x16->32
 * products only.  Exposed for tests and for other modules' Q15 scaling. */
int32_t sig_mul_q15_32x16(int32_t a, int16_t u);

/* p(u) in the coefficients' Q format.  SIG_OK, or SIG_WARN_SATURATED when a
 * partial sum hit an int32 rail (the result is then the saturated value);
 * SIG_ERR_ARG (and *out untouched) for NULL pointers or order > 8. */
sig_status sig_poly_horner_q15(const int32_t *c, uint8_t order, int16_t u, int32_t *out);

/* p(u) in sig_real; SIG_ERR_ARG for NULL pointers or order > 8,
 * SIG_ERR_NONFINITE for a NaN/inf u or result (*out untouched). */
sig_status sig_poly_horner_f(const sig_real *c, uint8_t order, sig_real u, sig_real *out);

#endif /* SIG_POLY_H */
