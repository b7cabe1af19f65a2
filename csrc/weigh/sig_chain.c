/* sig_chain.c - the weighing chain, float and fixed; see sig_chain.h. */
#include "sig_chain.h"
#include "sig_chain_stages.h"

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
        && nonneg_finite(p->zero_band) && nonneg_finite(p->zero_rate);
}

/* The load moved: P back to P0; with noise_auto the estimate also starts
 * again from the new samples (reset; the next step seeds it). */
static void restart_kf_f(sig_chain_f *c)
{
    if (c->noise_auto) (void)sig_kalman1_reset_f(&c->kf);
    else (void)sig_kalman1_restart_f(&c->kf);
}

static void restart_kf_q(sig_chain_q *c)
{
    if (c->noise_auto) (void)sig_kalman1_reset_q(&c->kf);
    else (void)sig_kalman1_restart_q(&c->kf);
}

/* noise_auto: the thresholds from the measured sigma (sig_chain.h) */
static void set_thresholds_f(sig_chain_f *c)
{
    if (!c->noise_auto) return;
    sig_chain_thresholds_f(c->noise.sigma, c->noise.count == 0u, &c->limit.a0, &c->motion_band,
                           &c->st.step, &c->zero_band, &c->zero_rate);
}

/* noise_auto: the gate of the noise estimator (sig_chain_stages.h) */
#define NOISE_GATE(c, ret, update) \
    SIG_CHAIN_NOISE_GATE((c)->gate, ret, (c)->ap.n, (c)->motion_run, (c)->noise.count, update)

static void noise_gate_reset(sig_chain_gate *g)
{
    g->rejected_prev = false;
    g->holdoff = 0u;
    g->frozen = 0u;
}

/* noise_auto, after the stages: the estimator, then the thresholds; the floor flag */
static sig_status noise_step_f(sig_chain_f *c, sig_real x, sig_status ret)
{
    bool update;
    NOISE_GATE(c, ret, update);
    (void)sig_noise_step_f(&c->noise, x, update);
    set_thresholds_f(c);
    return sig_noise_at_floor_f(&c->noise) ? (sig_status)(ret | SIG_CHAIN_NOISE_FLOOR) : ret;
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
    c->offset = SIG_REAL(0.0);
    c->out = SIG_REAL(0.0);
    c->motion_run = 0u;
    c->tare_pending = false;
    c->stable = false;
    c->has_out = false;
    noise_gate_reset(&c->gate);
    (void)sig_noise_reset_f(&c->noise);
    set_thresholds_f(c);
    return SIG_OK;
}

sig_status sig_chain_step_f(sig_chain_f *c, sig_real x, sig_real *out, bool *stable)
{
    sig_status st, ret;
    sig_real y, m, xk;
    bool stab;
    if (!c || !out || !stable) return SIG_ERR_ARG;
    st = sig_limit_step_f(&c->limit, x, &y);
    if (st < 0) return st;                      /* non-finite and nothing seeded yet */
    ret = st;
    if ((st & SIG_LIMIT_RESEEDED) != 0) {
        (void)sig_antipulse_reset_f(&c->ap);
        if (c->motion_band > SIG_REAL(0.0)) restart_kf_f(c);
        c->motion_run = 0u;
    }
    (void)sig_antipulse_step_f(&c->ap, y, &m);
    if (c->motion_band > SIG_REAL(0.0) && c->kf.seeded
        && sig_chain_motion(m - c->kf.x > c->motion_band || c->kf.x - m > c->motion_band,
                            &c->motion_run, c->motion_count)) {
        (void)sig_antipulse_reset_f(&c->ap);
        (void)sig_antipulse_step_f(&c->ap, y, &m);
        restart_kf_f(c);
        ret = (sig_status)(ret | SIG_CHAIN_MOTION);
    }
    (void)sig_limit_set_ref_f(&c->limit, m);
    if (c->noise_auto && (c->ap.count < c->ap.n || !c->stable))
        (void)sig_kalman1_reset_f(&c->kf);      /* settling: the window's trimmed mean is the estimate */
    /* m is finite (the anti-pulse mean is clamped to its window), so these
     * cannot fail; if they ever did, stop before using an unset estimate */
    st = sig_kalman1_step_f(&c->kf, m, &xk);
    if (st < 0) return st;
    st = sig_stable_step_f(&c->st, xk, &stab);
    if (st < 0) return st;
    if (stab && sig_chain_offset_f(xk, &c->offset, &c->tare_pending, c->zero_band, c->zero_rate))
        ret = (sig_status)(ret | SIG_CHAIN_TARED);
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
        c->offset = c->kf.x;
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
    c->offset = offset;
    c->tare_pending = false;
    return SIG_OK;
}

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
        && p->zero_band_q7 >= 0 && p->zero_rate_q7 >= 0;
}

static void set_thresholds_q(sig_chain_q *c)
{
    if (!c->noise_auto) return;
    SIG_CHAIN_THRESHOLDS_Q(c->noise.sigma, c->noise.count == 0u, c->limit.a0, c->motion_band,
                           c->st.step, c->zero_band, c->zero_rate);
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
    c->offset = 0;
    c->out = 0;
    c->motion_run = 0u;
    c->tare_pending = false;
    c->stable = false;
    c->has_out = false;
    noise_gate_reset(&c->gate);
    (void)sig_noise_reset_q(&c->noise);
    set_thresholds_q(c);
    return SIG_OK;
}

sig_status sig_chain_step_q(sig_chain_q *c, int32_t x, int32_t *out_q7, bool *stable)
{
    sig_status ret = SIG_OK;
    int32_t y, m, m7, xk;
    bool stab;
    if (!c || !out_q7 || !stable) return SIG_ERR_ARG;
    if (x > SIG_CODE_MAX) { x = SIG_CODE_MAX; ret = SIG_WARN_CLAMPED; }
    else if (x < -SIG_CODE_MAX) { x = -SIG_CODE_MAX; ret = SIG_WARN_CLAMPED; }
    ret = (sig_status)(ret | sig_limit_step_q(&c->limit, x, &y));
    if ((ret & SIG_LIMIT_RESEEDED) != 0) {
        (void)sig_antipulse_reset_q(&c->ap);
        if (c->motion_band > 0) restart_kf_q(c);
        c->motion_run = 0u;
    }
    (void)sig_antipulse_step_q(&c->ap, y, &m);
    m7 = codes_to_q7(m);
    if (c->motion_band > 0 && c->kf.seeded
        && sig_chain_motion(sig_abs32_sat(sig_sat_sub32(m7, c->kf.x)) > c->motion_band,
                            &c->motion_run, c->motion_count)) {
        (void)sig_antipulse_reset_q(&c->ap);
        (void)sig_antipulse_step_q(&c->ap, y, &m);
        m7 = codes_to_q7(m);
        restart_kf_q(c);
        ret = (sig_status)(ret | SIG_CHAIN_MOTION);
    }
    (void)sig_limit_set_ref_q(&c->limit, m);
    if (c->noise_auto && (c->ap.count < c->ap.n || !c->stable))
        (void)sig_kalman1_reset_q(&c->kf);      /* settling: the window's trimmed mean is the estimate */
    (void)sig_kalman1_step_q(&c->kf, m7, &xk);
    (void)sig_stable_step_q(&c->st, xk, &stab);
    if (stab && sig_chain_offset_q(xk, &c->offset, &c->tare_pending, c->zero_band, c->zero_rate))
        ret = (sig_status)(ret | SIG_CHAIN_TARED);
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
        c->offset = c->kf.x;
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
    c->offset = offset_q7;
    c->tare_pending = false;
    return SIG_OK;
}
