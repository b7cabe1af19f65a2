/* sig_effects_rail.h - private to csrc/refine: the two fixed-point steps every
 * effect's _q form shares, written once.
 *
 * Saturation convention: SIG_WARN_SATURATED is set whenever an intermediate
 * or output value equals an int32 rail (INT32_MIN or INT32_MAX) after a
 * saturating operation, whether or not the exact value was beyond it: one
 * cheap test, the same in the Python reference.  Ordinary functions (one
 * copy on the 8051, where sdcc would give a static one to every file). */
#ifndef SIG_EFFECTS_RAIL_H
#define SIG_EFFECTS_RAIL_H

#include "sig_types.h"

/* st with SIG_WARN_SATURATED added when v sits on an int32 rail */
sig_status sig_flag_rail(sig_status st, int32_t v);

/* floor((v + 2^(n-1)) / 2^n), saturating; v's rail flagged by the caller */
int32_t sig_round_shift(int32_t v, uint8_t n);

#endif /* SIG_EFFECTS_RAIL_H */
