/* test_types.c - sig_types.h helpers against int64 references: every pair
 * of edge values (rails, +-1 around them, powers of two and their
 * neighbours) and a million pseudo-random pairs. */
#include <stdint.h>

#include "check.h"
#include "sig_types.h"

static int64_t floor_div_pow2(int64_t x, unsigned n)
{
    int64_t d = (int64_t)1 << n;
    int64_t q = x / d;
    if (x % d != 0 && x < 0) q -= 1;
    return q;
}

static int32_t sat32(int64_t x)
{
    return x > INT32_MAX ? INT32_MAX : x < INT32_MIN ? INT32_MIN : (int32_t)x;
}

static void check_pair(int32_t a, int32_t b)
{
    int64_t p = (int64_t)a * (int64_t)b;
    CHECK_EQ_I(sig_mul_q16_sat(a, b), sat32(floor_div_pow2(p, 16)));
    CHECK_EQ_I(sig_sat_add32(a, b), sat32((int64_t)a + b));
    CHECK_EQ_I(sig_sat_sub32(a, b), sat32((int64_t)a - b));
}

static void check_one(int32_t a)
{
    uint8_t n;
    for (n = 0; n < 32; n++) {
        CHECK_EQ_I(sig_asr32(a, n), floor_div_pow2(a, n));
        CHECK_EQ_I(sig_shl32_sat(a, n), sat32((int64_t)a * ((int64_t)1 << n)));
    }
    CHECK_EQ_I(sig_sat16(a), a > INT16_MAX ? INT16_MAX : a < INT16_MIN ? INT16_MIN : a);
    CHECK_EQ_I(sig_abs32_sat(a), sat32(a < 0 ? -(int64_t)a : a));
}

int main(void)
{
    int32_t edges[200];
    size_t n_edges = 0, i, j;
    long k;
    int s;

    edges[n_edges++] = INT32_MIN;
    edges[n_edges++] = INT32_MIN + 1;
    edges[n_edges++] = INT32_MAX;
    edges[n_edges++] = INT32_MAX - 1;
    edges[n_edges++] = 0;
    for (s = 0; s < 31; s++) {
        int32_t p = (int32_t)1 << s;
        edges[n_edges++] = p;
        edges[n_edges++] = p - 1;
        edges[n_edges++] = p + 1;
        edges[n_edges++] = -p;
        edges[n_edges++] = -p - 1;
        edges[n_edges++] = 1 - p;
    }
    for (i = 0; i < n_edges; i++) {
        check_one(edges[i]);
        for (j = 0; j < n_edges; j++) check_pair(edges[i], edges[j]);
    }
    for (k = 0; k < 1000000L; k++) {
        int32_t a = (int32_t)(uint32_t)check_rand32();
        int32_t b = (int32_t)(uint32_t)check_rand32();
        check_pair(a, b);
        /* products near the saturation boundary: b ~ 2^47 / a */
        if (a != 0) check_pair(a, (int32_t)(((int64_t)INT32_MAX << 16) / a / ((k & 1) ? 1 : -1)));
        if ((k & 1023) == 0) check_one(a);
    }
    /* documented fixed points */
    CHECK_EQ_I(sig_mul_q16_sat(SIG_Q16_ONE, SIG_Q16_ONE), SIG_Q16_ONE);
    CHECK_EQ_I(sig_mul_q16_sat(-1, 1), -1);          /* floor(-1/65536) = -1 */
    CHECK_EQ_I(sig_mul_q16_sat(INT32_MIN, INT32_MIN), INT32_MAX);
    CHECK_EQ_I(sig_mul_q16_sat(INT32_MIN, SIG_Q16_ONE), INT32_MIN);
    CHECK_EQ_I(sig_asr32(-1, 31), -1);
    CHECK_EQ_I(sig_shl32_sat(INT32_MIN, 1), INT32_MIN);
    return check_report("test_types");
}
