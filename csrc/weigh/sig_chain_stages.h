/* sig_chain_stages.h - private to csrc/weigh: the chain's own per-sample
 * decisions (motion test, tare, zero tracking), written once and shared by
 * the step path (sig_chain.c) and the batch path (sig_chain_batch.c), so the
 * two cannot drift apart.  static inline (sdcc: plain static, see below):
 * each caller keeps its state in registers; the compiler sees through the
 * pointers. */
#ifndef SIG_CHAIN_STAGES_H
#define SIG_CHAIN_STAGES_H

#include "sig_types.h"
#include "sig_chain.h"
#include "sig_chain_noise.h"

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

/* Motion test: a sample whose Kalman innovation is outside the motion band
 * (`moving`, tested by the caller in its own number format) counts one more
 * sample of motion, anything else ends the run.  True when the run reaches
 * count: the caller restarts window and Kalman, and the run starts again. */
SIG_CHAIN_STAGE bool sig_chain_motion(bool moving, uint8_t *run, uint8_t count)
{
    *run = SIG_RUN_NEXT(*run, moving);
    if (*run < count) return false;
    *run = 0u;
    return true;
}

/* Tare and zero tracking on a stable sample xk: a pending tare takes xk as
 * the offset (returns true); otherwise, while |xk - offset| <= zband, the
 * offset moves towards xk by at most zrate (zband 0: no tracking). */
SIG_CHAIN_STAGE bool sig_chain_offset_f(sig_real xk, sig_real *offset, bool *tare_pending,
                                      sig_real zband, sig_real zrate)
{
    sig_real dz = xk - *offset;
    if (*tare_pending) {
        *tare_pending = false;
        *offset = xk;
        return true;
    }
    if (zband <= SIG_REAL(0.0) || dz > zband || -dz > zband) return false;
    *offset += dz > zrate ? zrate : (dz < -zrate ? -zrate : dz);
    return false;
}

/* no subtraction while nothing is pending and tracking is off: the 8051
 * pays a call for each saturating operation */
SIG_CHAIN_STAGE bool sig_chain_offset_q(int32_t xk, int32_t *offset, bool *tare_pending,
                                      int32_t zband, int32_t zrate)
{
    int32_t dz;
    if (*tare_pending) {
        *tare_pending = false;
        *offset = xk;
        return true;
    }
    if (zband <= 0) return false;
    dz = sig_sat_sub32(xk, *offset);
    if (sig_abs32_sat(dz) > zband) return false;
    *offset = sig_sat_add32(*offset, dz > zrate ? zrate : (dz < -zrate ? -zrate : dz));
    return false;
}

/* noise_auto: the thresholds from the measured sigma s (sig_chain.h); with
 * no difference seen yet (`none`) no impulse can be told from noise: A0
 * takes every sample. */
SIG_CHAIN_STAGE void sig_chain_thresholds_f(sig_real s, bool none, sig_real *a0, sig_real *band,
                                          sig_real *step, sig_real *zband, sig_real *zrate)
{
    *a0 = SIG_REAL(6.0) * (none ? SIG_NOISE_MAX_F : s);
    *band = SIG_REAL(1.5) * s;
    *step = SIG_REAL(0.25) * s;
    *zband = SIG_REAL(2.0) * s;
    *zrate = SIG_REAL(0.0625) * s;
}


#endif /* SIG_CHAIN_STAGES_H */
