/* sig_pwl_msp430.h - MSP430 assembly form of the table lookup (port layer):
 * sig_pwl_eval_msp430 (sig_pwl_msp430.S) computes exactly sig_pwl_eval_q16
 * (sig_pwl.h).  Its fast path needs recip = rh * 2^16 (knots 2^16 / rh
 * temperature units apart: a power-of-two spacing when rh is a power of two);
 * other tables go through the portable C.  The assembly reads sig_pwl_q16
 * at fixed offsets: the typedef below stops the build if they change. */
#ifndef SIG_PWL_MSP430_H
#define SIG_PWL_MSP430_H

#include <stddef.h>
#include "sig_pwl.h"

sig_status sig_pwl_eval_msp430(const sig_pwl_q16 *p, int16_t t, int32_t *out_q16);

/* The n_axes tables of one coefficient image (sig_pwl_load_image: shared
 * n_knots, t_lo, t_hi, recip; own table and value_frac) at one temperature:
 * out_q16[a] == sig_pwl_eval_q16(&p[a], t, ...) for every axis, the clamp,
 * segment and fraction computed once.  SIG_OK or SIG_WARN_CLAMPED;
 * SIG_ERR_ARG for NULL pointers or n_axes == 0.  p[1..]'s shared fields are
 * not read. */
sig_status sig_pwl_eval_axes_msp430(const sig_pwl_q16 *p, uint8_t n_axes, int16_t t,
                                    int32_t *out_q16);

#ifdef __MSP430__
typedef char sig_pwl_msp430_layout_check[
    (offsetof(sig_pwl_q16, table) == 0 && offsetof(sig_pwl_q16, recip) == 2
     && offsetof(sig_pwl_q16, t_lo) == 6 && offsetof(sig_pwl_q16, t_hi) == 8
     && offsetof(sig_pwl_q16, n_knots) == 12 && offsetof(sig_pwl_q16, value_frac) == 13
     && sizeof(sig_pwl_q16) == 14 && sizeof(void *) == 2) ? 1 : -1];
#endif

#endif /* SIG_PWL_MSP430_H */
