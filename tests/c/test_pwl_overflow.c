/* test_pwl_overflow.c - found by fuzz/fuzz_pwl.c: a float table whose
 * neighbouring entries are finite but differ by more than the largest float
 * (here -FLT_MAX, FLT_MAX) made sig_pwl_eval_f return +inf between the knots
 * and NaN (0 * inf) on the first knot.  Either init must reject such a table
 * or the evaluation must not overflow: never a non-finite output. */
#include <math.h>

#include "check.h"
#include "sig_pwl.h"

int main(void)
{
    sig_real tab[3];
    sig_pwl_f p;
    sig_real t, out;
    sig_status st;
    tab[0] = (sig_real)-3.4028235e38f;
    tab[1] = (sig_real)3.4028235e38f;
    tab[2] = SIG_REAL(0.0);
    st = sig_pwl_init_f(&p, tab, 3, SIG_REAL(0.0), SIG_REAL(2.0), SIG_REAL(1.0));
    if (st == SIG_OK) {
        for (t = SIG_REAL(0.0); t <= SIG_REAL(2.0); t += SIG_REAL(0.25)) {
            out = SIG_REAL(0.0);
            CHECK(sig_pwl_eval_f(&p, t, &out) >= 0);
            CHECK(isfinite(out));
            CHECK(out >= tab[0] && out <= tab[1]);
        }
    } else {
        CHECK(st == SIG_ERR_ARG || st == SIG_ERR_NONFINITE);
    }
    return check_report("test_pwl_overflow");
}
