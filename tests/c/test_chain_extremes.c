/* test_chain_extremes.c - the float weighing chain keeps a valid state for
 * any finite samples and any accepted parameters (the bad-input invariants: no
 * NaN in the Kalman state, P >= 0, output never NaN).  Found by
 * fuzz/fuzz_chain.c:
 *   1. huge finite samples of both signs (lock-out re-seed, or a huge A0):
 *      the Kalman innovation z - x overflowed to -inf, x became -inf, and
 *      the next innovation inf - inf made x NaN for ever;
 *   2. a huge A0 with a short window: the anti-pulse sum overflowed to inf,
 *      the Kalman stage refused it (SIG_ERR_NONFINITE) and the chain, which
 *      ignores that status, went on with an uninitialised estimate;
 *   3. (MemorySanitizer, fuzz_chain-msan) the largest finite sample, then
 *      rejected ones: the window holds two FLT_MAX, its mean overflowed and
 *      the chain again used the Kalman estimate it had not set
 *      (sig_stable.c:30 reads it);
 *   4. huge accepted Kalman parameters (Q, P0 near the float maximum): the
 *      prediction P + Q overflowed and the gain became inf / inf = NaN.
 * Each scenario runs in the form this file is compiled for (float, or
 * double with -DSIG_REAL_DOUBLE), with values scaled to that form's range. */
#include <float.h>

#include "check.h"
#include "sig_chain.h"

#ifdef SIG_REAL_DOUBLE
#define BIG ((sig_real)(DBL_MAX / 1.5))
#define RAIL ((sig_real)DBL_MAX)
#else
#define BIG ((sig_real)(FLT_MAX / 1.5f))
#define RAIL ((sig_real)FLT_MAX)
#endif

static int is_nan(sig_real x) { return x != x; }

static void run(const char *what, const sig_chain_params_f *p, const sig_real *xs, int n)
{
    sig_chain_f c;
    sig_real out;
    bool stable;
    int i, bad = 0;
    CHECK_EQ_I(sig_chain_init_f(&c, p), SIG_OK);
    for (i = 0; i < n; i++) {
        sig_status st = sig_chain_step_f(&c, xs[i], &out, &stable);
        /* the output is the Kalman estimate minus the offset (0 here), and
         * that estimate is a convex combination of x0 (1) and window means,
         * all within [-RAIL, RAIL] */
        if (st < 0 || is_nan(out) || out != c.kf.x - c.offset || !(out >= -RAIL && out <= RAIL)
            || is_nan(c.kf.x)
            || is_nan(c.kf.p) || is_nan(c.kf.k) || c.kf.p < 0) {
            if (!bad) fprintf(stderr, "%s: sample %d (%g): status %d out %g x %g P %g K %g\n",
                              what, i, (double)xs[i], st, (double)out, (double)c.kf.x,
                              (double)c.kf.p, (double)c.kf.k);
            bad = 1;
        }
    }
    CHECK(!bad);
}

int main(void)
{
    sig_chain_params_f p;
    sig_real swing[8];
    int i;
    for (i = 0; i < 8; i++) swing[i] = (i % 3 == 0) ? BIG : -BIG;

    sig_chain_params_paper_f(&p);
    p.lockout_n = 1;                 /* every far sample re-seeds: the level jumps by 2 BIG */
    run("lock-out re-seed across the range", &p, swing, 8);

    sig_chain_params_paper_f(&p);
    p.a0 = BIG;                      /* accept everything */
    p.window = 3;
    run("huge A0, window 3", &p, swing, 8);

    {
        sig_real rail[6];
        rail[0] = RAIL; rail[1] = (sig_real)-1.4e14; rail[2] = SIG_REAL(-0.0057);
        rail[3] = SIG_REAL(-0.0057); rail[4] = RAIL; rail[5] = -RAIL;
        sig_chain_params_paper_f(&p);
        p.a0 = SIG_REAL(20.0);
        run("the largest finite sample, then impulses", &p, rail, 6);
    }

    sig_chain_params_paper_f(&p);
    p.q = BIG;
    p.p0 = BIG;
    run("huge Q and P0", &p, swing + 1, 4);

    sig_chain_params_paper_f(&p);
    p.q = BIG;
    p.r = BIG;
    p.seed_first = true;    /* P0 < R: a start from x0 is refused (sig_chain.h) */
    {
        sig_real small[4] = {1, 2, 3, 4};
        run("huge Q and R", &p, small, 4);
    }
    return check_report("test_chain_extremes");
}
