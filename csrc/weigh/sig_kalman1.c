/* sig_kalman1.c - scalar Kalman filter, float and fixed; see sig_kalman1.h. */
#include "sig_kalman1.h"
#include "sig_mul_wide.h"

#define SIG_Q30_ONE UINT32_C(1073741824)

/* Exact 32-bit helpers of the fixed form: no int64, no division (a 32x32
 * product from four 16x16 products).  Plain static functions, not inline
 * header helpers: sdcc emits every static inline function of a header in each
 * file that includes it, each with its own spill area in the 8051's RAM. */
/* floor((a * b + 2^29) / 2^30): a Q30 product rounded half up; the caller
 * guarantees the result fits in 32 bits (a * b < 2^62 - 2^29). */
static uint32_t mul_q30(uint32_t a, uint32_t b)
{
    uint32_t lo;
    uint32_t hi = sig_mul_wide(a, b, &lo);
    lo += UINT32_C(0x20000000);                    /* + 2^29: round half up */
    if (lo < UINT32_C(0x20000000)) hi++;
    return (hi << 2) | (lo >> 30);
}

/* Signed a times a Q30 gain k <= 2^30, rounded half away from zero:
 * sign(a) * floor((|a| k + 2^29) / 2^30); |result| <= |a|. */
static int32_t mul_q30_gain(int32_t a, uint32_t k)
{
    uint32_t r = mul_q30(a < 0 ? (uint32_t)0 - (uint32_t)a : (uint32_t)a, k);
    if (a >= 0) return (int32_t)r;
    return r >= UINT32_C(0x80000000) ? INT32_MIN : -(int32_t)r;
}


#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_kalman1_init_f(sig_kalman1_f *s, sig_real q, sig_real r, sig_real p0,
                              sig_real x0, bool seed_first)
{
    if (!s || !sig_real_isfinite(q) || !sig_real_isfinite(r) || !sig_real_isfinite(p0) || !sig_real_isfinite(x0)) return SIG_ERR_ARG;
    if (q < SIG_REAL(0.0) || !(r > SIG_REAL(0.0)) || p0 < SIG_REAL(0.0)) return SIG_ERR_ARG;
    s->q = q;
    s->r = r;
    s->p0 = p0;
    s->x0 = x0;
    s->seed_first = seed_first;
    return sig_kalman1_reset_f(s);
}

sig_status sig_kalman1_reset_f(sig_kalman1_f *s)
{
    if (!s) return SIG_ERR_ARG;
    s->x = s->x0;
    s->p = s->p0;
    s->k = SIG_REAL(0.0);
    s->innov = SIG_REAL(0.0);
    s->seeded = false;
    s->converged = false;
    return SIG_OK;
}

sig_status sig_kalman1_restart_f(sig_kalman1_f *s)
{
    if (!s) return SIG_ERR_ARG;
    s->p = s->p0;
    s->converged = false;
    return SIG_OK;
}

sig_status sig_kalman1_step_f(sig_kalman1_f *s, sig_real z, sig_real *out)
{
    sig_real pm, den, pn;
    if (!s || !out) return SIG_ERR_ARG;
    if (!sig_real_isfinite(z)) return SIG_ERR_NONFINITE;
    if (!s->seeded) {
        s->seeded = true;
        if (s->seed_first) s->x = z;
    }
    if (!s->converged) {
        pm = s->p + s->q;
        den = pm + s->r;
        s->k = sig_real_isfinite(den) ? pm / den : SIG_REAL(1.0) / (SIG_REAL(1.0) + s->r / pm);
        pn = s->r * s->k;
        s->converged = pn == s->p;
        s->p = pn;
    }
    s->innov = z - s->x;
    if (sig_real_isfinite(s->innov)) s->x = s->x + s->k * s->innov;
    else s->x = (SIG_REAL(1.0) - s->k) * s->x + s->k * z;
    *out = s->x;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */

/* floor(2^46 / d) for 2^16 <= d < 2^31 by shift and subtract (init only). */
static uint32_t recip46(uint32_t d)
{
    uint32_t r = 1u, y = 0u;
    uint8_t i;
    for (i = 0u; i < 46u; i++) {
        r <<= 1;
        y <<= 1;
        if (r >= d) {
            r -= d;
            y |= 1u;
        }
    }
    return y;
}

sig_status sig_kalman1_init_q(sig_kalman1_q *s, uint32_t q_q30, uint32_t p0_q16,
                              int32_t x0_q7, bool seed_first)
{
    if (!s || q_q30 > SIG_KALMAN1_Q_MAX || p0_q16 > SIG_KALMAN1_P0_MAX) return SIG_ERR_ARG;
    s->q = q_q30;
    s->p0 = p0_q16;
    s->x0 = x0_q7;
    s->seed_first = seed_first;
    /* 1 + p0 + q in Q16 (q rounded to Q16): < 2^31 by the limits above */
    s->y1 = recip46(UINT32_C(65536) + p0_q16 + ((q_q30 + UINT32_C(8192)) >> 14));
    return sig_kalman1_reset_q(s);
}

sig_status sig_kalman1_reset_q(sig_kalman1_q *s)
{
    if (!s) return SIG_ERR_ARG;
    s->x = s->x0;
    s->innov = 0;
    s->y = SIG_Q30_ONE;
    s->phase = 0u;
    s->seeded = false;
    return SIG_OK;
}

sig_status sig_kalman1_restart_q(sig_kalman1_q *s)
{
    if (!s) return SIG_ERR_ARG;
    s->phase = 0u;
    return SIG_OK;
}

/* One Newton step towards 1/d: y (2 - d y), all Q30; d < 2^32, y <= 2^30. */
static uint32_t newton_recip(uint32_t y, uint32_t d)
{
    uint32_t t = mul_q30(d, y);
    if (t >= UINT32_C(0x80000000)) return y >> 1;   /* seed above 2/d: halve (not reached from valid seeds) */
    return mul_q30(y, UINT32_C(0x80000000) - t);
}

sig_status sig_kalman1_step_q(sig_kalman1_q *s, int32_t z_q7, int32_t *out_q7)
{
    uint32_t d, yn, half;
    if (!s || !out_q7) return SIG_ERR_ARG;
    if (!s->seeded) {
        s->seeded = true;
        if (s->seed_first) s->x = z_q7;
    }
    if (s->phase == 0u) {
        s->y = s->y1;
        s->phase = 1u;
    } else if (s->phase != 3u) {
        d = SIG_Q30_ONE + (SIG_Q30_ONE - s->y) + s->q;        /* 1 + K + q < 3 */
        if (s->phase == 1u) {
            half = d >> 1;                                     /* seed 1.5 - d/2, at least 0.25 */
            yn = half < UINT32_C(0x50000000) ? UINT32_C(0x60000000) - half : UINT32_C(0x10000000);
        } else {
            yn = s->y;
        }
        yn = newton_recip(newton_recip(yn, d), d);
        if (yn > SIG_Q30_ONE) yn = SIG_Q30_ONE;
        if (yn == 0u) yn = 1u;
        s->phase = (s->phase == 2u && yn == s->y) ? 3u : 2u;
        s->y = yn;
    }
    s->innov = sig_sat_sub32(z_q7, s->x);
    s->x = sig_sat_add32(s->x, mul_q30_gain(s->innov, SIG_Q30_ONE - s->y));
    *out_q7 = s->x;
    return SIG_OK;
}
