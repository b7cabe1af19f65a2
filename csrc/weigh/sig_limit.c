/* sig_limit.c - limit (threshold) filter with the lock-out fix; see sig_limit.h. */
#include "sig_limit.h"

/* NaN and +-inf are the values for which x - x is not 0 (no libm needed). */
sig_status sig_limit_init_f(sig_limit_f *s, sig_real a0, uint8_t lockout_n)
{
    if (!s || !sig_real_isfinite(a0) || !(a0 > SIG_REAL(0.0))) return SIG_ERR_ARG;
    s->a0 = a0;
    s->lockout_n = lockout_n;
    return sig_limit_reset_f(s);
}

sig_status sig_limit_reset_f(sig_limit_f *s)
{
    if (!s) return SIG_ERR_ARG;
    s->dc = SIG_REAL(0.0);
    s->run = 0u;
    s->side = 0;
    s->seeded = false;
    return SIG_OK;
}

sig_status sig_limit_set_ref_f(sig_limit_f *s, sig_real dc)
{
    if (!s || !sig_real_isfinite(dc)) return SIG_ERR_ARG;
    s->dc = dc;
    s->seeded = true;
    return SIG_OK;
}

sig_status sig_limit_step_f(sig_limit_f *s, sig_real x, sig_real *out)
{
    sig_real d;
    int8_t side;
    if (!s || !out) return SIG_ERR_ARG;
    if (!sig_real_isfinite(x)) {
        if (!s->seeded) return SIG_ERR_NONFINITE;
        *out = s->dc;                 /* an impulse; not counted for the lock-out */
        return SIG_WARN_REJECTED;
    }
    if (!s->seeded) {
        s->dc = x;
        s->seeded = true;
        s->run = 0u;
        s->side = 0;
        *out = x;
        return SIG_OK;
    }
    d = x - s->dc;                    /* may be +-inf for huge values: still rejected */
    if (d > s->a0 || d < -s->a0) {
        side = d > SIG_REAL(0.0) ? (int8_t)1 : (int8_t)-1;
        if (side == s->side) {
            if (s->run < 255u) s->run++;
        } else {
            s->side = side;
            s->run = 1u;
        }
        if (s->lockout_n != 0u && s->run >= s->lockout_n) {
            s->dc = x;
            s->run = 0u;
            s->side = 0;
            *out = x;
            return SIG_LIMIT_RESEEDED;
        }
        *out = s->dc;
        return SIG_WARN_REJECTED;
    }
    s->run = 0u;
    s->side = 0;
    s->dc = x;
    *out = x;
    return SIG_OK;
}

sig_status sig_limit_init_q(sig_limit_q *s, int32_t a0, uint8_t lockout_n)
{
    if (!s || a0 <= 0) return SIG_ERR_ARG;
    s->a0 = a0;
    s->lockout_n = lockout_n;
    return sig_limit_reset_q(s);
}

sig_status sig_limit_reset_q(sig_limit_q *s)
{
    if (!s) return SIG_ERR_ARG;
    s->dc = 0;
    s->run = 0u;
    s->side = 0;
    s->seeded = false;
    return SIG_OK;
}

sig_status sig_limit_set_ref_q(sig_limit_q *s, int32_t dc)
{
    if (!s) return SIG_ERR_ARG;
    s->dc = dc;
    s->seeded = true;
    return SIG_OK;
}

sig_status sig_limit_step_q(sig_limit_q *s, int32_t x, int32_t *out)
{
    int32_t d;
    int8_t side;
    if (!s || !out) return SIG_ERR_ARG;
    if (!s->seeded) {
        s->dc = x;
        s->seeded = true;
        s->run = 0u;
        s->side = 0;
        *out = x;
        return SIG_OK;
    }
    d = sig_sat_sub32(x, s->dc);      /* saturation keeps the sign: still rejected */
    if (d > s->a0 || d < -s->a0) {
        side = d > 0 ? (int8_t)1 : (int8_t)-1;
        if (side == s->side) {
            if (s->run < 255u) s->run++;
        } else {
            s->side = side;
            s->run = 1u;
        }
        if (s->lockout_n != 0u && s->run >= s->lockout_n) {
            s->dc = x;
            s->run = 0u;
            s->side = 0;
            *out = x;
            return SIG_LIMIT_RESEEDED;
        }
        *out = s->dc;
        return SIG_WARN_REJECTED;
    }
    s->run = 0u;
    s->side = 0;
    s->dc = x;
    *out = x;
    return SIG_OK;
}
