/* sig_chain_auto.c - the parameters of the default weighing chain ("auto"):
 * the one place their numbers are written (pysig.weigh.presets is checked
 * against these constructors); see sig_chain.h. */
#include "sig_chain.h"

/* Set by ratios only (no sensor constant, no unit): R = 1, Q/R = 1e-3 (the
 * estimate forgets the last swing of a load change within ~3 s at 10 Hz),
 * P0/R = 10, x0 0, seeded from the first sample; lock-out fix after 3
 * rejections on one side, motion after 2 samples beyond the band, stable
 * after 5 steps within the band.  The thresholds follow the measured noise
 * (noise_auto): the values here are those at the noise floor, replaced from
 * the measured sigma before every sample. */
#define AUTO_WINDOW SIG_ANTIPULSE_DEFAULT
#define AUTO_STABLE_COUNT 5u
#define AUTO_LOCKOUT_N 3u
#define AUTO_MOTION_COUNT 2u

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
sig_status sig_chain_params_auto_f(sig_chain_params_f *p)
{
    sig_real s = SIG_NOISE_FLOOR_ABS;
    if (!p) return SIG_ERR_ARG;
    p->a0 = SIG_REAL(6.0) * s;
    p->window = AUTO_WINDOW;
    p->q = SIG_REAL(1e-3);
    p->r = SIG_REAL(1.0);
    p->p0 = SIG_REAL(10.0);
    p->x0 = SIG_REAL(0.0);
    p->seed_first = true;
    p->stable_step = SIG_REAL(0.25) * s;
    p->stable_count = AUTO_STABLE_COUNT;
    p->lockout_n = AUTO_LOCKOUT_N;
    p->motion_band = SIG_REAL(1.5) * s;
    p->motion_count = AUTO_MOTION_COUNT;
    p->zero_band = s;
    p->zero_rate = SIG_REAL(0.0625) * s;
    p->noise_auto = true;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */

/* The same in fixed point: Q/R 1e-3 in Q2.30 (rounded), P0/R 10 in Q16.16,
 * the thresholds of the floor sigma (SIG_NOISE_FLOOR_Q7) as sig_chain.c
 * derives them. */
sig_status sig_chain_params_auto_q(sig_chain_params_q *p)
{
    int32_t s = SIG_NOISE_FLOOR_Q7;
    if (!p) return SIG_ERR_ARG;
    p->a0 = (6 * s + 64) >> 7;
    p->window = AUTO_WINDOW;
    p->q_q30 = UINT32_C(1073742);              /* round(1e-3 * 2^30) */
    p->p0_q16 = UINT32_C(655360);              /* 10 * 2^16 */
    p->x0_q7 = 0;
    p->seed_first = true;
    p->stable_step_q7 = s >> 2;
    p->stable_count = AUTO_STABLE_COUNT;
    p->lockout_n = AUTO_LOCKOUT_N;
    p->motion_band_q7 = s + (s >> 1);
    p->motion_count = AUTO_MOTION_COUNT;
    p->zero_band_q7 = s;
    p->zero_rate_q7 = s >> 4;
    p->noise_auto = true;
    return SIG_OK;
}
