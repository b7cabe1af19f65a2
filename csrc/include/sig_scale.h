/* sig_scale.h - apply a stored linear scale calibration: ADC counts -> mass.
 *
 * The calibration is fitted on the host (pysig.weigh._calibration.calibrate, least
 * squares on standard masses) and stored as an offset and a gain; this file
 * applies it, in fixed point for the MCUs and in float.
 *
 * Fixed-point form (sig_scale_q16):
 *   counts     int32_t ADC code (a 24-bit ADC's codes, or a filtered value
 *              in codes).
 *   offset     int32_t ADC code at zero mass (the fitted intercept, rounded:
 *              at most half a code of error).
 *   d          sat32(counts - offset).
 *   gain_mant  int32_t, gain * 2^(16 + gain_shift) where gain is the mass
 *              unit per code; gain_shift 0..62 is chosen by the host so that
 *              gain_mant keeps ~31 significant bits.
 *   output     int32_t Q16.16 mass in the calibration's unit (kg or lb):
 *              floor(d * gain_mant / 2^gain_shift), saturated to int32
 *              (+-32768 units) with SIG_WARN_SATURATED.
 *   The 64-bit product d * gain_mant is built exactly from 16-bit halves in
 *   two uint32 words (no int64: the 8051 pays ~800k clocks per 64-bit
 *   multiply); the shift floors towards minus infinity.
 *
 * Float form (sig_scale_f): mass = (counts - offset) * gain in sig_real.
 */
#ifndef SIG_SCALE_H
#define SIG_SCALE_H

#include "sig_types.h"

#define SIG_SCALE_MAX_SHIFT 62u

typedef struct {
    int32_t offset;       /* ADC code at zero mass */
    int32_t gain_mant;    /* unit per code, Q(16 + gain_shift) */
    uint8_t gain_shift;   /* 0..62 */
} sig_scale_q16;

typedef struct {
    sig_real offset;      /* ADC code at zero mass */
    sig_real gain;        /* unit per code */
} sig_scale_f;

/* Stores the calibration.  SIG_ERR_ARG (and *s untouched) for a NULL
 * pointer, gain_mant == 0 or gain_shift > 62. */
sig_status sig_scale_init_q16(sig_scale_q16 *s, int32_t offset, int32_t gain_mant, uint8_t gain_shift);

/* *mass_q16 = Q16.16 mass of `counts`.  SIG_OK, or SIG_WARN_SATURATED when
 * d or the result hit an int32 rail (the saturated value is stored).
 * SIG_ERR_ARG for NULL pointers. */
sig_status sig_scale_apply_q16(const sig_scale_q16 *s, int32_t counts, int32_t *mass_q16);

/* SIG_ERR_ARG for a NULL pointer or a zero gain, SIG_ERR_NONFINITE for a
 * non-finite offset or gain (x != x and the overflow test catch NaN and
 * inf without libm); *s untouched on error. */
sig_status sig_scale_init_f(sig_scale_f *s, sig_real offset, sig_real gain);

/* *mass = (counts - offset) * gain.  SIG_ERR_NONFINITE (and *mass
 * untouched) for a non-finite counts value. */
sig_status sig_scale_apply_f(const sig_scale_f *s, sig_real counts, sig_real *mass);

#endif /* SIG_SCALE_H */
