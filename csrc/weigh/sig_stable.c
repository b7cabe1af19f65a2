/* sig_stable.c - stability detector; see sig_stable.h. */
#include "sig_stable.h"

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_stable_init_f(sig_stable_f *s, sig_real step, uint8_t count)
{
    if (!s || !sig_real_isfinite(step) || step < SIG_REAL(0.0) || count == 0u) return SIG_ERR_ARG;
    s->step = step;
    s->count = count;
    return sig_stable_reset_f(s);
}

sig_status sig_stable_reset_f(sig_stable_f *s)
{
    if (!s) return SIG_ERR_ARG;
    s->prev = SIG_REAL(0.0);
    s->run = 0u;
    s->has_prev = false;
    return SIG_OK;
}

sig_status sig_stable_step_f(sig_stable_f *s, sig_real x, bool *stable)
{
    sig_real d;
    if (!s || !stable) return SIG_ERR_ARG;
    if (!sig_real_isfinite(x)) return SIG_ERR_NONFINITE;
    d = x - s->prev;
    s->run = SIG_RUN_NEXT(s->run, s->has_prev && d <= s->step && -d <= s->step);
    s->prev = x;
    s->has_prev = true;
    *stable = s->run >= s->count;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */

sig_status sig_stable_init_q(sig_stable_q *s, int32_t step_q7, uint8_t count)
{
    if (!s || step_q7 < 0 || count == 0u) return SIG_ERR_ARG;
    s->step = step_q7;
    s->count = count;
    return sig_stable_reset_q(s);
}

sig_status sig_stable_reset_q(sig_stable_q *s)
{
    if (!s) return SIG_ERR_ARG;
    s->prev = 0;
    s->run = 0u;
    s->has_prev = false;
    return SIG_OK;
}

sig_status sig_stable_step_q(sig_stable_q *s, int32_t x_q7, bool *stable)
{
    if (!s || !stable) return SIG_ERR_ARG;
    s->run = SIG_RUN_NEXT(s->run, s->has_prev && sig_abs32_sat(sig_sat_sub32(x_q7, s->prev)) <= s->step);
    s->prev = x_q7;
    s->has_prev = true;
    *stable = s->run >= s->count;
    return SIG_OK;
}
