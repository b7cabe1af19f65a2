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

/* noise_auto, the ramp follower before the limit: a sample that looks as if
 * the load stopped (within A0/2 of the last followed one and nearer it than
 * the prediction, tested by the caller) pauses the ramp; the second in a
 * row ends it (returns true). */
SIG_CHAIN_STAGE bool sig_chain_ramp_stop(bool looks_stopped, bool *on, bool *missed, bool *paused)
{
    if (!looks_stopped) {
        *paused = false;
        return false;
    }
    if (*paused) {
        *on = *missed = *paused = false;
        return true;
    }
    *paused = true;
    return false;
}

/* noise_auto, the ramp follower after the limit (sig_chain.h): what this
 * sample is for the ramp, from the limit's status and run (a re-seed ends
 * the ramp).  The caller does the arithmetic of each case in its own
 * number format. */
#define SIG_CHAIN_RAMP_NONE 0u
#define SIG_CHAIN_RAMP_FOLLOW 1u     /* accepted within A0 of the prediction */
#define SIG_CHAIN_RAMP_BROKEN 2u     /* rejected: back near the origin, or hold */
#define SIG_CHAIN_RAMP_TRY 3u        /* a rejection on one side: a ramp if it and the one before moved on */
SIG_CHAIN_STAGE uint8_t sig_chain_ramp_case(bool *on, bool *missed, bool *paused, sig_status ret, uint8_t run)
{
    bool rejected = (ret & SIG_WARN_REJECTED) != 0;
    if (!*on) return rejected && run >= 1u ? SIG_CHAIN_RAMP_TRY : SIG_CHAIN_RAMP_NONE;
    if ((ret & SIG_LIMIT_RESEEDED) != 0) {
        *on = *missed = *paused = false;
        return SIG_CHAIN_RAMP_NONE;
    }
    return rejected ? SIG_CHAIN_RAMP_BROKEN : SIG_CHAIN_RAMP_FOLLOW;
}

/* A rejected sample during a ramp, not back at its origin: the last followed
 * value is held; the first such sample keeps the ramp (a glitch in a pour),
 * a second in a row ends it.  Returns the status. */
SIG_CHAIN_STAGE sig_status sig_chain_ramp_hold(bool *on, bool *missed, bool *paused, sig_status ret)
{
    if (*missed) {
        *on = *missed = *paused = false;
        return ret;
    }
    *missed = true;
    return (sig_status)(ret | SIG_CHAIN_RAMP);
}

/* a sample the ramp logic took after the limit had rejected it: no impulse,
 * a re-seed (window and Kalman restart) */
#define SIG_CHAIN_TAKEN(ret) ((sig_status)(((ret) & ~SIG_WARN_REJECTED) | SIG_LIMIT_RESEEDED))

/* noise_auto: the output's drift over blocks of n samples (sig_chain.h).
 * True when the caller sets the anchor to the output: on every sample while
 * the window refills (drifting until a block is seen; `big`: the output lies
 * more than 2^10 sigma from the last stable output, tested by the caller in
 * its own format, and the first block is held as drifting, *hold), and at
 * each block's end (the caller first sets `drifting` from the block's
 * change, sig_chain_drift_verdict). */
SIG_CHAIN_STAGE bool sig_chain_drift_due(bool refilling, bool big, uint8_t *age, uint8_t n, bool *drifting,
                                         bool *hold)
{
    if (refilling) {
        *age = 0u;
        *drifting = true;
        *hold = big;
        return true;
    }
    if (++*age < n) return false;
    *age = 0u;
    return true;
}

/* noise_auto: a block's verdict: it moved the output by more than sigma, or
 * it is the first block after a change of more than 2^10 sigma (a creep or
 * a swing of a few per mille of so large a change still exceeds the noise
 * when that block ends) */
SIG_CHAIN_STAGE bool sig_chain_drift_verdict(bool moved, bool *hold)
{
    bool v = moved || *hold;
    *hold = false;
    return v;
}

/* noise_auto: the stability detector's verdict counts only when the output
 * is backed by the samples (sig_chain.h); `near`: the sample and the window
 * mean near the output, tested by the caller in its own format; `trending`:
 * the samples have begun to leave the output on one side (sig_chain_trend_*). */
SIG_CHAIN_STAGE bool sig_chain_backed(sig_status ret, uint8_t held, uint8_t n, uint8_t motion_run,
                                      bool drifting, bool trending, bool near)
{
    /* the last three combined without branches: on noise each is a coin
     * toss now and then, a mispredicted branch late in the sample's work */
    return (ret & (SIG_WARN_REJECTED | SIG_LIMIT_RESEEDED | SIG_CHAIN_MOTION | SIG_CHAIN_RAMP)) == 0
        && held == n && motion_run == 0u && (!drifting & !trending & near);
}

/* noise_auto: the trend test (sig_chain.h).  The residual r = y - output
 * goes into an exponentially weighted mean with weight 1/2 (the sample
 * 1/2, the one before 1/4, ...); on a still load its standard deviation is
 * sigma / sqrt(3), and the test is two-sided at 2 of them (95 %): a load
 * that has begun to move by 1-3 sigma per sample moves the mean out within
 * a sample or two, before the output lags 3 sigma behind it.  The mean
 * starts again with the window (refilling).  True while |mean| is beyond
 * the band, 2 / sqrt(3) = 1.1547 sigma taken as 37/32 sigma (shifts in the
 * fixed form). */
#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
SIG_CHAIN_STAGE bool sig_chain_trend_f(bool refilling, sig_real r, sig_real sigma, sig_real *mean)
{
    sig_real e, band;
    if (refilling) {
        *mean = SIG_REAL(0.0);
        return false;
    }
    e = *mean + (r - *mean) * SIG_REAL(0.5);
    *mean = e;
    band = sigma * SIG_REAL(1.15625);
#ifdef SIG_REAL_DOUBLE
    return (e > -e ? e : -e) > band;            /* host: |e| as a max, no branch (sig_chain_backed) */
#else
    return e > band || -e > band;               /* float in software (MCUs): fewer operations */
#endif
}
#endif /* SIG_NO_FLOAT */

/* the fixed form: r and sigma in Q24.7 (0 <= sigma <= 2^27), saturating */
SIG_CHAIN_STAGE bool sig_chain_trend_q(bool refilling, int32_t r, int32_t sigma, int32_t *mean)
{
    if (refilling) {
        *mean = 0;
        return false;
    }
    *mean = sig_sat_add32(*mean, sig_asr32(sig_sat_sub32(r, *mean), 1u));
    return sig_abs32_sat(*mean) > sigma + (sigma >> 3) + (sigma >> 5);
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
/* Tare and zero tracking on a stable sample xk: a pending tare takes xk as
 * the offset and as *zero (returns true); otherwise, while
 * |xk - *zero| <= zband, the offset moves towards xk by at most zrate
 * (zband 0: no tracking).  A sample not `stable` changes nothing; that is
 * tested last, after the tests that hold for long runs of samples (on noise
 * `stable` itself flips now and then: a branch on it first would be
 * mispredicted).  noise_auto passes the set zero (the offset at
 * the last tare, set_offset or reset): the offset then stays within the
 * band of it, so tracking's total correction is bounded (OIML R76 bounds
 * zero tracking's range around the set zero the same way); the
 * fixed-threshold presets pass the offset itself: a drift is followed
 * without bound. */
SIG_CHAIN_STAGE bool sig_chain_offset_f(bool stable, sig_real xk, sig_real *offset, sig_real *zero,
                                      bool *tare_pending, sig_real zband, sig_real zrate)
{
    sig_real dz = xk - *offset, dr;
    if (*tare_pending && stable) {
        *tare_pending = false;
        *offset = *zero = xk;
        return true;
    }
    dr = zero == offset ? dz : xk - *zero;      /* one soft-float subtraction less when they are one */
    /* out of the band first (the common case); on the host |dr| as a max, one
     * test; a float in software (MCUs) pays per operation: two tests */
#ifdef SIG_REAL_DOUBLE
    if ((dr > -dr ? dr : -dr) > zband || zband <= SIG_REAL(0.0) || !stable) return false;
#else
    if (dr > zband || -dr > zband || zband <= SIG_REAL(0.0) || !stable) return false;
#endif
    *offset += dz > zrate ? zrate : (dz < -zrate ? -zrate : dz);
    return false;
}
#endif /* SIG_NO_FLOAT */

/* no subtraction while nothing is pending and tracking is off, one when
 * zero is the offset itself: the 8051 pays a call for each saturating
 * operation */
SIG_CHAIN_STAGE bool sig_chain_offset_q(int32_t xk, int32_t *offset, int32_t *zero, bool *tare_pending,
                                      int32_t zband, int32_t zrate)
{
    int32_t dz;
    if (*tare_pending) {
        *tare_pending = false;
        *offset = *zero = xk;
        return true;
    }
    if (zband <= 0) return false;
    dz = sig_sat_sub32(xk, *offset);
    if (sig_abs32_sat(zero == offset ? dz : sig_sat_sub32(xk, *zero)) > zband) return false;
    *offset = sig_sat_add32(*offset, dz > zrate ? zrate : (dz < -zrate ? -zrate : dz));
    return false;
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
/* noise_auto: the thresholds from the measured sigma s (sig_chain.h;
 * fixed point: SIG_CHAIN_THRESHOLDS_Q in sig_chain_noise.h); with
 * no difference seen yet (`none`) no impulse can be told from noise: A0
 * takes every sample.  Each also alone, for a loop that derives one where
 * it is used (sig_chain_batch.c). */
#define SIG_CHAIN_A0_F(s, none) (SIG_REAL(6.0) * ((none) ? SIG_NOISE_MAX_F : (s)))
#define SIG_CHAIN_BAND_F(s) (SIG_REAL(1.5) * (s))
#define SIG_CHAIN_STEP_F(s) (SIG_REAL(0.25) * (s))
#define SIG_CHAIN_ZBAND_F(s) (s)
#define SIG_CHAIN_ZRATE_F(s) (SIG_REAL(0.0625) * (s))
#define SIG_CHAIN_NEAR_F(s) (SIG_REAL(2.0) * (s))
SIG_CHAIN_STAGE void sig_chain_thresholds_f(sig_real s, bool none, sig_real *a0, sig_real *band,
                                          sig_real *step, sig_real *zband, sig_real *zrate, sig_real *nband)
{
    *a0 = SIG_CHAIN_A0_F(s, none);
    *band = SIG_CHAIN_BAND_F(s);
    *step = SIG_CHAIN_STEP_F(s);
    *zband = SIG_CHAIN_ZBAND_F(s);
    *zrate = SIG_CHAIN_ZRATE_F(s);
    *nband = SIG_CHAIN_NEAR_F(s);
}
#endif /* SIG_NO_FLOAT */

#endif /* SIG_CHAIN_STAGES_H */
