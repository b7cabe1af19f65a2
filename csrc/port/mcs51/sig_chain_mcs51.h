/* sig_chain_mcs51.h - the fixed weighing chain (sig_chain_step_q, sig_chain.h)
 * spelt for the 8051: the same results bit for bit, in a form sdcc compiles
 * to short code.
 *
 * What differs from the portable chain (csrc/weigh/sig_chain.c):
 *  - one chain, at a fixed address: the state is the global sig_chain_mcs51
 *    (in the 8051's indirect RAM; the configuration sig_chain_mcs51_cfg and
 *    the window in xdata, the gain table in code memory) and the functions
 *    take no state pointer, so sdcc never goes through its 3-byte generic
 *    pointers;
 *  - the anti-pulse window holds int16 deviations from a base code (the
 *    first sample after every window reset), with a running sum and its
 *    extremes; the trimmed mean is base + round(t / (N - 2)), t the trimmed
 *    sum of deviations, by one 16x16 product with a reciprocal chosen at
 *    init (exact over the range it is used on: |t| small, see u_lim);
 *  - the Kalman gain is read from a table: the fixed gain recursion of
 *    sig_kalman1_step_q does not depend on the data, so after every
 *    (re)start it replays the same sequence K_0, K_1, ... and then holds
 *    its steady value.  sig_chain_mcs51_gains() fills the table by running
 *    the portable sig_kalman1 (host or target, once); the update
 *    x += K * innov is two 16x16 products while |innov| < 2^15;
 *  - the motion test and the stability test reuse the innovation and the
 *    Kalman increment (the same differences the portable stages form).
 * Anything outside the fast ranges (window filling, a sample rejected or
 * beyond the int16 deviations or the clamp, a large innovation, a lock-out re-seed, a motion restart, |x| >= 2^30)
 * takes a general 32-bit branch with the same results, only slower.
 *
 * Range: the window's deviations must fit int16 around some base; a step
 * whose sample cannot be held so (the window would span more than 32767
 * codes) re-bases the window, and if even that cannot hold it returns
 * SIG_ERR_ARG with the state unchanged.  The spread of the window stays
 * within a few A0 (every accepted sample is within A0 of the trimmed mean),
 * so init accepts A0 <= 8191 codes (a quarter of the int16 range; the
 * bit-exactness tests draw A0 up to it).
 *
 * The default chain (noise_auto: the noise measured on the fly, every
 * threshold following it, the ramp follower, impulses and motion counted
 * apart, `stable` only when backed by the samples; sig_chain.h) runs when
 * the port is compiled with SIG_CHAIN_MCS51_AUTO (and -I csrc/weigh for the
 * shared stage code); without it init refuses noise_auto with SIG_ERR_ARG,
 * so fixed-threshold firmware links none of the portable chain.  Its state
 * is a portable sig_chain_q in xdata (sig_chain_mcs51_auto): every step that
 * is not the steady state (window filling or restarting, the output not yet
 * settled, a sample rejected, re-seeded or out of the int16 deviations, a
 * ramp, a motion restart) runs the portable sig_chain_step_q on it, so any
 * rule of the portable chain reaches the port by itself.  The steady state
 * (settled, window full, the sample accepted, no ramp, no motion restart)
 * runs here on the deviation window and the gain table, with the portable
 * chain's decisions taken from the shared stage code (sig_chain_stages.h:
 * drift blocks, backing of `stable`, tare and zero tracking, the motion
 * run; sig_chain_noise.h: the noise gate and the thresholds; sig_noise.c:
 * the estimator), and the noise estimate, gate and thresholds kept in the
 * portable struct.  The port's hot fields are copied into the portable
 * struct before a portable step and back after it when the next step may be
 * the steady state (`hot`).  A window that cannot be held as int16
 * deviations stays with the portable step: no range error in this mode. */
#ifndef SIG_CHAIN_MCS51_H
#define SIG_CHAIN_MCS51_H

#include "sig_chain.h"

#ifdef __SDCC
#define SIG_MCS51_DATA  __data
#define SIG_MCS51_IDATA __idata
#define SIG_MCS51_XDATA __xdata
#define SIG_MCS51_CODE  __code
#define SIG_MCS51_REENTRANT __reentrant   /* locals on the stack, not in direct RAM */
#else
#define SIG_MCS51_DATA
#define SIG_MCS51_IDATA
#define SIG_MCS51_XDATA
#define SIG_MCS51_CODE
#define SIG_MCS51_REENTRANT
#endif

#define SIG_CHAIN_MCS51_A0_MAX INT32_C(8191)

typedef struct {
    int32_t base;           /* codes: the window holds sample - base */
    int32_t sum;            /* sum of the held deviations */
    int32_t x;              /* Kalman estimate, Q24.7 */
    int32_t offset;         /* tare / zero offset, Q24.7 */
    int32_t out;            /* last output x - offset, Q24.7 */
    int32_t zero_band;      /* Q24.7, 0 = no zero tracking */
    int32_t stable_step, motion_band;     /* Q24.7; motion_band 0 = off */
    uint32_t k;             /* gain of the current step, Q2.30 */
    uint16_t gain_i;        /* next gain index (holds at the table's length) */
    int16_t a0;             /* codes, <= SIG_CHAIN_MCS51_A0_MAX */
    int16_t dc;             /* Dc - base (the limit's reference) */
    int16_t mx, mn;         /* extremes of the held deviations */
    int32_t base7;          /* base in Q24.7 */
    int16_t stable_step16, motion_band16;   /* min(., 32767): the fast path's int16 tests */
    uint16_t recip;         /* ceil(2^recip_shift / (N - 2)) */
    uint16_t u_lim;         /* floor(u * recip / 2^recip_shift) == floor(u / (N - 2)) for u <= u_lim */
    uint8_t recip_shift;    /* 16..30 */
    uint8_t half;           /* (N - 2) / 2: the rounding of the trimmed mean */
    uint8_t n, count, head; /* window length, samples held, next slot */
    uint8_t lock_run;
    int8_t lock_side;
    uint8_t motion_count, motion_run;
    uint8_t stable_count, stable_run;
    bool seeded, kf_seeded, has_prev, tare_pending, stable, has_out;
    bool small;             /* |x|, |offset| < 2^30, |base7| < 2^30 - 2^22: the fast path's range */
    bool noise_auto;        /* the default chain (SIG_CHAIN_MCS51_AUTO builds) */
    bool hot;               /* noise_auto: these fields hold the chain (else sig_chain_mcs51_auto does) */
} sig_chain_mcs51_state;

/* what the steady state does not touch (xdata) */
typedef struct {
    int32_t x0;             /* Q24.7, the estimate after a reset */
    int32_t zero_rate;      /* Q24.7 per sample */
    const SIG_MCS51_CODE uint32_t *gains;   /* K_0 .. K_(gain_n - 1) = steady gain */
    uint16_t gain_n;
    uint8_t lockout_n;
    bool seed_first;
} sig_chain_mcs51_config;

extern SIG_MCS51_IDATA sig_chain_mcs51_state sig_chain_mcs51;
extern SIG_MCS51_XDATA sig_chain_mcs51_config sig_chain_mcs51_cfg;
extern SIG_MCS51_XDATA int16_t sig_chain_mcs51_window[SIG_ANTIPULSE_MAX];
#ifdef SIG_CHAIN_MCS51_AUTO
/* noise_auto: the portable chain's state (above) */
extern SIG_MCS51_XDATA sig_chain_q sig_chain_mcs51_auto;
#endif
/* The gain sequence of the fixed Kalman (q_q30, p0_q16 as sig_kalman1_init_q)
 * from a (re)start to its steady value, by the portable sig_kalman1: run
 * once on the host (its table goes into the firmware's code memory) or at
 * start-up.  table[0 .. *n - 1], the last entry the steady gain (from the
 * step on which sig_kalman1 stops updating it).  SIG_ERR_ARG for NULL
 * pointers, parameters sig_kalman1_init_q rejects, or a gain that has not
 * settled within max steps (q = 1e-3: 251 steps; 1e-5: 1779). */
sig_status sig_chain_mcs51_gains(uint32_t q_q30, uint32_t p0_q16, uint32_t *table,
                                 uint16_t max, uint16_t *n);

/* Initialise the chain from p (as sig_chain_init_q) and the gain table of
 * sig_chain_mcs51_gains for the same q, p0 (kept by address, not copied).
 * SIG_ERR_ARG (nothing changed) for parameters sig_chain_init_q rejects,
 * A0 above SIG_CHAIN_MCS51_A0_MAX, noise_auto in a build without
 * SIG_CHAIN_MCS51_AUTO, a NULL table or n_gains == 0. */
sig_status sig_chain_mcs51_init(const sig_chain_params_q *p,
                                const SIG_MCS51_CODE uint32_t *gains, uint16_t n_gains) SIG_MCS51_REENTRANT;
sig_status sig_chain_mcs51_reset(void);

/* One sample: the status of sig_chain_step_q; output and stability flag in
 * sig_chain_mcs51.out (Q24.7) and .stable. */
sig_status sig_chain_mcs51_step(int32_t x);
sig_status sig_chain_mcs51_tare(void);

#endif /* SIG_CHAIN_MCS51_H */
