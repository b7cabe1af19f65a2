/* test_pwl.c - sig_pwl: parameter checks leave the struct untouched, the
 * fixed-point evaluation equals an int64 re-implementation over every int16
 * temperature for a few tables, the float evaluation interpolates, clamps
 * and rejects NaN, and a table whose neighbouring entries differ by more
 * than the float range neither overflows nor produces NaN. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "sig_pwl.h"

static int64_t floor_shift(int64_t x, unsigned n)
{
    int64_t d = (int64_t)1 << n, q = x / d;
    return (x % d != 0 && x < 0) ? q - 1 : q;
}

static int32_t ref_q16(const int16_t *tab, unsigned n, int16_t t_lo, int16_t t_hi,
                       uint32_t recip, uint8_t vf, int32_t t)
{
    int64_t pos, seg, acc, out;
    if (t < t_lo) t = t_lo;
    if (t > t_hi) t = t_hi;
    pos = (((int64_t)t - t_lo) * (int64_t)recip) >> 16;
    seg = pos >> 16;
    if (seg >= (int64_t)n - 1) acc = (int64_t)tab[n - 1] * 4096;
    else acc = (int64_t)tab[seg] * 4096 + ((int64_t)tab[seg + 1] - tab[seg]) * ((pos & 0xFFFF) >> 4);
    out = vf >= 4 ? floor_shift(acc, vf - 4u) : acc * ((int64_t)1 << (4u - vf));
    return out > INT32_MAX ? INT32_MAX : out < INT32_MIN ? INT32_MIN : (int32_t)out;
}

static void sweep_q16(const int16_t *tab, uint8_t n, int16_t t_lo, int16_t t_hi, uint8_t vf)
{
    sig_pwl_q16 p;
    int32_t t, out;
    int64_t r = ((int64_t)(n - 1) << 32) / ((int32_t)t_hi - t_lo);
    uint32_t recip = r > (int64_t)UINT32_MAX ? UINT32_MAX : (uint32_t)r;   /* Q0.32 tops out below 1 */
    CHECK_EQ_I(sig_pwl_init_q16(&p, tab, n, t_lo, t_hi, recip, vf), SIG_OK);
    for (t = INT16_MIN; t <= INT16_MAX; t++) {
        sig_status st = sig_pwl_eval_q16(&p, (int16_t)t, &out);
        CHECK_EQ_I(st, (t < t_lo || t > t_hi) ? SIG_WARN_CLAMPED : SIG_OK);
        CHECK_EQ_I(out, ref_q16(tab, n, t_lo, t_hi, recip, vf, t));
    }
}

int main(void)
{
    static const int16_t rails[3] = {INT16_MIN, INT16_MAX, INT16_MIN};
    static const int16_t ramp[5] = {-1000, 0, 250, 251, 30000};
    static const sig_real ftab[3] = {SIG_REAL(1.0), SIG_REAL(3.0), SIG_REAL(-1.0)};
    sig_pwl_q16 p, before;
    sig_pwl_f pf, before_f;
    sig_real out;

    sweep_q16(rails, 3, -32768, 32767, 0);        /* the largest values, at value_frac 0 */
    sweep_q16(rails, 3, -100, 100, 15);
    sweep_q16(ramp, 5, -2000, 2000, 4);
    sweep_q16(ramp, 2, 0, 1, 7);
    sweep_q16(ramp, 5, 1000, 1013, 5);            /* 4 segments over 13 units: knots between codes */

    memset(&p, 0x5A, sizeof p);
    before = p;
    {
        uint32_t r = (uint32_t)(((int64_t)4 << 32) / 100);   /* 4 segments over 100 units */
        CHECK_EQ_I(sig_pwl_init_q16(&p, ramp, 1, 0, 100, r, 4), SIG_ERR_ARG);      /* one knot */
        CHECK_EQ_I(sig_pwl_init_q16(&p, ramp, 5, 100, 100, r, 4), SIG_ERR_ARG);    /* empty range */
        CHECK_EQ_I(sig_pwl_init_q16(&p, ramp, 5, 0, 100, 0, 4), SIG_ERR_ARG);      /* recip 0 */
        CHECK_EQ_I(sig_pwl_init_q16(&p, ramp, 5, 0, 100, r * 2, 4), SIG_ERR_ARG);  /* ends past the table */
        CHECK_EQ_I(sig_pwl_init_q16(&p, ramp, 5, 0, 100, r / 2, 4), SIG_ERR_ARG);  /* ends short of it */
        CHECK_EQ_I(sig_pwl_init_q16(&p, ramp, 5, 0, 100, UINT32_MAX, 4), SIG_ERR_ARG);
        CHECK_EQ_I(sig_pwl_init_q16(&p, ramp, 5, 0, 100, r, 16), SIG_ERR_ARG);     /* value_frac */
        CHECK_EQ_I(sig_pwl_init_q16(&p, NULL, 5, 0, 100, r, 4), SIG_ERR_ARG);
        CHECK_EQ_I(sig_pwl_init_q16(NULL, ramp, 5, 0, 100, r, 4), SIG_ERR_ARG);
    }
    CHECK(memcmp(&p, &before, sizeof p) == 0);

    memset(&pf, 0x5A, sizeof pf);
    before_f = pf;
    CHECK_EQ_I(sig_pwl_init_f(&pf, ftab, 3, SIG_REAL(1.0), SIG_REAL(1.0), SIG_REAL(1.0)), SIG_ERR_ARG);
    CHECK_EQ_I(sig_pwl_init_f(&pf, ftab, 3, (sig_real)NAN, SIG_REAL(2.0), SIG_REAL(1.0)), SIG_ERR_ARG);
    CHECK_EQ_I(sig_pwl_init_f(&pf, ftab, 3, SIG_REAL(0.0), (sig_real)INFINITY, SIG_REAL(1.0)), SIG_ERR_ARG);
    CHECK_EQ_I(sig_pwl_init_f(&pf, ftab, 3, SIG_REAL(0.0), SIG_REAL(2.0), SIG_REAL(0.0)), SIG_ERR_ARG);
    CHECK(memcmp(&pf, &before_f, sizeof pf) == 0);

    CHECK_EQ_I(sig_pwl_init_f(&pf, ftab, 3, SIG_REAL(10.0), SIG_REAL(30.0), SIG_REAL(0.1)), SIG_OK);
    CHECK_EQ_I(sig_pwl_eval_f(&pf, SIG_REAL(15.0), &out), SIG_OK);
    CHECK(out == SIG_REAL(2.0));
    CHECK_EQ_I(sig_pwl_eval_f(&pf, SIG_REAL(-1e30), &out), SIG_WARN_CLAMPED);
    CHECK(out == SIG_REAL(1.0));
    CHECK_EQ_I(sig_pwl_eval_f(&pf, (sig_real)INFINITY, &out), SIG_WARN_CLAMPED);
    CHECK(out == SIG_REAL(-1.0));
    out = SIG_REAL(7.0);
    CHECK_EQ_I(sig_pwl_eval_f(&pf, (sig_real)NAN, &out), SIG_ERR_NONFINITE);
    CHECK(out == SIG_REAL(7.0));
    return check_report("test_pwl");
}
