/* fuzz_pwl.c - the piecewise-linear table (sig_pwl) with arbitrary
 * parameters, tables and temperatures.
 *
 * The table is copied into a heap buffer of exactly n_knots entries, so any
 * read past it is an AddressSanitizer report.  Invariants:
 *   init   rejected parameters return SIG_ERR_ARG (SIG_ERR_NONFINITE for a
 *          non-finite float entry) and leave the struct byte for byte as it was;
 *   q16    equals an int64 re-implementation of sig_pwl.h's formulas, lies
 *          between the smallest and largest knot (interpolation never
 *          overshoots), and flags SIG_WARN_CLAMPED exactly when t is outside
 *          [t_lo, t_hi];
 *   float  a NaN temperature gives SIG_ERR_NONFINITE with *out untouched;
 *          otherwise the output is finite and within the knots' range. */
#include <stdlib.h>

#include "fuzz_input.h"
#include "sig_pwl.h"

#define REQUIRE(cond) do { if (!(cond)) abort(); } while (0)

static int64_t floor_shift(int64_t x, unsigned n)
{
    int64_t d = (int64_t)1 << n, q = x / d;
    return (x % d != 0 && x < 0) ? q - 1 : q;
}

static int32_t ref_eval_q16(const int16_t *tab, unsigned n, int16_t t_lo, int16_t t_hi,
                            uint32_t recip, uint8_t vf, int16_t t)
{
    int64_t d, pos, seg, acc, out;
    if (t < t_lo) t = t_lo;
    if (t > t_hi) t = t_hi;
    d = (int64_t)t - t_lo;
    pos = (d * (int64_t)recip) >> 16;           /* Q16.16 segment position */
    seg = pos >> 16;
    if (seg >= (int64_t)n - 1) acc = (int64_t)tab[n - 1] * 4096;
    else acc = (int64_t)tab[seg] * 4096 + ((int64_t)tab[seg + 1] - tab[seg]) * ((pos & 0xFFFF) >> 4);
    out = vf >= 4 ? floor_shift(acc, vf - 4u) : acc * ((int64_t)1 << (4u - vf));
    return out > INT32_MAX ? INT32_MAX : out < INT32_MIN ? INT32_MIN : (int32_t)out;
}

static void fuzz_q16(fuzz_input *in)
{
    uint8_t n = fuzz_u8(in), vf = fuzz_u8(in), derive = fuzz_u8(in);
    int16_t t_lo = fuzz_i16(in), t_hi = fuzz_i16(in);
    uint32_t recip = fuzz_take_bits(in, 4);
    int16_t *tab = malloc(n ? n * sizeof *tab : 1u);
    int32_t lo_knot = INT16_MAX, hi_knot = INT16_MIN;
    sig_pwl_q16 p, before;
    sig_status st;
    unsigned k;

    for (k = 0; k < n; k++) {
        tab[k] = fuzz_i16(in);
        if (tab[k] < lo_knot) lo_knot = tab[k];
        if (tab[k] > hi_knot) hi_knot = tab[k];
    }
    if (derive & 1u) {
        /* steer towards valid parameters: the recip that puts t_hi on the last knot */
        int64_t span = (int64_t)t_hi - t_lo;
        vf &= 15u;
        if (span > 0 && n >= 2) {
            int64_t r = ((int64_t)(n - 1) << 32) / span - (int64_t)(derive >> 1);
            if (r > 0 && r <= (int64_t)UINT32_MAX) recip = (uint32_t)r;
        }
    }
    memset(&p, 0xA5, sizeof p);
    before = p;
    st = sig_pwl_init_q16(&p, tab, n, t_lo, t_hi, recip, vf);
    if (st != SIG_OK) {
        REQUIRE(st == SIG_ERR_ARG);
        REQUIRE(memcmp(&p, &before, sizeof p) == 0);
    } else {
        int32_t scale = INT32_C(1) << (16u - vf);      /* Q16.16 per table unit */
        int16_t ts[4] = {INT16_MIN, INT16_MAX, t_lo, t_hi};
        for (k = 0; k < 4u + 16u; k++) {
            int16_t t = k < 4u ? ts[k] : fuzz_i16(in);
            int32_t out = 0x5A5A5A5A;
            st = sig_pwl_eval_q16(&p, t, &out);
            REQUIRE(st == ((t < t_lo || t > t_hi) ? SIG_WARN_CLAMPED : SIG_OK));
            REQUIRE(out == ref_eval_q16(tab, n, t_lo, t_hi, recip, vf, t));
            REQUIRE(out >= lo_knot * scale && out <= hi_knot * scale);
            if (k >= 4u && fuzz_left(in) == 0) break;
        }
    }
    free(tab);
}


static void fuzz_float(fuzz_input *in)
{
    uint8_t n = fuzz_u8(in), derive = fuzz_u8(in);
    sig_real t_lo = fuzz_real(in), t_hi = fuzz_real(in), inv_step = fuzz_real(in);
    sig_real *tab = malloc(n ? n * sizeof *tab : 1u);
    sig_real lo_knot = 0, hi_knot = 0;
    sig_pwl_f p, before;
    sig_status st;
    unsigned k;
    int all_finite = 1;

    for (k = 0; k < n; k++) {
        tab[k] = (derive & 2u) ? (sig_real)fuzz_i16(in) : fuzz_real(in);
        all_finite &= sig_real_isfinite(tab[k]);
        if (k == 0 || tab[k] < lo_knot) lo_knot = tab[k];
        if (k == 0 || tab[k] > hi_knot) hi_knot = tab[k];
    }
    if ((derive & 1u) && n >= 2 && t_hi > t_lo) inv_step = (sig_real)(n - 1) / (t_hi - t_lo);
    memset(&p, 0xA5, sizeof p);
    before = p;
    st = sig_pwl_init_f(&p, tab, n, t_lo, t_hi, inv_step);
    if (st != SIG_OK) {
        REQUIRE(st == SIG_ERR_ARG || (st == SIG_ERR_NONFINITE && !all_finite));
        REQUIRE(memcmp(&p, &before, sizeof p) == 0);
    } else {
        REQUIRE(all_finite);
        for (k = 0; k < 16u; k++) {
            sig_real t = k == 0 ? t_lo : k == 1 ? t_hi : fuzz_real(in);
            sig_real out = (sig_real)12345;
            st = sig_pwl_eval_f(&p, t, &out);
            if (t != t) {
                REQUIRE(st == SIG_ERR_NONFINITE && out == (sig_real)12345);
            } else {
                REQUIRE(st == ((t < t_lo || t > t_hi) ? SIG_WARN_CLAMPED : SIG_OK));
                REQUIRE(sig_real_isfinite(out));
                REQUIRE(out >= lo_knot && out <= hi_knot);
            }
            if (k >= 2u && fuzz_left(in) == 0) break;
        }
    }
    free(tab);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_make(data, size);
    if (fuzz_u8(&in) & 1u) fuzz_float(&in);
    else fuzz_q16(&in);
    return 0;
}
