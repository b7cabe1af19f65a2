/* test_scale.c - sig_scale_apply_q16 against a 64-bit oracle (host only:
 * the test may use long long, the library may not), edge values and a
 * pseudo-random sweep over every shift; argument checks leave state alone;
 * the float form refuses non-finite values. */
#include "check.h"
#include "sig_scale.h"

static long long floor_shift(long long p, unsigned n)
{
    long long d;
    if (n == 0u) return p;
    d = 1LL << n;
    if (p >= 0) return p / d;
    return -((-p + d - 1) / d);
}

static void oracle(int32_t counts, int32_t offset, int32_t mant, uint8_t shift,
                   int32_t *out, int *sat)
{
    long long d = (long long)counts - (long long)offset, q;
    *sat = 0;
    if (d > INT32_MAX) { d = INT32_MAX; *sat = 1; }
    if (d < INT32_MIN) { d = INT32_MIN; *sat = 1; }
    q = floor_shift(d * (long long)mant, shift);
    if (q > INT32_MAX) { q = INT32_MAX; *sat = 1; }
    if (q < INT32_MIN) { q = INT32_MIN; *sat = 1; }
    *out = (int32_t)q;
}

static void check_one(int32_t counts, int32_t offset, int32_t mant, uint8_t shift)
{
    sig_scale_q16 s;
    int32_t got = 12345, want;
    int sat;
    sig_status st;
    CHECK(sig_scale_init_q16(&s, offset, mant, shift) == SIG_OK);
    st = sig_scale_apply_q16(&s, counts, &got);
    oracle(counts, offset, mant, shift, &want, &sat);
    CHECK_EQ_I(got, want);
    CHECK_EQ_I(st, sat ? SIG_WARN_SATURATED : SIG_OK);
}

static const int32_t EDGES[] = {
    0, 1, -1, 2, -2, 3, -3, 65535, -65535, 65536, -65536, 65537, -65537,
    (1L << 23) - 1, -(1L << 23), 0x7FFF, -0x8000, 0x10000000L, -0x10000000L,
    INT32_MAX, INT32_MIN, INT32_MAX - 1, INT32_MIN + 1, 0x40000000L, -0x40000000L,
};
#define N_EDGES (sizeof EDGES / sizeof EDGES[0])

int main(void)
{
    sig_scale_q16 s;
    sig_scale_f f;
    sig_real m = SIG_REAL(7.0);
    int32_t q = 99;
    unsigned i, j, k, n;

    for (n = 0; n <= 62u; n++)
        for (i = 0; i < N_EDGES; i++)
            for (j = 0; j < N_EDGES; j++) {
                if (EDGES[j] == 0) continue;
                for (k = 0; k < 4u; k++)
                    check_one(EDGES[i], k == 0 ? 0 : EDGES[(i + j + k) % N_EDGES], EDGES[j], (uint8_t)n);
            }
    for (i = 0; i < 200000u; i++) {
        int32_t c = (int32_t)check_rand32(), o = (int32_t)check_rand32(), g = (int32_t)check_rand32();
        uint8_t n8 = (uint8_t)(check_rand32() % 63u);
        if (g == 0) g = 1;
        if (i & 1u) { c >>= 8; o >>= 8; }          /* 24-bit ADC codes */
        check_one(c, o, g, n8);
    }

    /* argument checks leave the state as it was */
    CHECK(sig_scale_init_q16(&s, 5, 1000, 10) == SIG_OK);
    CHECK(sig_scale_init_q16(&s, 7, 0, 10) == SIG_ERR_ARG);
    CHECK(sig_scale_init_q16(&s, 7, 1000, 63) == SIG_ERR_ARG);
    CHECK(sig_scale_init_q16(NULL, 7, 1000, 10) == SIG_ERR_ARG);
    CHECK_EQ_I(s.offset, 5);
    CHECK_EQ_I(s.gain_mant, 1000);
    CHECK(sig_scale_apply_q16(&s, 1, NULL) == SIG_ERR_ARG);
    CHECK(sig_scale_apply_q16(NULL, 1, &q) == SIG_ERR_ARG);
    CHECK_EQ_I(q, 99);

    CHECK(sig_scale_init_f(&f, SIG_REAL(100.0), SIG_REAL(0.5)) == SIG_OK);
    CHECK(sig_scale_apply_f(&f, SIG_REAL(300.0), &m) == SIG_OK);
    CHECK(m == SIG_REAL(100.0));
    {
        volatile sig_real zero = SIG_REAL(0.0);
        sig_real nan = zero / zero, inf = SIG_REAL(1.0) / zero;
        CHECK(sig_scale_apply_f(&f, nan, &m) == SIG_ERR_NONFINITE);
        CHECK(sig_scale_apply_f(&f, inf, &m) == SIG_ERR_NONFINITE);
        CHECK(sig_scale_apply_f(&f, -inf, &m) == SIG_ERR_NONFINITE);
        CHECK(m == SIG_REAL(100.0));
        CHECK(sig_scale_init_f(&f, nan, SIG_REAL(1.0)) == SIG_ERR_NONFINITE);
        CHECK(sig_scale_init_f(&f, SIG_REAL(0.0), inf) == SIG_ERR_NONFINITE);
        CHECK(sig_scale_init_f(&f, SIG_REAL(0.0), SIG_REAL(0.0)) == SIG_ERR_ARG);
        CHECK(f.offset == SIG_REAL(100.0) && f.gain == SIG_REAL(0.5));
    }
    return check_report("test_scale");
}
