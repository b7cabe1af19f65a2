/* sig_limit.c - limit (threshold) filter with the lock-out fix; see sig_limit.h. */
#include "sig_limit.h"

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
/* Where a sample lies, from d = x - Dc: +1 above A0, -1 below -A0, 0 within. */
static int8_t side_f(sig_real d, sig_real a0)
{
    return d > a0 ? (int8_t)1 : (d < -a0 ? (int8_t)-1 : (int8_t)0);
}
#endif /* SIG_NO_FLOAT */

static int8_t side_q(int32_t d, int32_t a0)
{
    return d > a0 ? (int8_t)1 : (d < -a0 ? (int8_t)-1 : (int8_t)0);
}

static void track_reset(sig_limit_track *t)
{
    t->run = 0u;
    t->side = 0;
    t->seeded = false;
}

static void track_accept(sig_limit_track *t)
{
    t->run = 0u;
    t->side = 0;
    t->seeded = true;
}

/* The decision both forms share once the typed code has placed the sample:
 * side +1 above Dc + A0, -1 below Dc - A0, 0 within (the first sample, which
 * seeds Dc, counts as within).  Returns SIG_OK (the sample becomes Dc),
 * SIG_WARN_REJECTED (Dc stays) or SIG_LIMIT_RESEEDED (the lock-out run is
 * complete: the sample becomes Dc). */
static sig_status track_decide(sig_limit_track *t, int8_t side)
{
    bool outside = side != 0 && t->seeded;
    t->seeded = true;
    if (outside) {
        t->run = side == t->side ? SIG_RUN_NEXT(t->run, true) : 1u;
        t->side = side;
        if (t->lockout_n == 0u || t->run < t->lockout_n) return SIG_WARN_REJECTED;
    }
    t->run = 0u;
    t->side = 0;
    return outside ? SIG_LIMIT_RESEEDED : SIG_OK;
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_limit_init_f(sig_limit_f *s, sig_real a0, uint8_t lockout_n)
{
    if (!s || !sig_real_isfinite(a0) || !(a0 > SIG_REAL(0.0))) return SIG_ERR_ARG;
    s->a0 = a0;
    s->t.lockout_n = lockout_n;
    return sig_limit_reset_f(s);
}

sig_status sig_limit_reset_f(sig_limit_f *s)
{
    if (!s) return SIG_ERR_ARG;
    s->dc = SIG_REAL(0.0);
    track_reset(&s->t);
    return SIG_OK;
}

/* A NaN or inf sample is an impulse that does not count for the lock-out. */
sig_status sig_limit_step_f(sig_limit_f *s, sig_real x, sig_real *out)
{
    sig_status st;
    if (!s || !out) return SIG_ERR_ARG;
    if (!sig_real_isfinite(x)) {
        if (!s->t.seeded) return SIG_ERR_NONFINITE;
        *out = s->dc;
        return SIG_WARN_REJECTED;
    }
    st = track_decide(&s->t, side_f(x - s->dc, s->a0));  /* x - Dc may be +-inf: still rejected */
    if (st != SIG_WARN_REJECTED) s->dc = x;
    *out = s->dc;
    return st;
}

sig_status sig_limit_set_ref_f(sig_limit_f *s, sig_real dc)
{
    if (!s || !sig_real_isfinite(dc)) return SIG_ERR_ARG;
    s->dc = dc;
    s->t.seeded = true;
    return SIG_OK;
}

sig_status sig_limit_accept_f(sig_limit_f *s, sig_real x)
{
    if (!s || !sig_real_isfinite(x)) return SIG_ERR_ARG;
    s->dc = x;
    track_accept(&s->t);
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */

sig_status sig_limit_init_q(sig_limit_q *s, int32_t a0, uint8_t lockout_n)
{
    if (!s || a0 <= 0) return SIG_ERR_ARG;
    s->a0 = a0;
    s->t.lockout_n = lockout_n;
    return sig_limit_reset_q(s);
}

sig_status sig_limit_reset_q(sig_limit_q *s)
{
    if (!s) return SIG_ERR_ARG;
    s->dc = 0;
    track_reset(&s->t);
    return SIG_OK;
}

sig_status sig_limit_step_q(sig_limit_q *s, int32_t x, int32_t *out)
{
    sig_status st;
    if (!s || !out) return SIG_ERR_ARG;
    st = track_decide(&s->t, side_q(sig_sat_sub32(x, s->dc), s->a0));  /* saturated: sign kept */
    if (st != SIG_WARN_REJECTED) s->dc = x;
    *out = s->dc;
    return st;
}

sig_status sig_limit_set_ref_q(sig_limit_q *s, int32_t dc)
{
    if (!s) return SIG_ERR_ARG;
    s->dc = dc;
    s->t.seeded = true;
    return SIG_OK;
}

sig_status sig_limit_accept_q(sig_limit_q *s, int32_t x)
{
    if (!s) return SIG_ERR_ARG;
    s->dc = x;
    track_accept(&s->t);
    return SIG_OK;
}
