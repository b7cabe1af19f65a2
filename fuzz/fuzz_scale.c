/* fuzz_scale.c - the counts -> mass calibration (sig_scale) with arbitrary
 * offsets, gains, shifts and counts, in both numeric forms.
 *
 * Invariants:
 *   init   gain_mant 0 or gain_shift > 62 (fixed), a zero or non-finite
 *          gain or offset (float) is rejected and the struct is untouched;
 *   q16    equals floor(sat32(counts - offset) * gain_mant / 2^gain_shift)
 *          computed with 128-bit integers, saturated to int32, and
 *          SIG_WARN_SATURATED is set exactly when the difference or the
 *          result left int32 (never wraps);
 *   float  a non-finite count gives SIG_ERR_NONFINITE with the output
 *          untouched; otherwise no NaN comes out. */
#include <stdlib.h>

#include "fuzz_input.h"
#include "sig_scale.h"

#define REQUIRE(cond) do { if (!(cond)) abort(); } while (0)

static void fuzz_fixed(fuzz_input *in)
{
    int32_t offset = fuzz_i32_edgy(in), gain = fuzz_i32_edgy(in);
    uint8_t shift = fuzz_u8(in);
    sig_scale_q16 s, before;
    sig_status st;
    int k;
    if (shift & 0x80u) shift &= 63u;                 /* mostly valid shifts */
    memset(&s, 0x6B, sizeof s);
    before = s;
    st = sig_scale_init_q16(&s, offset, gain, shift);
    if (gain == 0 || shift > 62u) {
        REQUIRE(st == SIG_ERR_ARG && memcmp(&s, &before, sizeof s) == 0);
        return;
    }
    REQUIRE(st == SIG_OK);
    for (k = 0; k < 32; k++) {
        int32_t counts = k == 0 ? INT32_MIN : k == 1 ? INT32_MAX : k == 2 ? offset : fuzz_i32_edgy(in);
        int64_t exact_d = (int64_t)counts - offset;
        int32_t d = exact_d > INT32_MAX ? INT32_MAX : exact_d < INT32_MIN ? INT32_MIN : (int32_t)exact_d;
        __int128 p = (__int128)d * gain, q = p >> shift;   /* arithmetic shift: floor */
        int32_t want = q > INT32_MAX ? INT32_MAX : q < INT32_MIN ? INT32_MIN : (int32_t)q;
        int sat = exact_d != d || q != want;
        int32_t out = 0x12345678;
        st = sig_scale_apply_q16(&s, counts, &out);
        REQUIRE(out == want);
        REQUIRE(st == (sat ? SIG_WARN_SATURATED : SIG_OK));
        if (k > 2 && fuzz_left(in) == 0) break;
    }
}

static void fuzz_float(fuzz_input *in)
{
    sig_real offset = fuzz_real(in), gain = fuzz_real(in);
    sig_scale_f s, before;
    sig_status st;
    int k;
    memset(&s, 0x6B, sizeof s);
    before = s;
    st = sig_scale_init_f(&s, offset, gain);
    if (st != SIG_OK) {
        REQUIRE((st == SIG_ERR_ARG || st == SIG_ERR_NONFINITE) && memcmp(&s, &before, sizeof s) == 0);
        REQUIRE(st == SIG_ERR_NONFINITE ? !(offset - offset == 0 && gain - gain == 0) : gain == 0);
        return;
    }
    REQUIRE(offset - offset == 0 && gain - gain == 0 && gain != 0);
    for (k = 0; k < 32 && fuzz_left(in) > 0; k++) {
        sig_real counts = (k & 1) ? fuzz_real(in) : (sig_real)fuzz_i32(in);
        sig_real out = (sig_real)42;
        st = sig_scale_apply_f(&s, counts, &out);
        if (!(counts - counts == 0)) {
            REQUIRE(st == SIG_ERR_NONFINITE && out == (sig_real)42);
        } else {
            REQUIRE(st >= 0 && out == out);
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_make(data, size);
    if (fuzz_u8(&in) & 1u) fuzz_float(&in);
    else fuzz_fixed(&in);
    return 0;
}
