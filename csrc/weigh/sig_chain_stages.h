/* sig_chain_stages.h - private to csrc/weigh: the chain's own per-sample
 * decisions (motion test, tare, zero tracking), written once and shared by
 * the step path (sig_chain.c) and the batch path (sig_chain_batch.c), so the
 * two cannot drift apart.  static inline (sdcc: plain static, see below):
 * each caller keeps its state in registers; the compiler sees through the
 * pointers. */
#ifndef SIG_CHAIN_STAGES_H
#define SIG_CHAIN_STAGES_H

#include "sig_types.h"

/* sdcc inlines a static inline function's locals and spill temporaries into
 * the caller's frame: with --stack-auto sig_chain_step_q's frame grew past
 * what the 8051's 256-byte internal RAM holds on the chain's deepest call
 * path.  For sdcc the stages are ordinary static functions (each frame lives
 * only during its own call); gcc/clang keep inlining them (same results). */
#ifdef __SDCC
#define SIG_CHAIN_STAGE static
#else
#define SIG_CHAIN_STAGE static inline
#endif

/* Motion test: |e| > band counts one more sample of motion (run saturates
 * at 255), anything else ends the run.  True when the run reaches count:
 * the caller restarts window and Kalman, and the run starts again at 0. */
SIG_CHAIN_STAGE bool sig_chain_motion_f(sig_real e, sig_real band, uint8_t *run, uint8_t count)
{
    if (e > band || -e > band) {
        if (*run < 255u) (*run)++;
    } else {
        *run = 0u;
    }
    if (*run >= count) {
        *run = 0u;
        return true;
    }
    return false;
}

SIG_CHAIN_STAGE bool sig_chain_motion_q(int32_t e, int32_t band, uint8_t *run, uint8_t count)
{
    if (sig_abs32_sat(e) > band) {
        if (*run < 255u) (*run)++;
    } else {
        *run = 0u;
    }
    if (*run >= count) {
        *run = 0u;
        return true;
    }
    return false;
}

/* Tare and zero tracking on a stable sample xk: a pending tare takes xk as
 * the offset (returns true); otherwise, while |xk - offset| <= zband, the
 * offset moves towards xk by at most zrate (zband 0: no tracking). */
/* A tare: the offset becomes xk, nothing is pending any more. */
SIG_CHAIN_STAGE void sig_chain_take_tare_f(sig_real xk, sig_real *offset, bool *tare_pending)
{
    *offset = xk;
    *tare_pending = false;
}

SIG_CHAIN_STAGE bool sig_chain_offset_f(sig_real xk, sig_real *offset, bool *tare_pending,
                                      sig_real zband, sig_real zrate)
{
    sig_real dz;
    if (*tare_pending) {
        sig_chain_take_tare_f(xk, offset, tare_pending);
        return true;
    }
    if (zband > SIG_REAL(0.0)) {
        dz = xk - *offset;
        if (dz <= zband && -dz <= zband) {
            if (dz > zrate) dz = zrate;
            if (dz < -zrate) dz = -zrate;
            *offset += dz;
        }
    }
    return false;
}

/* A tare: the offset becomes xk, nothing is pending any more. */
SIG_CHAIN_STAGE void sig_chain_take_tare_q(int32_t xk, int32_t *offset, bool *tare_pending)
{
    *offset = xk;
    *tare_pending = false;
}

SIG_CHAIN_STAGE bool sig_chain_offset_q(int32_t xk, int32_t *offset, bool *tare_pending,
                                      int32_t zband, int32_t zrate)
{
    int32_t dz;
    if (*tare_pending) {
        sig_chain_take_tare_q(xk, offset, tare_pending);
        return true;
    }
    if (zband > 0) {
        dz = sig_sat_sub32(xk, *offset);
        if (sig_abs32_sat(dz) <= zband) {
            if (dz > zrate) dz = zrate;
            if (dz < -zrate) dz = -zrate;
            *offset = sig_sat_add32(*offset, dz);
        }
    }
    return false;
}

#endif /* SIG_CHAIN_STAGES_H */
