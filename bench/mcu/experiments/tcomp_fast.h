/* tcomp_fast.h - EXPERIMENT (bench only): sig_tcomp_apply_q spelt for the
 * MSP430's 16x16 multiplier; same results bit for bit. */
#ifndef TCOMP_FAST_H
#define TCOMP_FAST_H
#include "sig_tcomp.h"
sig_status tcomp_fast_apply_q(const sig_tcomp_q *m, int16_t t, const int16_t *in, int16_t *out);
#endif
