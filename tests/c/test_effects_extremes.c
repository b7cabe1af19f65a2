/* test_effects_extremes.c - the float lag (thermal lag, creep) keeps a valid
 * state for any finite input.  Found by fuzz/fuzz_effects.c: inputs that
 * swing from +BIG to -BIG made x - z overflow to -inf, z became -inf, and
 * the next step's inf - inf left z NaN for good (every later output NaN).
 * A first-order lag is a convex combination of its inputs: z must stay
 * within [min x, max x]. */
#include <float.h>

#include "check.h"
#include "sig_effects.h"

#ifdef SIG_REAL_DOUBLE
#define BIG ((sig_real)(DBL_MAX / 1.5))
#else
#define BIG ((sig_real)(FLT_MAX / 1.5f))
#endif

int main(void)
{
    sig_lag_f lag;
    sig_creep_f creep;
    sig_real out, c, y;
    sig_real xs[6];
    int i;
    xs[0] = BIG; xs[1] = -BIG; xs[2] = -BIG; xs[3] = BIG; xs[4] = SIG_REAL(1.0); xs[5] = SIG_REAL(0.0);

    CHECK_EQ_I(sig_lag_init_f(&lag, SIG_REAL(0.5)), SIG_OK);
    CHECK_EQ_I(sig_creep_init_f(&creep, SIG_REAL(0.5), SIG_REAL(0.0)), SIG_OK);
    for (i = 0; i < 6; i++) {
        CHECK_EQ_I(sig_lag_step_f(&lag, xs[i], &out), SIG_OK);
        CHECK(lag.z == lag.z && lag.z >= -BIG && lag.z <= BIG);
        CHECK(out == lag.z);
        CHECK_EQ_I(sig_creep_step_f(&creep, xs[i], &c, &y), SIG_OK);
        CHECK(creep.lag.z == creep.lag.z && c == c && y == y);
    }
    return check_report("test_effects_extremes");
}
