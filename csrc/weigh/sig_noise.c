/* sig_noise.c - the noise sigma measured on the fly; see sig_noise.h. */
#include "sig_noise.h"
#include "sig_antipulse.h"
#include "sig_noise_stages.h"

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */

sig_status sig_noise_reset_f(sig_noise_f *s)
{
    if (!s) return SIG_ERR_ARG;
    s->prev = SIG_REAL(0.0);
    s->sigma = SIG_NOISE_FLOOR_ABS;
    s->res = SIG_REAL(0.0);
    s->count = 0u;
    s->has_prev = false;
    return SIG_OK;
}

sig_status sig_noise_step_f(sig_noise_f *s, sig_real x, bool update)
{
    if (!s) return SIG_ERR_ARG;
    return sig_noise_next_f(s, x, update);
}

bool sig_noise_at_floor_f(const sig_noise_f *s)
{
    return s->sigma <= sig_noise_floor_f(s->prev, s->res);
}
#endif /* SIG_NO_FLOAT */

sig_status sig_noise_reset_q(sig_noise_q *s)
{
    if (!s) return SIG_ERR_ARG;
    s->prev = 0;
    s->sigma = SIG_NOISE_FLOOR_Q7;
    s->count = 0u;
    s->has_prev = false;
    return SIG_OK;
}

sig_status sig_noise_step_q(sig_noise_q *s, int32_t x, bool update)
{
    int32_t d, up, sigma;                       /* the state in locals: one load, one store */
    uint8_t count;
    if (!s) return SIG_ERR_ARG;
    if (x > SIG_CODE_MAX) x = SIG_CODE_MAX;
    else if (x < -SIG_CODE_MAX) x = -SIG_CODE_MAX;
    if (s->has_prev && update) {
        sigma = s->sigma;
        count = s->count;
        d = x - s->prev;                        /* |codes| <= 2^24 - 1: no overflow */
        if (d < 0) d = -d;
        d = d > (INT32_MAX >> 7) ? INT32_MAX : (int32_t)((uint32_t)d << 7);
        if (count == 0u) {
            sigma = d < SIG_NOISE_MAX_Q7 ? d : SIG_NOISE_MAX_Q7;
        } else {
            /* constant shifts (a variable one is a loop on the MCUs) */
            if (count >= 56u) up = sigma >> 5;
            else if (count >= SIG_NOISE_WARMUP) up = sigma >> 4;
            else if (count >= 8u) up = sigma >> 3;
            else up = sigma >> 2;                /* sigma > 0 */
            if (d > sigma) {
                sigma += up;
                if (sigma > SIG_NOISE_MAX_Q7) sigma = SIG_NOISE_MAX_Q7;
            } else if (d < sigma) {
                sigma -= up - (up >> 3);
            }
        }
        if (count < 255u) count++;
        s->count = count;
        s->sigma = sigma < SIG_NOISE_FLOOR_Q7 ? SIG_NOISE_FLOOR_Q7 : sigma;
    }
    s->prev = x;
    s->has_prev = true;
    return SIG_OK;
}

bool sig_noise_at_floor_q(const sig_noise_q *s)
{
    return s->sigma <= SIG_NOISE_FLOOR_Q7;
}
