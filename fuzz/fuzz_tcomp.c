/* fuzz_tcomp.c - the temperature-compensation evaluator (sig_tcomp, and the
 * Horner kernels of sig_poly under it) with arbitrary models, temperatures
 * and readings, in both numeric forms.
 *
 * Invariants:
 *   init    rejected parameters give SIG_ERR_ARG / SIG_ERR_NONFINITE and leave
 *           the model byte for byte as it was;
 *   q16     sig_tcomp_apply_q and sig_tcomp_delta_q equal an int64
 *           re-implementation of sig_tcomp.h's formulas (clamp, scale,
 *           Horner with saturation flags, rounding, int16 saturation), bit
 *           for bit and flag for flag; in == out aliasing gives the same;
 *   float   a NaN temperature or non-finite reading gives SIG_ERR_NONFINITE
 *           with the outputs untouched; any other call gives OK/CLAMPED with
 *           no NaN in the outputs, or SIG_ERR_NONFINITE (Horner overflow)
 *           with the outputs untouched; for moderate models the result is
 *           within float rounding of a double evaluation. */
#include <math.h>
#include <stdlib.h>

#include "fuzz_input.h"
#include "sig_tcomp.h"

#define REQUIRE(cond) do { if (!(cond)) abort(); } while (0)

static int64_t floor_shift(int64_t x, unsigned n)
{
    int64_t d = (int64_t)1 << n, q = x / d;
    return (x % d != 0 && x < 0) ? q - 1 : q;
}

static int64_t sat(int64_t x, int64_t lo, int64_t hi) { return x < lo ? lo : x > hi ? hi : x; }

/* delta in Q(q) before rounding, and the status bits, per sig_tcomp.h */
static int32_t ref_delta(const sig_tcomp_q *m, unsigned axis, int16_t t, sig_status *st)
{
    int64_t tc = t, prod, u, acc, s;
    int k;
    *st = SIG_OK;
    if (tc < m->t_lo) { tc = m->t_lo; *st = SIG_WARN_CLAMPED; }
    else if (tc > m->t_hi) { tc = m->t_hi; *st = SIG_WARN_CLAMPED; }
    prod = (tc - m->t_center) * m->u_mul;
    if (m->u_shift > 0) prod += (int64_t)1 << (m->u_shift - 1);
    u = floor_shift(prod, m->u_shift);
    REQUIRE(u >= -32767 && u <= 32767);        /* init promised |u| <= 32767 */
    acc = m->coef[axis][m->order];
    for (k = m->order; k > 0; k--) {
        s = m->coef[axis][k - 1] + floor_shift(acc * u, 15);
        if (s != sat(s, INT32_MIN, INT32_MAX)) *st |= SIG_WARN_SATURATED;
        acc = sat(s, INT32_MIN, INT32_MAX);
    }
    return (int32_t)acc;
}

static void fuzz_fixed(fuzz_input *in)
{
    uint8_t n_axes = fuzz_u8(in), order = fuzz_u8(in), steer = fuzz_u8(in), u_shift = fuzz_u8(in);
    int16_t t_lo = fuzz_i16(in), t_hi = fuzz_i16(in), t_center = fuzz_i16(in), t0 = fuzz_i16(in);
    int16_t u_mul = fuzz_i16(in);
    int32_t coef[3 * 9];
    uint8_t q[3];
    sig_tcomp_q m, before;
    sig_status st;
    unsigned a, k, n_coef;

    if (steer & 1u) {
        /* valid counts, a centred range and the largest u_mul keeping |u| <= 32767 */
        int32_t half;
        n_axes = (uint8_t)(1u + n_axes % 3u);
        order = (uint8_t)(1u + order % 8u);
        u_shift %= 16u;
        if (t_lo > t_hi) { int16_t x = t_lo; t_lo = t_hi; t_hi = x; }
        if (t_lo == t_hi) t_hi = (int16_t)(t_lo == INT16_MAX ? t_lo : t_lo + 1), t_lo = (int16_t)(t_hi - 1);
        t_center = (int16_t)(((int32_t)t_lo + t_hi) / 2);
        half = (int32_t)t_hi - t_center > t_center - (int32_t)t_lo ? (int32_t)t_hi - t_center : t_center - (int32_t)t_lo;
        if (half <= 32767 && half > 0) {
            int64_t um = (((int64_t)32767 << u_shift) - ((int64_t)1 << u_shift >> 1)) / half;
            u_mul = (int16_t)(um > 32767 ? 32767 : um < 1 ? 1 : um);
        }
    }
    n_coef = (n_axes >= 1 && n_axes <= 3 && order >= 1 && order <= 8) ? n_axes * (order + 1u) : 27u;
    for (k = 0; k < n_coef && k < 27u; k++) {
        /* steer bit 2: moderate coefficients, so init proves no overflow and
         * the unsaturated Horner fast path runs */
        if (steer & 4u) coef[k] = (int32_t)fuzz_i16(in) * (INT32_C(1) << (fuzz_u8(in) % 15u));
        else coef[k] = fuzz_i32_edgy(in);
    }
    for (a = 0; a < 3; a++) q[a] = (steer & 2u) ? fuzz_u8(in) : (uint8_t)(fuzz_u8(in) % 31u);

    memset(&m, 0x3C, sizeof m);
    before = m;
    st = sig_tcomp_init_q(&m, n_axes, order, coef, q, t_lo, t_hi, t_center, t0, u_mul, u_shift);
    if (st != SIG_OK) {
        REQUIRE(st == SIG_ERR_ARG && memcmp(&m, &before, sizeof m) == 0);
        return;
    }
    for (k = 0; k < 24u; k++) {
        int16_t t = k == 0 ? INT16_MIN : k == 1 ? INT16_MAX : k == 2 ? t_lo : k == 3 ? t_hi : fuzz_i16(in);
        int16_t r[3], out[3], alias[3];
        sig_status want = SIG_OK, st_axis;
        for (a = 0; a < 3; a++) { r[a] = fuzz_i16(in); out[a] = 0x5A5A; }
        for (a = 0; a < n_axes; a++) {
            int64_t d = ref_delta(&m, a, t, &st_axis), c;
            int32_t got;
            REQUIRE(sig_tcomp_delta_q(&m, (uint8_t)a, t, &got) == st_axis && got == d);
            want |= st_axis;
            if (m.q[a] > 0) d = floor_shift(sat(d + ((int64_t)1 << (m.q[a] - 1)), INT32_MIN, INT32_MAX), m.q[a]);
            c = sat((int64_t)r[a] - d, INT32_MIN, INT32_MAX);
            if (c != sat(c, INT16_MIN, INT16_MAX)) want |= SIG_WARN_SATURATED;
            alias[a] = (int16_t)sat(c, INT16_MIN, INT16_MAX);
        }
        st = sig_tcomp_apply_q(&m, t, r, out);
        REQUIRE(st == want);
        for (a = 0; a < n_axes; a++) REQUIRE(out[a] == alias[a]);
        for (a = n_axes; a < 3; a++) REQUIRE(out[a] == 0x5A5A);   /* only n_axes written */
        REQUIRE(sig_tcomp_apply_q(&m, t, r, r) == want);
        for (a = 0; a < n_axes; a++) REQUIRE(r[a] == out[a]);
        if (k >= 4u && fuzz_left(in) == 0) break;
    }
}


static void fuzz_float(fuzz_input *in)
{
    uint8_t n_axes = fuzz_u8(in), order = fuzz_u8(in), steer = fuzz_u8(in);
    sig_real t_lo = fuzz_real(in), t_hi = fuzz_real(in), center = fuzz_real(in), inv_scale = fuzz_real(in);
    sig_real coef[27];
    sig_tcomp_f m, before;
    sig_status st;
    unsigned a, k, n_coef;
    int moderate = 1;

    if (steer & 1u) {
        n_axes = (uint8_t)(1u + n_axes % 3u);
        order = (uint8_t)(1u + order % 8u);
        t_lo = (sig_real)fuzz_i16(in) / 100;
        t_hi = t_lo + (sig_real)(fuzz_u16(in) | 1u) / 100;
        center = (t_lo + t_hi) / 2;
        inv_scale = 2 / (t_hi - t_lo);
    }
    n_coef = (n_axes >= 1 && n_axes <= 3 && order >= 1 && order <= 8) ? n_axes * (order + 1u) : 27u;
    for (k = 0; k < n_coef && k < 27u; k++) {
        coef[k] = (steer & 2u) ? (sig_real)fuzz_i32(in) / 65536 : fuzz_real(in);
        if (!(fabs((double)coef[k]) <= 1e6)) moderate = 0;
    }
    memset(&m, 0x3C, sizeof m);
    before = m;
    st = sig_tcomp_init_f(&m, n_axes, order, coef, t_lo, t_hi, center, inv_scale);
    if (st != SIG_OK) {
        REQUIRE((st == SIG_ERR_ARG || st == SIG_ERR_NONFINITE) && memcmp(&m, &before, sizeof m) == 0);
        return;
    }
    for (k = 0; k < 16u; k++) {
        sig_real t = k == 0 ? t_lo : k == 1 ? t_hi : fuzz_real(in);
        sig_real r[3], out[3];
        int any_nonfinite = 0;
        for (a = 0; a < 3; a++) {
            r[a] = (steer & 4u) ? fuzz_real(in) : (sig_real)fuzz_i16(in);
            out[a] = (sig_real)777;
            if (a < n_axes && !sig_real_isfinite(r[a])) any_nonfinite = 1;
        }
        st = sig_tcomp_apply_f(&m, t, r, out);
        if (t != t || any_nonfinite) {
            REQUIRE(st == SIG_ERR_NONFINITE);
        } else {
            REQUIRE(st == SIG_ERR_NONFINITE || st == ((t < t_lo || t > t_hi) ? SIG_WARN_CLAMPED : SIG_OK));
        }
        if (st < 0) {
            for (a = 0; a < 3; a++) REQUIRE(out[a] == (sig_real)777);
        } else {
            sig_real tc = t < m.t_lo ? m.t_lo : t > m.t_hi ? m.t_hi : t;
            sig_real u = (tc - m.center) * m.inv_scale;
            for (a = 0; a < n_axes; a++) {
                double acc = (double)m.coef[a][m.order], mag = fabs(acc);
                int j;
                REQUIRE(out[a] == out[a]);
                for (j = m.order; j > 0; j--) {
                    acc = (double)m.coef[a][j - 1] + acc * (double)u;
                    mag = fabs((double)m.coef[a][j - 1]) + mag * fabs((double)u);
                }
                if (moderate && fabs((double)u) <= 1.0 && fabs((double)r[a]) <= 1e6)
                    REQUIRE(fabs((double)out[a] - ((double)r[a] - acc))
                            <= 1e-5 * (mag + fabs((double)r[a])) + 1e-30);
            }
            for (a = n_axes; a < 3; a++) REQUIRE(out[a] == (sig_real)777);
        }
        if (k >= 2u && fuzz_left(in) == 0) break;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_make(data, size);
    if (fuzz_u8(&in) & 1u) fuzz_float(&in);
    else fuzz_fixed(&in);
    return 0;
}
