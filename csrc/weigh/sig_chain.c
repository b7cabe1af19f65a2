/* sig_chain.c - the weighing chain, float and fixed; see sig_chain.h. */
#include "sig_chain.h"
#include "sig_chain_stages.h"

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
static bool nonneg_finite(sig_real x)
{
    return sig_real_isfinite(x) && x >= SIG_REAL(0.0);
}

sig_status sig_chain_params_paper_f(sig_chain_params_f *p)
{
    if (!p) return SIG_ERR_ARG;
    p->a0 = SIG_REAL(2.0);
    p->window = SIG_ANTIPULSE_DEFAULT;
    p->q = SIG_REAL(1e-7);
    p->r = SIG_REAL(0.05);
    p->p0 = SIG_REAL(10.0);
    p->x0 = SIG_REAL(1.0);
    p->seed_first = false;
    p->stable_step = SIG_REAL(0.01);
    p->stable_count = 1u;
    p->lockout_n = 0u;
    p->motion_band = SIG_REAL(0.0);
    p->motion_count = 1u;
    p->zero_band = SIG_REAL(0.0);
    p->zero_rate = SIG_REAL(0.0);
    p->noise_auto = false;
    return SIG_OK;
}

static bool params_ok_f(const sig_chain_params_f *p)
{
    return sig_real_isfinite(p->a0) && p->a0 > SIG_REAL(0.0)
        && p->window >= 3u && p->window <= SIG_ANTIPULSE_MAX
        && nonneg_finite(p->q) && sig_real_isfinite(p->r) && p->r > SIG_REAL(0.0)
        && nonneg_finite(p->p0) && sig_real_isfinite(p->x0)
        && nonneg_finite(p->stable_step) && p->stable_count >= 1u
        && nonneg_finite(p->motion_band) && p->motion_count >= 1u
        && nonneg_finite(p->zero_band) && nonneg_finite(p->zero_rate)
        && (p->seed_first || (!p->noise_auto && p->p0 >= p->r));     /* see sig_chain.h */
}

/* The load moved: P back to P0; with noise_auto the estimate also starts
 * again from the new samples (reset; the next step seeds it). */
static void restart_kf_f(sig_chain_f *c)
{
    if (c->noise_auto) (void)sig_kalman1_reset_f(&c->kf);
    else (void)sig_kalman1_restart_f(&c->kf);
}
#endif /* SIG_NO_FLOAT */

static void restart_kf_q(sig_chain_q *c)
{
    if (c->noise_auto) (void)sig_kalman1_reset_q(&c->kf);
    else (void)sig_kalman1_restart_q(&c->kf);
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
/* noise_auto: the thresholds from the measured sigma (sig_chain.h) */
static void set_thresholds_f(sig_chain_f *c)
{
    if (!c->noise_auto) return;
    sig_chain_thresholds_f(c->noise.sigma, c->noise.count == 0u, &c->limit.a0, &c->motion_band,
                           &c->st.step, &c->zero_band, &c->zero_rate, &c->near_band);
}
#endif /* SIG_NO_FLOAT */

/* noise_auto: the gate of the noise estimator (sig_chain_stages.h) */
#define NOISE_GATE(c, ret, update) \
    SIG_CHAIN_NOISE_GATE((c)->gate, ret, (c)->ap.n, (c)->motion_run, (c)->noise.count, update)

static void noise_gate_reset(sig_chain_gate *g)
{
    g->rejected_prev = false;
    g->holdoff = 0u;
    g->frozen = 0u;
}

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
/* noise_auto, after the stages: the estimator, then the thresholds; the floor flag */
static sig_status noise_step_f(sig_chain_f *c, sig_real x, sig_status ret)
{
    bool update;
    NOISE_GATE(c, ret, update);
    (void)sig_noise_step_f(&c->noise, x, update);
    set_thresholds_f(c);
    return sig_noise_at_floor_f(&c->noise) ? (sig_status)(ret | SIG_CHAIN_NOISE_FLOOR) : ret;
}

#endif /* SIG_NO_FLOAT */

/* noise_auto: the ramp follower (sig_chain.h), written once as macros over
 * either chain (the fields have the same names in both; like NOISE_GATE).
 * The caller's numeric form comes in as T (the type), ZERO, HALF(v) (v / 2:
 * a multiply or a floor shift), FINITE(v), and its limit's set_ref and
 * accept; every other operation reads the same in both forms (fixed: codes,
 * |.| < 2^27, no overflow). */

/* Before the limit: the limit judges the sample against last + slope (two
 * slopes after a held sample), or against the last followed value when the
 * sample looks as if the load stopped (within A0/2 of it and nearer it than
 * the prediction); `ended` when the ramp ends here (sig_chain_ramp_stop). */
#define RAMP_BEFORE(c, x, p, T, ZERO, HALF, SET_REF, ended) do {                       \
        T half_ = HALF((c)->limit.a0), dl_ = (x) - (c)->last, dp_ = (x) - (p);          \
        bool looks_ = dl_ <= half_ && -dl_ <= half_                                     \
                      && (dl_ < ZERO ? -dl_ : dl_) <= (dp_ < ZERO ? -dp_ : dp_);        \
        (c)->pred = (p);                                                                 \
        (void)SET_REF(&(c)->limit, looks_ ? (c)->last : (p));                            \
        (ended) = sig_chain_ramp_stop(looks_, &(c)->ramp, &(c)->missed, &(c)->paused);  \
    } while (0)

/* After the limit: start, follow or end a ramp; *y is the limit's output,
 * replaced when the ramp takes the sample or holds a value.  A start on a
 * second rejection needs the sample to have moved on by more than A0/2 and
 * its two steps out (Dc to the first rejected sample, that to this one)
 * within a factor 4; on a first rejection, the sample before (accepted)
 * more than A0/2 out on the same side and the two steps within a factor 2
 * (a ramp of 3-6 sigma per sample: its first sample is within A0; a swing
 * turning back shrinks its step).  A held sample that lies beyond the prediction on the
 * ramp's side (a glitch in a pour) shows the prediction, else the last
 * followed value (a bump's top, a swing turning). */
#define RAMP_AFTER(c, x, y, ret, finite, T, ZERO, HALF, ACCEPT, SET_REF) do {           \
        T d_, moved_, before_, a0_ = (c)->limit.a0;                                      \
        switch (sig_chain_ramp_case(&(c)->ramp, &(c)->missed, &(c)->paused, (ret),       \
                                    (c)->limit.t.run)) {                                 \
        case SIG_CHAIN_RAMP_FOLLOW:           /* the slope: half way to the new step */  \
            if (!(c)->missed && !(c)->paused)                                            \
                (c)->slope += HALF(((x) - (c)->last) - (c)->slope);                      \
            (c)->last = (x);                                                             \
            (c)->missed = false;                                                         \
            (c)->followed = true;                                                        \
            (ret) = (sig_status)((ret) | SIG_CHAIN_RAMP);                                \
            break;                                                                       \
        case SIG_CHAIN_RAMP_BROKEN:                                                      \
            d_ = (x) - (c)->origin;                                                      \
            moved_ = (x) - (c)->pred;                                                    \
            before_ = (c)->last - (c)->origin;                                           \
            if ((finite) && d_ <= a0_ && -d_ <= a0_) {        /* came back: taken */     \
                (c)->ramp = (c)->missed = (c)->paused = false;                           \
                (void)ACCEPT(&(c)->limit, (x));                                          \
                *(y) = (x);                                                              \
                (ret) = SIG_CHAIN_TAKEN(ret);                                            \
            } else if (!(c)->followed                         /* a glitch pair */        \
                       && (moved_ < ZERO ? -moved_ : moved_) > (d_ < ZERO ? -d_ : d_)   \
                       && (d_ < ZERO ? -d_ : d_) <= (before_ < ZERO ? -before_ : before_)) { \
                (c)->ramp = (c)->missed = (c)->paused = false;                           \
                (void)SET_REF(&(c)->limit, (c)->origin);                                 \
                *(y) = (c)->origin;                                                      \
                (ret) = (sig_status)((ret) | SIG_LIMIT_RESEEDED);                        \
            } else {                          /* beyond the prediction: */               \
                *(y) = !(c)->missed && ((c)->slope > ZERO ? (x) > (c)->pred              \
                                                          : (x) < (c)->pred)             \
                       ? (c)->pred : (c)->last;       /* the prediction, else last */    \
                (ret) = sig_chain_ramp_hold(&(c)->ramp, &(c)->missed, &(c)->paused, (ret)); \
            }                                                                            \
            break;                                                                       \
        case SIG_CHAIN_RAMP_TRY:                                                         \
            d_ = (x) - (c)->prev_x;                                                      \
            moved_ = (c)->limit.t.side > 0 ? d_ : -d_;                                   \
            before_ = (c)->limit.t.side > 0 ? (c)->prev_x - (c)->limit.dc                \
                                            : (c)->limit.dc - (c)->prev_x;               \
            if ((finite) && ((c)->limit.t.run >= 2u                                      \
                             ? moved_ > HALF(a0_) && 4 * moved_ >= before_               \
                               && moved_ <= 4 * before_                                  \
                             : before_ > HALF(a0_) && 2 * moved_ >= before_              \
                               && moved_ <= 2 * before_)) {                              \
                (c)->origin = (c)->limit.dc;                                             \
                (void)ACCEPT(&(c)->limit, (x));                                          \
                (c)->ramp = true;                                                        \
                (c)->missed = (c)->paused = (c)->followed = false;                       \
                (c)->slope = d_;                                                         \
                (c)->last = (x);                                                         \
                *(y) = (x);                                                              \
                (ret) = (sig_status)(SIG_CHAIN_TAKEN(ret) | SIG_CHAIN_RAMP);             \
            }                                                                            \
            break;                                                                       \
        default:                                                                         \
            break;                                                                       \
        }                                                                                \
        if (finite) (c)->prev_x = (x);                                                   \
    } while (0)

#define HALF_F(v) ((v) * SIG_REAL(0.5))
#define HALF_Q(v) sig_asr32((v), 1u)

/* |a - b| > band for the chain's distance tests.  The float form is one
 * function (an inline float comparison is a library call on the 8051, and
 * the code space of its builds is nearly full); the fixed form stays inline
 * (its helpers are calls already, and a frame more would deepen the 8051
 * firmware's stack). */
#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
static bool apart_f(sig_real a, sig_real b, sig_real band)
{
    return a - b > band || b - a > band;    /* no |a - b|: the difference may overflow */
}
#endif /* SIG_NO_FLOAT */

#define APART_Q(a, b, band) (sig_abs32_sat(sig_sat_sub32((a), (b))) > (band))   /* Q24.7, saturating */

#ifndef SIG_NO_FLOAT    /* the float form; a fixed-only build leaves it out (sig_types.h) */
static bool ramp_before_f(sig_chain_f *c, sig_real x)
{
    sig_real p;
    bool ended;
    if (!c->ramp) return false;
    p = c->last + (c->missed ? c->slope + c->slope : c->slope);
    if (!sig_real_isfinite(p)) p = c->last;
    RAMP_BEFORE(c, x, p, sig_real, SIG_REAL(0.0), HALF_F, sig_limit_set_ref_f, ended);
    return ended;
}

static sig_status ramp_after_f(sig_chain_f *c, sig_real x, sig_real *y, sig_status ret)
{
    bool finite = sig_real_isfinite(x);
    RAMP_AFTER(c, x, y, ret, finite, sig_real, SIG_REAL(0.0), HALF_F, sig_limit_accept_f, sig_limit_set_ref_f);
    return ret;
}

sig_status sig_chain_init_f(sig_chain_f *c, const sig_chain_params_f *p)
{
    if (!c || !p || !params_ok_f(p)) return SIG_ERR_ARG;
    (void)sig_limit_init_f(&c->limit, p->a0, p->lockout_n);
    (void)sig_antipulse_init_f(&c->ap, p->window);
    (void)sig_kalman1_init_f(&c->kf, p->q, p->r, p->p0, p->x0, p->seed_first);
    (void)sig_stable_init_f(&c->st, p->stable_step, p->stable_count);
    c->motion_band = p->motion_band;
    c->motion_count = p->motion_count;
    c->zero_band = p->zero_band;
    c->zero_rate = p->zero_rate;
    c->noise_auto = p->noise_auto;
    return sig_chain_reset_f(c);
}

sig_status sig_chain_reset_f(sig_chain_f *c)
{
    if (!c) return SIG_ERR_ARG;
    (void)sig_limit_reset_f(&c->limit);
    (void)sig_antipulse_reset_f(&c->ap);
    (void)sig_kalman1_reset_f(&c->kf);
    (void)sig_stable_reset_f(&c->st);
    c->offset = c->zero = SIG_REAL(0.0);
    c->out = SIG_REAL(0.0);
    c->motion_run = 0u;
    c->tare_pending = false;
    c->stable = false;
    c->has_out = false;
    noise_gate_reset(&c->gate);
    c->slope = c->last = c->origin = c->prev_x = c->pred = SIG_REAL(0.0);
    c->ramp = c->missed = c->paused = c->followed = false;
    c->settled = false;
    c->anchor = SIG_REAL(0.0);
    c->trend_mean = SIG_REAL(0.0);
    c->drift_age = 0u;
    c->drifting = true;
    c->has_level = false;     /* level is read only once it is set; hold_block is set as the window refills */
    (void)sig_noise_reset_f(&c->noise);
    set_thresholds_f(c);
    return SIG_OK;
}

sig_status sig_chain_step_f(sig_chain_f *c, sig_real x, sig_real *out, bool *stable)
{
    sig_status st, ret;
    sig_real y, m, xk;
    bool stab, ramp_ended, trending, refilling;
    if (!c || !out || !stable) return SIG_ERR_ARG;
    /* a ramp needs a seeded limit, so nothing changes before the error below */
    ramp_ended = c->noise_auto && ramp_before_f(c, x);
    st = sig_limit_step_f(&c->limit, x, &y);
    if (st < 0) return st;                      /* non-finite and nothing seeded yet */
    ret = st;
    if (c->noise_auto) ret = ramp_after_f(c, x, &y, ret);
    if ((ret & SIG_LIMIT_RESEEDED) != 0) {
        (void)sig_antipulse_reset_f(&c->ap);
        if (c->motion_band > SIG_REAL(0.0)) restart_kf_f(c);
        c->motion_run = 0u;
    }
    if (c->ramp || ramp_ended) {                /* the window holds the ramp's last sample only */
        (void)sig_antipulse_reset_f(&c->ap);
        c->motion_run = 0u;
    }
    if (ramp_ended) {
        restart_kf_f(c);
        ret = (sig_status)(ret | SIG_CHAIN_MOTION);
    }
    (void)sig_antipulse_step_f(&c->ap, y, &m);
    if (c->motion_band > SIG_REAL(0.0) && c->kf.seeded && !c->ramp
        && sig_chain_motion(apart_f(m, c->kf.x, c->motion_band),
                            &c->motion_run, c->motion_count)) {
        (void)sig_antipulse_reset_f(&c->ap);
        (void)sig_antipulse_step_f(&c->ap, y, &m);
        restart_kf_f(c);
        ret = (sig_status)(ret | SIG_CHAIN_MOTION);
    }
    (void)sig_limit_set_ref_f(&c->limit, m);
    refilling = c->ap.count < c->ap.n;          /* the window is full from here on */
    if (c->noise_auto && (refilling || !c->settled))
        (void)sig_kalman1_reset_f(&c->kf);      /* settling: the window's trimmed mean is the estimate */
    /* m is finite (the anti-pulse mean is clamped to its window), so these
     * cannot fail; if they ever did, stop before using an unset estimate */
    st = sig_kalman1_step_f(&c->kf, m, &xk);
    if (st < 0) return st;
    st = sig_stable_step_f(&c->st, xk, &stab);
    if (st < 0) return st;
    c->settled = stab;
    if (c->noise_auto
        && sig_chain_drift_due(refilling,
                               refilling && c->has_level && apart_f(xk, c->level, c->noise.sigma * SIG_REAL(1024.0)),
                               &c->drift_age, c->ap.n, &c->drifting, &c->hold_block)) {
        if (!refilling)
            c->drifting = sig_chain_drift_verdict(apart_f(xk, c->anchor, c->noise.sigma), &c->hold_block);
        c->anchor = xk;
    }
    trending = c->noise_auto
               && sig_chain_trend_f(refilling, y - xk, c->noise.sigma, &c->trend_mean);
    if (c->noise_auto && stab)
        stab = sig_chain_backed(ret, c->ap.count, c->ap.n, c->motion_run, c->drifting, trending,
                                !apart_f(y, xk, c->near_band) && !apart_f(m, xk, c->noise.sigma));
    if (stab) {
        c->level = xk;
        c->has_level = true;
        if (sig_chain_offset_f(true, xk, &c->offset, c->noise_auto ? &c->zero : &c->offset, &c->tare_pending,
                               c->zero_band, c->zero_rate))
            ret = (sig_status)(ret | SIG_CHAIN_TARED);
    }
    c->out = xk - c->offset;
    c->stable = stab;
    c->has_out = true;
    if (c->noise_auto) ret = noise_step_f(c, x, ret);
    *out = c->out;
    *stable = stab;
    return ret;
}

sig_status sig_chain_tare_f(sig_chain_f *c)
{
    if (!c) return SIG_ERR_ARG;
    if (c->has_out && c->stable) {             /* stable now: the tare of a stable sample */
        c->offset = c->zero = c->kf.x;
        c->tare_pending = false;
        c->out = SIG_REAL(0.0);
        return SIG_CHAIN_TARED;
    }
    c->tare_pending = true;
    return SIG_OK;
}

sig_status sig_chain_set_offset_f(sig_chain_f *c, sig_real offset)
{
    if (!c || !sig_real_isfinite(offset)) return SIG_ERR_ARG;
    c->offset = c->zero = offset;
    c->tare_pending = false;
    return SIG_OK;
}
#endif /* SIG_NO_FLOAT */

/* ---- fixed point ---------------------------------------------------------- */

/* codes (|m| <= SIG_CODE_MAX) to Q24.7: m * 128 exactly, by a shift of the
 * magnitude (no multiply, no shift of a negative value). */
static int32_t codes_to_q7(int32_t m)
{
    return m >= 0 ? (int32_t)((uint32_t)m << 7) : -(int32_t)((uint32_t)-m << 7);
}

static bool params_ok_q(const sig_chain_params_q *p)
{
    return p->a0 > 0 && p->window >= 3u && p->window <= SIG_ANTIPULSE_MAX
        && p->q_q30 <= SIG_KALMAN1_Q_MAX && p->p0_q16 <= SIG_KALMAN1_P0_MAX
        && p->stable_step_q7 >= 0 && p->stable_count >= 1u
        && p->motion_band_q7 >= 0 && p->motion_count >= 1u
        && p->zero_band_q7 >= 0 && p->zero_rate_q7 >= 0
        && (p->seed_first || (!p->noise_auto && p->p0_q16 >= (uint32_t)SIG_Q16_ONE));
}

static void set_thresholds_q(sig_chain_q *c)
{
    if (!c->noise_auto) return;
    SIG_CHAIN_THRESHOLDS_Q(c->noise.sigma, c->noise.count == 0u, c->limit.a0, c->motion_band,
                           c->st.step, c->zero_band, c->zero_rate, c->near_band);
}

static sig_status noise_step_q(sig_chain_q *c, int32_t x, sig_status ret)
{
    bool update;
    NOISE_GATE(c, ret, update);
    (void)sig_noise_step_q(&c->noise, x, update);
    set_thresholds_q(c);
    /* sig_noise_at_floor_q inline: a call costs the 8051 more than the compare */
    return c->noise.sigma <= SIG_NOISE_FLOOR_Q7 ? (sig_status)(ret | SIG_CHAIN_NOISE_FLOOR) : ret;
}

static bool ramp_before_q(sig_chain_q *c, int32_t x)
{
    int32_t p;
    bool ended;
    if (!c->ramp) return false;
    p = c->last + (c->missed ? c->slope + c->slope : c->slope);   /* |last| < 2^24, |slope| < 2^25 */
    p = p > SIG_CODE_MAX ? SIG_CODE_MAX : (p < -SIG_CODE_MAX ? -SIG_CODE_MAX : p);
    RAMP_BEFORE(c, x, p, int32_t, 0, HALF_Q, sig_limit_set_ref_q, ended);
    return ended;
}

static sig_status ramp_after_q(sig_chain_q *c, int32_t x, int32_t *y, sig_status ret)
{
    RAMP_AFTER(c, x, y, ret, true, int32_t, 0, HALF_Q, sig_limit_accept_q, sig_limit_set_ref_q);
    return ret;
}

sig_status sig_chain_init_q(sig_chain_q *c, const sig_chain_params_q *p)
{
    if (!c || !p || !params_ok_q(p)) return SIG_ERR_ARG;
    (void)sig_limit_init_q(&c->limit, p->a0, p->lockout_n);
    (void)sig_antipulse_init_q(&c->ap, p->window);
    (void)sig_kalman1_init_q(&c->kf, p->q_q30, p->p0_q16, p->x0_q7, p->seed_first);
    (void)sig_stable_init_q(&c->st, p->stable_step_q7, p->stable_count);
    c->motion_band = p->motion_band_q7;
    c->motion_count = p->motion_count;
    c->zero_band = p->zero_band_q7;
    c->zero_rate = p->zero_rate_q7;
    c->noise_auto = p->noise_auto;
    return sig_chain_reset_q(c);
}

sig_status sig_chain_reset_q(sig_chain_q *c)
{
    if (!c) return SIG_ERR_ARG;
    (void)sig_limit_reset_q(&c->limit);
    (void)sig_antipulse_reset_q(&c->ap);
    (void)sig_kalman1_reset_q(&c->kf);
    (void)sig_stable_reset_q(&c->st);
    c->offset = c->zero = 0;
    c->out = 0;
    c->motion_run = 0u;
    c->tare_pending = false;
    c->stable = false;
    c->has_out = false;
    noise_gate_reset(&c->gate);
    c->slope = c->last = c->origin = c->prev_x = c->pred = 0;
    c->ramp = c->missed = c->paused = c->followed = false;
    c->settled = false;
    c->anchor = 0;
    c->trend_mean = 0;
    c->trending = false;
    c->drift_age = 0u;
    c->drifting = true;
    c->has_level = false;     /* level is read only once it is set; hold_block is set as the window refills */
    (void)sig_noise_reset_q(&c->noise);
    set_thresholds_q(c);
    return SIG_OK;
}

sig_status sig_chain_step_q(sig_chain_q *c, int32_t x, int32_t *out_q7, bool *stable)
{
    sig_status ret = SIG_OK;
    int32_t y, m, m7, xk;
    bool stab, ramp_ended;
    if (!c || !out_q7 || !stable) return SIG_ERR_ARG;
    if (x > SIG_CODE_MAX) { x = SIG_CODE_MAX; ret = SIG_WARN_CLAMPED; }
    else if (x < -SIG_CODE_MAX) { x = -SIG_CODE_MAX; ret = SIG_WARN_CLAMPED; }
    ramp_ended = c->noise_auto && ramp_before_q(c, x);
    ret = (sig_status)(ret | sig_limit_step_q(&c->limit, x, &y));
    if (c->noise_auto) ret = ramp_after_q(c, x, &y, ret);
    if ((ret & SIG_LIMIT_RESEEDED) != 0) {
        (void)sig_antipulse_reset_q(&c->ap);
        if (c->motion_band > 0) restart_kf_q(c);
        c->motion_run = 0u;
    }
    if (c->ramp || ramp_ended) {                /* the window holds the ramp's last sample only */
        (void)sig_antipulse_reset_q(&c->ap);
        c->motion_run = 0u;
    }
    if (ramp_ended) {
        restart_kf_q(c);
        ret = (sig_status)(ret | SIG_CHAIN_MOTION);
    }
    (void)sig_antipulse_step_q(&c->ap, y, &m);
    m7 = codes_to_q7(m);
    if (c->motion_band > 0 && c->kf.seeded && !c->ramp
        && sig_chain_motion(APART_Q(m7, c->kf.x, c->motion_band),
                            &c->motion_run, c->motion_count)) {
        (void)sig_antipulse_reset_q(&c->ap);
        (void)sig_antipulse_step_q(&c->ap, y, &m);
        m7 = codes_to_q7(m);
        restart_kf_q(c);
        ret = (sig_status)(ret | SIG_CHAIN_MOTION);
    }
    (void)sig_limit_set_ref_q(&c->limit, m);
    if (c->noise_auto && (c->ap.count < c->ap.n || !c->settled))
        (void)sig_kalman1_reset_q(&c->kf);      /* settling: the window's trimmed mean is the estimate */
    (void)sig_kalman1_step_q(&c->kf, m7, &xk);
    (void)sig_stable_step_q(&c->st, xk, &stab);
    c->settled = stab;
    if (c->noise_auto
        && sig_chain_drift_due(c->ap.count < c->ap.n,
                               c->ap.count < c->ap.n && c->has_level
                               && (sig_abs32_sat(sig_sat_sub32(xk, c->level)) >> 10) > c->noise.sigma,
                               &c->drift_age, c->ap.n, &c->drifting, &c->hold_block)) {
        if (c->ap.count == c->ap.n)
            c->drifting = sig_chain_drift_verdict(APART_Q(xk, c->anchor, c->noise.sigma), &c->hold_block);
        c->anchor = xk;
    }
    /* the verdict in the state, not in a local: the 8051's stack holds
     * this frame on the chain's deepest call path */
    c->trending = c->noise_auto
                  && sig_chain_trend_q(c->ap.count < c->ap.n, sig_sat_sub32(codes_to_q7(y), xk), c->noise.sigma,
                                       &c->trend_mean);
    if (c->noise_auto && stab)
        stab = sig_chain_backed(ret, c->ap.count, c->ap.n, c->motion_run, c->drifting, c->trending,
                                !APART_Q(codes_to_q7(y), xk, c->near_band) && !APART_Q(m7, xk, c->noise.sigma));
    if (stab) {
        c->level = xk;
        c->has_level = true;
        if (sig_chain_offset_q(xk, &c->offset, c->noise_auto ? &c->zero : &c->offset, &c->tare_pending,
                               c->zero_band, c->zero_rate))
            ret = (sig_status)(ret | SIG_CHAIN_TARED);
    }
    c->out = sig_sat_sub32(xk, c->offset);
    c->stable = stab;
    c->has_out = true;
    if (c->noise_auto) ret = noise_step_q(c, x, ret);
    *out_q7 = c->out;
    *stable = stab;
    return ret;
}

sig_status sig_chain_tare_q(sig_chain_q *c)
{
    if (!c) return SIG_ERR_ARG;
    if (c->has_out && c->stable) {             /* stable now: the tare of a stable sample */
        c->offset = c->zero = c->kf.x;
        c->tare_pending = false;
        c->out = 0;
        return SIG_CHAIN_TARED;
    }
    c->tare_pending = true;
    return SIG_OK;
}

sig_status sig_chain_set_offset_q(sig_chain_q *c, int32_t offset_q7)
{
    if (!c) return SIG_ERR_ARG;
    c->offset = c->zero = offset_q7;
    c->tare_pending = false;
    return SIG_OK;
}
