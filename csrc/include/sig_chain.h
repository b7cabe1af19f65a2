/* sig_chain.h - the weighing chain: limit -> anti-pulse -> Kalman -> stability,
 * wired as in the weighing paper, plus three switchable fixes beyond the weighing paper.
 *
 * Per sample: the limit filter replaces an impulse by Dc; the anti-pulse
 * window takes the result and its trimmed mean m becomes the new Dc; the
 * Kalman filter smooths m; the stability detector watches the Kalman output;
 * the output is the Kalman estimate minus the tare offset.
 *
 * Beyond the weighing paper (each off in the "paper" preset):
 *  - lock-out fix (lockout_n > 0): see sig_limit.h.  On a re-seed the window
 *    is emptied so Dc follows the new level at once.
 *  - motion-aware settling (motion_band > 0; the host presets derive it from
 *    the reading variance R as 4 sigma of the window mean, 4 * sqrt(R / (N - 2)),
 *    and A0 as 6 * sqrt(R): tests/spec/chain.py): when |m - x| > motion_band for
 *    motion_count successive samples, or on a lock-out re-seed, the load
 *    moved: the window is emptied (refilled from the current sample) and the
 *    Kalman P is set back to P0, so the filter restarts as a running mean of
 *    the new level instead of following at the steady-state gain.
 *  - tare and zero tracking: sig_chain_tare_* takes the current Kalman
 *    output as the offset when stable, or at the next stable sample
 *    (pending).  Zero tracking (zero_band > 0): while stable and
 *    |x - offset| <= zero_band, the offset moves towards x by at most
 *    zero_rate per sample.  With noise_auto the test is |x - zero| <=
 *    zero_band instead, zero the set zero (the offset at the last tare,
 *    set_offset or reset): tracking's total correction stays within the
 *    band, so it cannot carry a stable output away from what the samples
 *    say (in raw codes 0 is no zero until a tare).
 *
 * Fixed form (_q; Q0 in, Q24.7 out: not the Q format of other modules' _q):
 * int32 ADC codes in (clamped to +-SIG_CODE_MAX, status
 * SIG_WARN_CLAMPED); output, offset, thresholds of the Kalman side in Q24.7
 * (codes * 128); see sig_kalman1.h for the gain formats.
 *
 *  - noise measured on the fly (noise_auto): a sig_noise estimator sees
 *    every sample unless it or the one before was an impulse or the load
 *    is moving (a restart or re-seed and `window` samples after it, or a
 *    motion run under way; see SIG_CHAIN_NOISE_FROZEN_MAX), and before
 *    each sample the thresholds follow its sigma:
 *        A0 = 6 sigma, motion_band = 1.5 sigma, stable_step = sigma / 4,
 *        zero_band = sigma, zero_rate = sigma / 16 per sample
 *    (the fixed form by shifts and adds; A0 in codes, rounded, >= 1; until
 *    the estimator has seen one difference, A0 takes every sample).  The
 *    given a0, motion_band, stable_step, zero_band, zero_rate are replaced.
 *    A restart also starts the Kalman estimate again from the new samples,
 *    and while the anti-pulse window is filling, or the output is not yet
 *    stable, the window's trimmed mean is the estimate (the Kalman filter
 *    is re-seeded on it): a slow final approach of the load is forgotten
 *    with the window instead of being averaged in.  No sensor constant:
 *    the float form is scale invariant (input * c -> output * c).
 *    Ramps (a pour is a load change, not a glitch): when the limit rejects
 *    a second sample on one side and it lies further out than the first by
 *    more than A0/2 (and the two steps out, Dc to the first and the first to
 *    the second, within a factor 4 of each other), both moved on - or a first
 *    rejected sample when the sample before, accepted, lay more than A0/2 out
 *    on the same side and the two steps agree within a factor 2 (a ramp of
 *    3-6 sigma per sample, whose first sample is within A0) - it is taken (status
 *    SIG_LIMIT_RESEEDED | SIG_CHAIN_RAMP) and the load is followed as a
 *    ramp - each sample within A0 of last + slope is the output (the window
 *    holds it alone; SIG_CHAIN_RAMP), the slope moving half way to each new
 *    difference.  A
 *    sample within A0/2 of the last followed one and nearer it than the
 *    prediction is followed with the slope kept; the second in a row ends the
 *    ramp (the load stopped; a restart, SIG_CHAIN_MOTION).
 *    A rejected sample back within A0 of where the ramp began ends it and is
 *    taken (a glitch pair or a bump that came back, SIG_LIMIT_RESEEDED);
 *    rejected before any sample was followed, nearer that level than the
 *    prediction and no farther from it than the ramp's last value, the start
 *    was a glitch pair:
 *    the level before it is held and the window restarts from it
 *    (SIG_WARN_REJECTED | SIG_LIMIT_RESEEDED); otherwise the prediction is
 *    held when the sample lies beyond it on the ramp's side (a glitch in a
 *    pour), else the last followed value (a bump's top, a swing turning),
 *    the ramp predicted two slopes on, and a second rejection in a row ends
 *    it (the last followed value held).  Single glitches and pairs at one level stay rejected.
 *    Stable only when the output is backed by the samples: the stability
 *    detector's verdict is reported only on a sample that was not replaced,
 *    held, re-seeded, a motion restart or a ramp sample, with a full window
 *    since the last restart, no motion run under way, no drift (the output
 *    moved by at most sigma over the last block of `window` samples, blocks
 *    counted from the first full window after a restart: a load still
 *    creeping or swinging out; the first block is held as drifting when the
 *    output, as the window refilled, lay more than 2^10 sigma from the last
 *    stable output: a creep or swing of a few per mille of so large a
 *    change still exceeds the noise when that block ends), the sample within
 *    2 sigma of the output (near_band: a two-sided 95 % test, one sample of
 *    evidence against the output), the window's trimmed mean within
 *    1 sigma of it (a load that has begun to move faster than the output
 *    follows) and no trend: the exponentially weighted mean (weight 1/2)
 *    of the sample's residual (sample - output, started again with the
 *    window) within 2 of its standard deviations, 2 sigma / sqrt(3), of 0
 *    (a load that moves by a few sigma per sample, too slowly for the
 *    motion test to trip at once; sig_chain_stages.h).
 *
 * Start of the Kalman estimate: seed_first takes the first window mean;
 * without it the estimate starts from x0 and the parameters must trust the
 * first samples, P0 >= R (the first gain >= 1/2; a constant input is then
 * within |x0 - input| / (n + 1) after n samples).  noise_auto re-seeds on
 * the window mean while settling and needs seed_first (with it off the
 * filter would restart from x0 every sample and never reach the input).
 * _init refuses other combinations with SIG_ERR_ARG.
 *
 * Status: negative = error, nothing changed; otherwise OR of
 * SIG_WARN_CLAMPED, SIG_WARN_REJECTED (limit replaced the sample, or a
 * non-finite sample), SIG_LIMIT_RESEEDED, SIG_CHAIN_MOTION, SIG_CHAIN_TARED.
 * A non-finite sample before the first finite one returns SIG_ERR_NONFINITE.
 */
#ifndef SIG_CHAIN_H
#define SIG_CHAIN_H

#include "sig_types.h"
#include "sig_limit.h"
#include "sig_antipulse.h"
#include "sig_kalman1.h"
#include "sig_stable.h"
#include "sig_noise.h"

/* SIG_CHAIN_MOTION, SIG_CHAIN_TARED, SIG_CHAIN_NOISE_FLOOR: sig_status.h */

/* noise_auto: a count goes up by one on each sample the noise estimator
 * skips (restart, re-seed, hold-off, a motion run, an impulse) and down by
 * one on each other sample (between 0 and twice this); from this value on
 * the estimator sees every sample, with its warm-up steps again: so much
 * motion is noise, and a lasting rise in noise cannot freeze the estimate.
 * A ramp sample (a pour) is skipped and leaves the count as it is. */
#define SIG_CHAIN_NOISE_FROZEN_MAX 64u

typedef struct {
    sig_real a0;            /* limit threshold, > 0 */
    uint8_t window;         /* anti-pulse N, 3..32 */
    sig_real q, r, p0, x0;  /* Kalman */
    bool seed_first;        /* Kalman starts from the first measurement */
    sig_real stable_step;   /* >= 0 */
    uint8_t stable_count;   /* >= 1 */
    uint8_t lockout_n;      /* 0 = paper (no fix) */
    sig_real motion_band;   /* 0 = off */
    uint8_t motion_count;   /* >= 1 */
    sig_real zero_band;     /* 0 = no zero tracking */
    sig_real zero_rate;     /* max offset change per sample, >= 0 */
    bool noise_auto;        /* thresholds follow the measured noise (see above) */
} sig_chain_params_f;

typedef struct {
    int32_t a0;             /* codes, > 0 */
    uint8_t window;
    uint32_t q_q30;         /* Q/R in Q2.30, <= 1.0 */
    uint32_t p0_q16;        /* P0/R in Q16.16, <= 16384 */
    int32_t x0_q7;          /* Q24.7 */
    bool seed_first;
    int32_t stable_step_q7; /* Q24.7, >= 0 */
    uint8_t stable_count;
    uint8_t lockout_n;
    int32_t motion_band_q7; /* Q24.7, 0 = off */
    uint8_t motion_count;
    int32_t zero_band_q7;   /* Q24.7, 0 = off */
    int32_t zero_rate_q7;   /* Q24.7 per sample, >= 0 */
    bool noise_auto;
} sig_chain_params_q;

/* noise_auto: when a sample may update the noise estimate (sig_chain.c),
 * the same for both forms. */
typedef struct {
    bool rejected_prev;     /* the previous sample was rejected */
    uint8_t holdoff;        /* samples left before updates resume after an event */
    uint8_t frozen;         /* how long updates have been held (SIG_CHAIN_NOISE_FROZEN_MAX) */
} sig_chain_gate;

typedef struct {
    sig_limit_f limit;
    sig_antipulse_f ap;
    sig_kalman1_f kf;
    sig_stable_f st;
    sig_real motion_band, zero_band, zero_rate;
    sig_real offset;        /* tare / zero offset */
    sig_real zero;          /* the set zero: the offset at the last tare, set_offset or reset */
    sig_real out;           /* last output */
    uint8_t motion_count, motion_run;
    bool tare_pending, stable, has_out;
    bool noise_auto;
    sig_chain_gate gate;
    sig_noise_f noise;
    /* noise_auto: the ramp follower and the backing of `stable` (above) */
    sig_real slope, last, origin;   /* per-sample slope, last followed value, Dc before the ramp */
    sig_real pred;          /* the ramp's prediction for this sample */
    sig_real prev_x;        /* last finite sample */
    sig_real near_band;     /* 2 sigma */
    sig_real trend_mean;    /* the residual's weighted mean (above) */
    bool ramp, missed, paused;   /* following a ramp; its last sample held; it looked stopped */
    bool followed;          /* a sample followed since the ramp began */
    bool settled;           /* the stability detector's own verdict */
    sig_real anchor;        /* the output at the last block's start */
    sig_real level;         /* the output at the last stable sample */
    uint8_t drift_age;      /* samples into the block */
    bool drifting;          /* the last block moved the output by more than sigma */
    bool has_level;         /* a sample was stable since the reset */
    bool hold_block;        /* the first block after a large change counts as drifting */
} sig_chain_f;

typedef struct {
    sig_limit_q limit;
    sig_antipulse_q ap;
    sig_kalman1_q kf;
    sig_stable_q st;
    int32_t motion_band, zero_band, zero_rate;   /* Q24.7 */
    int32_t offset;         /* Q24.7 */
    int32_t zero;           /* Q24.7, the set zero (as the float form's) */
    int32_t out;            /* Q24.7 */
    uint8_t motion_count, motion_run;
    bool tare_pending, stable, has_out;
    bool noise_auto;
    sig_chain_gate gate;
    sig_noise_q noise;
    int32_t slope, last, origin, prev_x;   /* codes (|slope| <= 2^25) */
    int32_t pred;           /* codes */
    int32_t near_band;      /* Q24.7 */
    int32_t trend_mean;     /* Q24.7 */
    bool trending;          /* this sample's trend verdict */
    bool ramp, missed, paused, followed, settled;
    int32_t anchor;         /* Q24.7 */
    int32_t level;          /* Q24.7 */
    uint8_t drift_age;
    bool drifting, has_level, hold_block;
} sig_chain_q;

/* The weighing paper's parameters in kg: Q 1e-7, R 0.05, x0 1, P0 10, N 12, A0 2 kg
 * (just above the weighing paper's largest raw reading error, 1.86 kg), stable step
 * 0.01 kg, count 1; no lock-out fix, no motion mode, no zero tracking. */
sig_status sig_chain_params_paper_f(sig_chain_params_f *p);

/* The default chain ("auto", sig_chain_auto.c): no sensor constant and no
 * unit; the noise is measured on the fly (noise_auto) and the thresholds
 * follow it; the Kalman filter is set by ratios (r = 1: q and p0 are Q/R and
 * P0/R).  The same parameters as pysig's default Chain(), float and fixed. */
sig_status sig_chain_params_auto_f(sig_chain_params_f *p);
sig_status sig_chain_params_auto_q(sig_chain_params_q *p);

sig_status sig_chain_init_f(sig_chain_f *c, const sig_chain_params_f *p);
sig_status sig_chain_reset_f(sig_chain_f *c);        /* all stages, offset 0 */
sig_status sig_chain_step_f(sig_chain_f *c, sig_real x, sig_real *out, bool *stable);   /* a buffer at once: sig_chain_batch.h */
sig_status sig_chain_tare_f(sig_chain_f *c);         /* now if stable, else at the next stable sample */
sig_status sig_chain_set_offset_f(sig_chain_f *c, sig_real offset);

sig_status sig_chain_init_q(sig_chain_q *c, const sig_chain_params_q *p);
sig_status sig_chain_reset_q(sig_chain_q *c);
sig_status sig_chain_step_q(sig_chain_q *c, int32_t x, int32_t *out_q7, bool *stable);
sig_status sig_chain_tare_q(sig_chain_q *c);
sig_status sig_chain_set_offset_q(sig_chain_q *c, int32_t offset_q7);

#endif /* SIG_CHAIN_H */
