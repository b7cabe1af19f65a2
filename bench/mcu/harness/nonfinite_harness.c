/* nonfinite_harness.c - the non-finite rows of the bad-input matrix
 * (docs/bad-input.md, "C core") on the target: every float (_f) entry
 * point with a finiteness guard gets each non-finite value of bad_bits
 * (quiet NaN, negative NaN, a NaN with only the lowest fraction bit set,
 * +inf, -inf), built from its bits so no compiler folds it.
 *
 * For case c and value v: nf_status[c][v] is the returned status and
 * nf_kept[c][v] is 1 when the call left its state struct and its output as
 * they were (what an error promises).  A case whose documented answer is a
 * replaced sample (limit, chain, noise estimator) or a clamped temperature
 * records in nf_kept whether its output is finite instead.  The test
 * (tests/test_mcu_nonfinite.py) builds the same file on the host, the
 * MSP430 and the 8051 and compares all three with the documented table.
 * The order of the cases is the test's NF_CASES. */
#include <stdint.h>
#include "sig_antipulse.h"
#include "sig_chain.h"
#include "sig_effects.h"
#include "sig_kalman1.h"
#include "sig_limit.h"
#include "sig_noise.h"
#include "sig_poly.h"
#include "sig_pwl.h"
#include "sig_scale.h"
#include "sig_stable.h"
#include "sig_tcomp.h"

#include "bench_marks.h"
#ifdef NF_HOST_PRINT
#include <stdio.h>
#endif

#define NF_BAD 5u
#define NF_CASES 35u

const uint32_t bad_bits[NF_BAD] = {
    UINT32_C(0x7FC00000), UINT32_C(0xFFC00000), UINT32_C(0x7F800001),
    UINT32_C(0x7F800000), UINT32_C(0xFF800000)};

sig_status nf_status[NF_CASES][NF_BAD];
uint8_t nf_kept[NF_CASES][NF_BAD];
sig_status init_status;          /* OR of the setup calls: 0 when all succeeded */

/* states and outputs as globals: xdata on the 8051, not its small stack */
sig_lag_f lag;
sig_hyst_f hyst;
sig_creep_f creep;
sig_gain_f gain;
sig_nonlin_f nonlin;
sig_cross_f cross;
sig_kalman1_f kf;
sig_limit_f limit;
sig_stable_f stab;
sig_antipulse_f ap;
sig_noise_f noise;
sig_scale_f scale;
sig_chain_f chain;
sig_chain_params_f chain_p;
sig_tcomp_f tcomp;
sig_pwl_f pwl;
uint8_t snap[sizeof(sig_chain_f)];
sig_real out1, out2, out3[2], others[2];
bool flag;

const sig_real poly2[3] = {SIG_REAL(1.0), SIG_REAL(0.01), SIG_REAL(0.001)};
const sig_real tcomp_coef[6] = {SIG_REAL(1.0), SIG_REAL(2.0), SIG_REAL(0.5),
                                SIG_REAL(-1.0), SIG_REAL(0.25), SIG_REAL(0.125)};
const sig_real pwl_table[3] = {SIG_REAL(0.0), SIG_REAL(1.0), SIG_REAL(4.0)};
const sig_real cross_k[2] = {SIG_REAL(0.01), SIG_REAL(-0.02)};
sig_real bad_table[3];

static sig_real from_bits(uint32_t b)
{
    union { uint32_t b; sig_real r; } u;
    u.b = b;
    return u.r;
}

static void take(const void *p, uint16_t n)
{
    uint16_t i;
    for (i = 0u; i < n; i++) snap[i] = ((const uint8_t *)p)[i];
}

static uint8_t same(const void *p, uint16_t n)
{
    uint16_t i;
    for (i = 0u; i < n; i++)
        if (snap[i] != ((const uint8_t *)p)[i]) return 0u;
    return 1u;
}

#define SENTINEL SIG_REAL(-7.5)

uint8_t nf_case, nf_value;        /* the case being run, the value index */

/* before a call: snapshot state s, outputs to the sentinel */
static void begin(const void *s, uint16_t n)
{
    take(s, n);
    out1 = SENTINEL; out2 = SENTINEL;
    out3[0] = SENTINEL; out3[1] = SENTINEL;
}

/* after it: the status, and whether state and outputs are as they were */
static void end_kept(sig_status st, const void *s, uint16_t n)
{
    nf_status[nf_case][nf_value] = st;
    nf_kept[nf_case][nf_value] = (uint8_t)(same(s, n) && out1 == SENTINEL && out2 == SENTINEL
                                           && out3[0] == SENTINEL && out3[1] == SENTINEL);
    nf_case++;
}

/* after a call whose answer is a usable output: the status, and `ok` */
static void end_output(sig_status st, bool ok)
{
    nf_status[nf_case][nf_value] = st;
    nf_kept[nf_case][nf_value] = ok ? 1u : 0u;
    nf_case++;
}

/* one case on state struct s: snapshot, call, compare */
#define KEEP_CASE(s, call) do {                                      \
        begin(&(s), (uint16_t)sizeof(s));                            \
        end_kept((call), &(s), (uint16_t)sizeof(s));                 \
    } while (0)

/* ---- the weighing stages ---------------------------------------------- */
#define NF_WEIGH_CASES 15u
/* sig_scale's rows run with the calibration half when the halves are built
 * apart: the chain (float and fixed, one module) and its stages fill the
 * 8051's 64 KB nearly alone */
#define NF_SCALE_APPLY_CASE 5u
#define NF_SCALE_INIT_CASE 13u
#ifdef NF_ONLY_WEIGH
#define SCALE_CASE(call) (nf_case++)
#else
#define SCALE_CASE(call) KEEP_CASE(scale, call)
#endif

#ifndef NF_ONLY_CALIB
static sig_status setup_weigh(void)
{
    sig_status st = SIG_OK;
    uint8_t i;
    st = (sig_status)(st | sig_kalman1_init_f(&kf, SIG_REAL(1e-3), SIG_REAL(1.0), SIG_REAL(10.0),
                                              SIG_REAL(0.0), true));
    st = (sig_status)(st | sig_limit_init_f(&limit, SIG_REAL(2.0), 3u));
    st = (sig_status)(st | sig_stable_init_f(&stab, SIG_REAL(0.01), 2u));
    st = (sig_status)(st | sig_stable_step_f(&stab, SIG_REAL(3.0), &flag));
    st = (sig_status)(st | sig_antipulse_init_f(&ap, 5u));
    for (i = 0u; i < 3u; i++) st = (sig_status)(st | sig_antipulse_step_f(&ap, SIG_REAL(2.0), &out1));
    st = (sig_status)(st | sig_chain_params_paper_f(&chain_p));
    return st;
}

static void weigh_cases(sig_real x)
{
    uint8_t i;
    sig_status st;
    /* steps: SIG_ERR_NONFINITE, nothing changed */
    (void)sig_kalman1_reset_f(&kf);
    KEEP_CASE(kf, sig_kalman1_step_f(&kf, x, &out1));              /* fresh */
    (void)sig_kalman1_step_f(&kf, SIG_REAL(5.0), &out2);
    KEEP_CASE(kf, sig_kalman1_step_f(&kf, x, &out1));              /* seeded */
    (void)sig_limit_reset_f(&limit);
    KEEP_CASE(limit, sig_limit_step_f(&limit, x, &out1));          /* fresh */
    KEEP_CASE(stab, sig_stable_step_f(&stab, x, &flag));
    KEEP_CASE(ap, sig_antipulse_step_f(&ap, x, &out1));
    SCALE_CASE(sig_scale_apply_f(&scale, x, &out1));
    (void)sig_chain_init_f(&chain, &chain_p);
    KEEP_CASE(chain, sig_chain_step_f(&chain, x, &out1, &flag));   /* fresh */
    /* after finite samples: replaced, the output usable */
    (void)sig_limit_reset_f(&limit);
    (void)sig_limit_step_f(&limit, SIG_REAL(5.0), &out2);
    st = sig_limit_step_f(&limit, x, &out1);
    end_output(st, out1 == SIG_REAL(5.0));
    (void)sig_chain_init_f(&chain, &chain_p);
    for (i = 0u; i < 20u; i++) (void)sig_chain_step_f(&chain, SIG_REAL(10.0), &out2, &flag);
    out1 = SENTINEL;
    st = sig_chain_step_f(&chain, x, &out1, &flag);
    end_output(st, sig_real_isfinite(out1) && out1 != SENTINEL);
    (void)sig_noise_reset_f(&noise);
    (void)sig_noise_step_f(&noise, SIG_REAL(1.0), true);
    KEEP_CASE(noise, sig_noise_step_f(&noise, x, true));
    /* a non-finite parameter: refused, struct untouched */
    KEEP_CASE(kf, sig_kalman1_init_f(&kf, x, SIG_REAL(1.0), SIG_REAL(10.0), SIG_REAL(0.0), true));
    KEEP_CASE(limit, sig_limit_init_f(&limit, x, 3u));
    KEEP_CASE(stab, sig_stable_init_f(&stab, x, 2u));
    SCALE_CASE(sig_scale_init_f(&scale, SIG_REAL(100.0), x));
    chain_p.q = x;
    KEEP_CASE(chain, sig_chain_init_f(&chain, &chain_p));
    (void)sig_chain_params_paper_f(&chain_p);
}

#endif /* NF_ONLY_CALIB */

#ifdef NF_ONLY_CALIB
static void scale_cases(sig_real x)
{
    nf_case = NF_SCALE_APPLY_CASE;
    SCALE_CASE(sig_scale_apply_f(&scale, x, &out1));
    nf_case = NF_SCALE_INIT_CASE;
    SCALE_CASE(sig_scale_init_f(&scale, SIG_REAL(100.0), x));
}
#endif

/* ---- the calibration models: compensation, tables, refine's effects ---- */
#ifndef NF_ONLY_WEIGH
static sig_status setup_calib(void)
{
    sig_status st = SIG_OK;
    st = (sig_status)(st | sig_lag_init_f(&lag, SIG_REAL(0.5)));
    st = (sig_status)(st | sig_lag_step_f(&lag, SIG_REAL(1.0), &out1));
    st = (sig_status)(st | sig_hyst_init_f(&hyst, SIG_REAL(1.0), SIG_REAL(0.5), 0));
    st = (sig_status)(st | sig_hyst_step_f(&hyst, SIG_REAL(20.0), &out1, &out2));
    st = (sig_status)(st | sig_creep_init_f(&creep, SIG_REAL(0.5), SIG_REAL(0.1)));
    st = (sig_status)(st | sig_creep_step_f(&creep, SIG_REAL(1.0), &out1, &out2));
    st = (sig_status)(st | sig_gain_init_f(&gain, poly2, 2u));
    st = (sig_status)(st | sig_nonlin_init_f(&nonlin, poly2, 2u, SIG_REAL(0.0), SIG_REAL(0.001)));
    st = (sig_status)(st | sig_cross_init_f(&cross, cross_k, 2u));
    st = (sig_status)(st | sig_tcomp_init_f(&tcomp, 2u, 2u, tcomp_coef, SIG_REAL(-10.0),
                                            SIG_REAL(70.0), SIG_REAL(30.0), SIG_REAL(0.025)));
    st = (sig_status)(st | sig_pwl_init_f(&pwl, pwl_table, 3u, SIG_REAL(0.0), SIG_REAL(20.0),
                                          SIG_REAL(0.1)));
    others[0] = SIG_REAL(10.0);
    others[1] = SIG_REAL(20.0);
    return st;
}

static void calib_cases(sig_real x)
{
    sig_real in2[2];
    sig_status st;
    /* steps and applies: SIG_ERR_NONFINITE, nothing changed */
    KEEP_CASE(lag, sig_lag_step_f(&lag, x, &out1));
    KEEP_CASE(hyst, sig_hyst_step_f(&hyst, x, &out1, &out2));
    KEEP_CASE(creep, sig_creep_step_f(&creep, x, &out1, &out2));
    KEEP_CASE(gain, sig_gain_apply_f(&gain, SIG_REAL(0.1), x, &out1));
    KEEP_CASE(gain, sig_gain_apply_f(&gain, x, SIG_REAL(1.0), &out1));
    KEEP_CASE(nonlin, sig_nonlin_apply_f(&nonlin, x, &out1));
    KEEP_CASE(cross, sig_cross_apply_f(&cross, x, others, &out1));
    others[1] = x;
    KEEP_CASE(cross, sig_cross_apply_f(&cross, SIG_REAL(1.0), others, &out1));
    others[1] = SIG_REAL(20.0);
    in2[0] = x;
    in2[1] = SIG_REAL(3.0);
    KEEP_CASE(tcomp, sig_tcomp_apply_f(&tcomp, SIG_REAL(25.0), in2, out3));
    KEEP_CASE(tcomp, sig_poly_horner_f(poly2, 2u, x, &out1));
    /* a temperature: NaN refused, +-inf beyond the range, clamped */
    in2[0] = SIG_REAL(1.0);
    begin(&tcomp, 1u);
    st = sig_tcomp_apply_f(&tcomp, x, in2, out3);
    end_output(st, st < 0 ? out3[0] == SENTINEL && out3[1] == SENTINEL
                          : sig_real_isfinite(out3[0]) && sig_real_isfinite(out3[1]));
    begin(&pwl, 1u);
    st = sig_pwl_eval_f(&pwl, x, &out1);
    end_output(st, st < 0 ? out1 == SENTINEL : sig_real_isfinite(out1));
    /* a non-finite parameter: refused, struct untouched */
    KEEP_CASE(lag, sig_lag_init_f(&lag, x));
    KEEP_CASE(hyst, sig_hyst_init_f(&hyst, x, SIG_REAL(0.5), 0));
    KEEP_CASE(creep, sig_creep_init_f(&creep, SIG_REAL(0.5), x));
    bad_table[0] = SIG_REAL(1.0);
    bad_table[1] = x;
    bad_table[2] = SIG_REAL(0.5);
    KEEP_CASE(gain, sig_gain_init_f(&gain, bad_table, 2u));
    KEEP_CASE(nonlin, sig_nonlin_init_f(&nonlin, poly2, 2u, x, SIG_REAL(0.001)));
    KEEP_CASE(cross, sig_cross_init_f(&cross, bad_table, 2u));
    KEEP_CASE(tcomp, sig_tcomp_init_f(&tcomp, 2u, 2u, tcomp_coef, x, SIG_REAL(70.0),
                                      SIG_REAL(30.0), SIG_REAL(0.025)));
    KEEP_CASE(pwl, sig_pwl_init_f(&pwl, bad_table, 3u, SIG_REAL(0.0), SIG_REAL(20.0), SIG_REAL(0.1)));
}

#endif /* NF_ONLY_WEIGH */

/* NF_ONLY_WEIGH / NF_ONLY_CALIB: one half (the whole does not fit the
 * 8051's 64 KB of code); the other half's rows stay 0 (sig_scale's rows
 * are the calibration half's then). */
int main(void)
{
    uint8_t v;
    sig_status st = SIG_OK;
#ifndef NF_ONLY_CALIB
    st = (sig_status)(st | setup_weigh());
#endif
#ifndef NF_ONLY_WEIGH
    st = (sig_status)(st | sig_scale_init_f(&scale, SIG_REAL(100.0), SIG_REAL(0.01)));
#endif
#ifndef NF_ONLY_WEIGH
    st = (sig_status)(st | setup_calib());
#endif
    init_status = st;
    bench_start();
    for (v = 0u; v < NF_BAD; v++) {
        sig_real x = from_bits(bad_bits[v]);
        nf_case = 0u;
        nf_value = v;
#ifndef NF_ONLY_CALIB
        weigh_cases(x);
#else
        scale_cases(x);
        nf_case = NF_WEIGH_CASES;
#endif
#ifndef NF_ONLY_WEIGH
        calib_cases(x);
#endif
    }
    bench_stop();
    bench_done();
#ifdef NF_HOST_PRINT
    {
        uint8_t c;
        printf("init %d\n", (int)init_status);
        for (c = 0u; c < NF_CASES; c++)
            for (v = 0u; v < NF_BAD; v++)
                printf("%u %u %d %u\n", c, v, (int)nf_status[c][v], nf_kept[c][v]);
    }
#endif
    return 0;
}
