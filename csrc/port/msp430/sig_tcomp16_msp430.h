/* sig_tcomp16_msp430.h - MSP430 assembly forms of the compensation's hot
 * paths (port layer): sig_tcomp16_apply_msp430 (sig_tcomp16_msp430.S) computes
 * exactly sig_tcomp16_apply_q (sig_tcomp16.h) on the 16x16 hardware
 * multiplier.  The assembly reads sig_tcomp16_q at fixed offsets: the
 * typedefs below stop the build if the struct's layout ever changes. */
#ifndef SIG_TCOMP16_MSP430_H
#define SIG_TCOMP16_MSP430_H

#include <stddef.h>
#include "sig_tcomp16.h"

sig_status sig_tcomp16_apply_msp430(const sig_tcomp16_q *m, int16_t t, const int16_t *in,
                                    int16_t *out);

#ifdef __MSP430__
typedef char sig_tcomp16_msp430_layout_check[
    (offsetof(sig_tcomp16_q, t_lo) == 66 && offsetof(sig_tcomp16_q, t_hi) == 68
     && offsetof(sig_tcomp16_q, w_shift) == 70 && offsetof(sig_tcomp16_q, order) == 71
     && offsetof(sig_tcomp16_q, n_axes) == 72) ? 1 : -1];
#endif

#endif /* SIG_TCOMP16_MSP430_H */
