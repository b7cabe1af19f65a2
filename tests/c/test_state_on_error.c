/* test_state_on_error.c - an error leaves the caller's state as it was.
 *
 * Every _step (and the chain's batch form) that can return an error, on a
 * state that has already seen samples: snapshot the struct, force each
 * error it can return (a NULL output; a non-finite sample for the float
 * forms; the tcomp model failing under sig_refined_step_q), compare the
 * struct byte for byte.  Structs are filled with a pattern before init so
 * their padding compares too.  The chain's init refuses the Kalman starts
 * that never reach a steady input, untouched as well. */
#include <string.h>

#include "check.h"
#include "sig_antipulse.h"
#include "sig_chain.h"
#include "sig_chain_batch.h"
#include "sig_effects.h"
#include "sig_kalman1.h"
#include "sig_limit.h"
#include "sig_noise.h"
#include "sig_stable.h"
#include "sig_tcomp.h"

static unsigned char snap[sizeof(sig_chain_q) > sizeof(sig_chain_f) ? sizeof(sig_chain_q)
                                                                    : sizeof(sig_chain_f)];

#define SNAP(s) memcpy(snap, &(s), sizeof(s))
#define SAME(s) (memcmp(snap, &(s), sizeof(s)) == 0)

/* the error `call` must return `want` and leave `s` as it was */
#define CHECK_ERROR_KEEPS(s, call, want) do {       \
        SNAP(s);                                    \
        CHECK_EQ_I((call), (want));                 \
        CHECK(SAME(s));                             \
    } while (0)

static sig_real nan_value(void)
{
    volatile sig_real zero = SIG_REAL(0.0);
    return zero / zero;
}

static sig_real inf_value(void)
{
    volatile sig_real zero = SIG_REAL(0.0);
    return SIG_REAL(1.0) / zero;
}

static void weigh_stages(void)
{
    sig_limit_f lf; sig_limit_q lq;
    sig_antipulse_f af; sig_antipulse_q aq;
    sig_kalman1_f kf; sig_kalman1_q kq;
    sig_stable_f sf; sig_stable_q sq;
    sig_noise_f nf;
    sig_real y, bad[2];
    int32_t yq;
    bool b;
    int i, k;
    bad[0] = nan_value();
    bad[1] = inf_value();
    memset(&lf, 0x5a, sizeof lf); memset(&lq, 0x5a, sizeof lq);
    memset(&af, 0x5a, sizeof af); memset(&aq, 0x5a, sizeof aq);
    memset(&kf, 0x5a, sizeof kf); memset(&kq, 0x5a, sizeof kq);
    memset(&sf, 0x5a, sizeof sf); memset(&sq, 0x5a, sizeof sq);
    memset(&nf, 0x5a, sizeof nf);
    CHECK_EQ_I(sig_limit_init_f(&lf, SIG_REAL(2.0), 3u), SIG_OK);
    CHECK_EQ_I(sig_limit_init_q(&lq, 200, 3u), SIG_OK);
    CHECK_EQ_I(sig_antipulse_init_f(&af, 6u), SIG_OK);
    CHECK_EQ_I(sig_antipulse_init_q(&aq, 6u), SIG_OK);
    CHECK_EQ_I(sig_kalman1_init_f(&kf, SIG_REAL(1e-3), SIG_REAL(1.0), SIG_REAL(10.0), SIG_REAL(0.0), true), SIG_OK);
    CHECK_EQ_I(sig_kalman1_init_q(&kq, 1073742u, 655360u, 0, true), SIG_OK);
    CHECK_EQ_I(sig_stable_init_f(&sf, SIG_REAL(0.5), 2u), SIG_OK);
    CHECK_EQ_I(sig_stable_init_q(&sq, 64, 2u), SIG_OK);
    CHECK_EQ_I(sig_noise_reset_f(&nf), SIG_OK);
    /* before the first sample, and after some */
    for (i = 0; i < 2; i++) {
        for (k = 0; k < 2; k++) {
            CHECK_ERROR_KEEPS(lf, sig_limit_step_f(&lf, SIG_REAL(1.0), NULL), SIG_ERR_ARG);
            CHECK_ERROR_KEEPS(af, sig_antipulse_step_f(&af, bad[k], &y), SIG_ERR_NONFINITE);
            CHECK_ERROR_KEEPS(kf, sig_kalman1_step_f(&kf, bad[k], &y), SIG_ERR_NONFINITE);
            CHECK_ERROR_KEEPS(sf, sig_stable_step_f(&sf, bad[k], &b), SIG_ERR_NONFINITE);
            /* the noise estimator skips a non-finite sample: a warning, nothing changed */
            CHECK_ERROR_KEEPS(nf, sig_noise_step_f(&nf, bad[k], true), SIG_WARN_REJECTED);
        }
        if (i == 0) CHECK_ERROR_KEEPS(lf, sig_limit_step_f(&lf, bad[0], &y), SIG_ERR_NONFINITE);
        CHECK_ERROR_KEEPS(af, sig_antipulse_step_f(&af, SIG_REAL(1.0), NULL), SIG_ERR_ARG);
        CHECK_ERROR_KEEPS(kf, sig_kalman1_step_f(&kf, SIG_REAL(1.0), NULL), SIG_ERR_ARG);
        CHECK_ERROR_KEEPS(sf, sig_stable_step_f(&sf, SIG_REAL(1.0), NULL), SIG_ERR_ARG);
        CHECK_ERROR_KEEPS(lq, sig_limit_step_q(&lq, 100, NULL), SIG_ERR_ARG);
        CHECK_ERROR_KEEPS(aq, sig_antipulse_step_q(&aq, 100, NULL), SIG_ERR_ARG);
        CHECK_ERROR_KEEPS(kq, sig_kalman1_step_q(&kq, 100, NULL), SIG_ERR_ARG);
        CHECK_ERROR_KEEPS(sq, sig_stable_step_q(&sq, 100, NULL), SIG_ERR_ARG);
        for (k = 0; k < 9; k++) {       /* some history for the second round */
            sig_real x = (sig_real)(k % 3) * SIG_REAL(0.25);
            CHECK(sig_limit_step_f(&lf, x, &y) >= 0);
            CHECK(sig_antipulse_step_f(&af, x, &y) >= 0);
            CHECK(sig_kalman1_step_f(&kf, x, &y) >= 0);
            CHECK(sig_stable_step_f(&sf, x, &b) >= 0);
            CHECK(sig_noise_step_f(&nf, x, true) >= 0);
            CHECK(sig_limit_step_q(&lq, k * 7, &yq) >= 0);
            CHECK(sig_antipulse_step_q(&aq, k * 7, &yq) >= 0);
            CHECK(sig_kalman1_step_q(&kq, k * 700, &yq) >= 0);
            CHECK(sig_stable_step_q(&sq, k * 700, &b) >= 0);
        }
    }
}

static void chain(void)
{
    sig_chain_params_f pf;
    sig_chain_params_q pq;
    sig_chain_f cf;
    sig_chain_q cq;
    sig_real y, xs[3];
    int32_t yq, xq[3] = {10, 11, 12};
    uint8_t stab[3];
    bool b;
    int i;
    memset(&cf, 0x5a, sizeof cf);
    memset(&cq, 0x5a, sizeof cq);
    CHECK_EQ_I(sig_chain_params_paper_f(&pf), SIG_OK);
    memset(&pq, 0, sizeof pq);
    pq.a0 = 200; pq.window = 12u; pq.q_q30 = 1073742u; pq.p0_q16 = 655360u; pq.x0_q7 = 0;
    pq.seed_first = true; pq.stable_step_q7 = 64; pq.stable_count = 2u; pq.motion_count = 1u;
    CHECK_EQ_I(sig_chain_init_f(&cf, &pf), SIG_OK);
    CHECK_EQ_I(sig_chain_init_q(&cq, &pq), SIG_OK);
    CHECK_ERROR_KEEPS(cf, sig_chain_step_f(&cf, nan_value(), &y, &b), SIG_ERR_NONFINITE);
    CHECK_ERROR_KEEPS(cf, sig_chain_step_f(&cf, inf_value(), &y, &b), SIG_ERR_NONFINITE);
    for (i = 0; i < 30; i++) {
        CHECK(sig_chain_step_f(&cf, SIG_REAL(1.0) + (sig_real)(i % 2) * SIG_REAL(0.01), &y, &b) >= 0);
        CHECK(sig_chain_step_q(&cq, 1000 + i % 2, &yq, &b) >= 0);
    }
    CHECK_ERROR_KEEPS(cf, sig_chain_step_f(&cf, SIG_REAL(1.0), NULL, &b), SIG_ERR_ARG);
    CHECK_ERROR_KEEPS(cf, sig_chain_step_f(&cf, SIG_REAL(1.0), &y, NULL), SIG_ERR_ARG);
    CHECK_ERROR_KEEPS(cq, sig_chain_step_q(&cq, 1000, NULL, &b), SIG_ERR_ARG);
    CHECK_ERROR_KEEPS(cq, sig_chain_step_q(&cq, 1000, &yq, NULL), SIG_ERR_ARG);
    xs[0] = xs[1] = xs[2] = SIG_REAL(1.0);
    CHECK_ERROR_KEEPS(cf, sig_chain_process_f(&cf, xs, 3u, NULL, stab), SIG_ERR_ARG);
    CHECK_ERROR_KEEPS(cq, sig_chain_process_q(&cq, xq, 3u, &yq, NULL), SIG_ERR_ARG);

    /* starts that never reach a steady input: refused, struct untouched */
    pf.noise_auto = true;
    pf.seed_first = false;
    CHECK_ERROR_KEEPS(cf, sig_chain_init_f(&cf, &pf), SIG_ERR_ARG);
    pf.noise_auto = false;
    pf.p0 = pf.r * SIG_REAL(0.5);
    CHECK_ERROR_KEEPS(cf, sig_chain_init_f(&cf, &pf), SIG_ERR_ARG);
    pf.p0 = pf.r;                                   /* P0 = R: the first gain is 1/2 */
    CHECK_EQ_I(sig_chain_init_f(&cf, &pf), SIG_OK);
    pq.noise_auto = true;
    pq.seed_first = false;
    CHECK_ERROR_KEEPS(cq, sig_chain_init_q(&cq, &pq), SIG_ERR_ARG);
    pq.noise_auto = false;
    pq.p0_q16 = 65535u;
    CHECK_ERROR_KEEPS(cq, sig_chain_init_q(&cq, &pq), SIG_ERR_ARG);
    pq.p0_q16 = 65536u;
    CHECK_EQ_I(sig_chain_init_q(&cq, &pq), SIG_OK);
}

static void effects(void)
{
    sig_lag_f lf; sig_lag_q lq;
    sig_hyst_f hf; sig_hyst_q hq;
    sig_creep_f cf; sig_creep_q cq;
    sig_real a, b, bad[2];
    int32_t a32, b32;
    int16_t a16;
    int k;
    bad[0] = nan_value();
    bad[1] = inf_value();
    memset(&lf, 0x5a, sizeof lf); memset(&lq, 0x5a, sizeof lq);
    memset(&hf, 0x5a, sizeof hf); memset(&hq, 0x5a, sizeof hq);
    memset(&cf, 0x5a, sizeof cf); memset(&cq, 0x5a, sizeof cq);
    CHECK_EQ_I(sig_lag_init_f(&lf, SIG_REAL(0.25)), SIG_OK);
    CHECK_EQ_I(sig_lag_init_q(&lq, 16384, 8u), SIG_OK);
    CHECK_EQ_I(sig_hyst_init_f(&hf, SIG_REAL(2.0), SIG_REAL(0.5), 1), SIG_OK);
    CHECK_EQ_I(sig_hyst_init_q(&hq, 200, 32768, 1), SIG_OK);
    CHECK_EQ_I(sig_creep_init_f(&cf, SIG_REAL(0.25), SIG_REAL(0.1)), SIG_OK);
    CHECK_EQ_I(sig_creep_init_q(&cq, 16384, 8u, 6554), SIG_OK);
    for (k = 0; k < 5; k++) {
        CHECK(sig_lag_step_f(&lf, (sig_real)k, &a) >= 0);
        CHECK(sig_lag_step_q(&lq, k * 100, &a32) >= 0);
        CHECK(sig_hyst_step_f(&hf, (sig_real)k, &a, &b) >= 0);
        CHECK(sig_hyst_step_q(&hq, (int16_t)(k * 100), &a16, &a32) >= 0);
        CHECK(sig_creep_step_f(&cf, (sig_real)k, &a, &b) >= 0);
        CHECK(sig_creep_step_q(&cq, k * 100, &a32, &b32) >= 0);
    }
    for (k = 0; k < 2; k++) {
        CHECK_ERROR_KEEPS(lf, sig_lag_step_f(&lf, bad[k], &a), SIG_ERR_NONFINITE);
        CHECK_ERROR_KEEPS(hf, sig_hyst_step_f(&hf, bad[k], &a, &b), SIG_ERR_NONFINITE);
        CHECK_ERROR_KEEPS(cf, sig_creep_step_f(&cf, bad[k], &a, &b), SIG_ERR_NONFINITE);
    }
    CHECK_ERROR_KEEPS(lf, sig_lag_step_f(&lf, SIG_REAL(1.0), NULL), SIG_ERR_ARG);
    CHECK_ERROR_KEEPS(hf, sig_hyst_step_f(&hf, SIG_REAL(1.0), &a, NULL), SIG_ERR_ARG);
    CHECK_ERROR_KEEPS(cf, sig_creep_step_f(&cf, SIG_REAL(1.0), NULL, &b), SIG_ERR_ARG);
    CHECK_ERROR_KEEPS(lq, sig_lag_step_q(&lq, 1, NULL), SIG_ERR_ARG);
    CHECK_ERROR_KEEPS(hq, sig_hyst_step_q(&hq, 1, &a16, NULL), SIG_ERR_ARG);
    CHECK_ERROR_KEEPS(cq, sig_creep_step_q(&cq, 1, NULL, &b32), SIG_ERR_ARG);
}

/* sig_refined_step_q: the tcomp model fails (an axis the model no longer
 * has) after the lag and hysteresis would have stepped */
static void refined(void)
{
    static const int32_t coef[6] = {100, 200, 50, -100, 20, 10};
    static const uint8_t q[2] = {4u, 4u};
    sig_tcomp_q m;
    sig_lag_q lag;
    sig_hyst_q hyst;
    sig_refined_q r;
    int32_t out;
    int k;
    memset(&r, 0x5a, sizeof r);
    memset(&lag, 0x5a, sizeof lag);     /* copied into r with its padding */
    memset(&hyst, 0x5a, sizeof hyst);
    CHECK_EQ_I(sig_tcomp_init_q(&m, 2u, 2u, coef, q, -1000, 7000, 3000, 2500, 8191, 10u), SIG_OK);
    CHECK_EQ_I(sig_lag_init_q(&lag, 16384, 16u), SIG_OK);
    CHECK_EQ_I(sig_hyst_init_q(&hyst, 50, 32768, 0), SIG_OK);
    CHECK_EQ_I(sig_refined_init_q(&r, &m, 1u, &lag, &hyst, NULL), SIG_OK);
    for (k = 0; k < 5; k++) CHECK(sig_refined_step_q(&r, (int16_t)(2000 + 300 * k), 50, &out) >= 0);
    m.n_axes = 1u;                                   /* the model lost axis 1 */
    CHECK_ERROR_KEEPS(r, sig_refined_step_q(&r, 4000, 60, &out), SIG_ERR_ARG);
    m.n_axes = 2u;
    CHECK_ERROR_KEEPS(r, sig_refined_step_q(&r, 4000, 60, NULL), SIG_ERR_ARG);
    CHECK(sig_refined_step_q(&r, 4000, 60, &out) >= 0);
}

int main(void)
{
    weigh_stages();
    chain();
    effects();
    refined();
    return check_report("test_state_on_error");
}
