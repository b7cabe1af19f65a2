/* fuzz_types.c - the saturating helpers of sig_types.h against int64
 * references: sig_mul_q16_sat must equal floor(a*b / 2^16) saturated to
 * int32 for every a, b; sig_asr32 must floor; sig_shl32_sat, sig_sat_add32,
 * sig_sat_sub32, sig_sat16 and sig_abs32_sat must saturate, never wrap. */
#include <stdlib.h>

#include "fuzz_input.h"
#include "sig_types.h"

static int64_t floor_div_pow2(int64_t x, unsigned n)
{
    int64_t d = (int64_t)1 << n;
    int64_t q = x / d;                     /* truncates toward zero */
    if (x % d != 0 && x < 0) q -= 1;
    return q;
}

static int32_t sat32(int64_t x)
{
    if (x > INT32_MAX) return INT32_MAX;
    if (x < INT32_MIN) return INT32_MIN;
    return (int32_t)x;
}

#define REQUIRE(cond) do { if (!(cond)) abort(); } while (0)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_make(data, size);
    do {
        int32_t a = fuzz_i32_edgy(&in);
        int32_t b = fuzz_i32_edgy(&in);
        uint8_t n = (uint8_t)(fuzz_u8(&in) & 31u);
        int64_t prod = (int64_t)a * (int64_t)b;

        REQUIRE(sig_mul_q16_sat(a, b) == sat32(floor_div_pow2(prod, 16)));
        REQUIRE(sig_mul_q16_sat(a, b) == sig_mul_q16_sat(b, a));
        REQUIRE(sig_asr32(a, n) == (int32_t)floor_div_pow2(a, n));
        REQUIRE(sig_shl32_sat(a, n) == sat32((int64_t)a * ((int64_t)1 << n)));
        REQUIRE(sig_sat_add32(a, b) == sat32((int64_t)a + b));
        REQUIRE(sig_sat_sub32(a, b) == sat32((int64_t)a - b));
        REQUIRE(sig_sat16(a) == (a > INT16_MAX ? INT16_MAX : a < INT16_MIN ? INT16_MIN : a));
        REQUIRE(sig_abs32_sat(a) == sat32(a < 0 ? -(int64_t)a : (int64_t)a));
    } while (fuzz_left(&in) > 0);
    return 0;
}
