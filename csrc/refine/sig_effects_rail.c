/* sig_effects_rail.c - the fixed-point steps the effects share (sig_effects_rail.h). */
#include "sig_effects_rail.h"

sig_status sig_flag_rail(sig_status st, int32_t v)
{
    return (v == INT32_MAX || v == INT32_MIN) ? (sig_status)(st | SIG_WARN_SATURATED) : st;
}

int32_t sig_round_shift(int32_t v, uint8_t n)
{
    if (n == 0u) return v;
    return sig_asr32(sig_sat_add32(v, (int32_t)(INT32_C(1) << (n - 1u))), n);
}
