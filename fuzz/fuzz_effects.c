/* fuzz_effects.c - the on-device refinement effects (sig_effects: lag,
 * hysteresis, creep, gain drift, nonlinearity, cross-axis) with arbitrary
 * parameters and inputs, in both numeric forms.
 *
 * Invariants:
 *   init    rejected parameters return an error and leave the struct as it was;
 *   lag_q   the output stays within one code of the hull of the inputs since
 *           the last reset (a first-order lag is a convex combination) unless
 *           SIG_WARN_SATURATED was raised;
 *   hyst_q  |branch| <= width and contribution == sat32(branch * k_q16);
 *   creep_q corrected == sat32(x - contribution);
 *   gain_q, nonlin_q, cross_q equal their definitions in sig_effects.h
 *           rebuilt from sig_poly_horner_q15 / sig_mul_q16_sat, and flag a
 *           rail whenever an output sits on one;
 *   refined sig_refined_step_q over a valid tcomp model with or without lag,
 *           hysteresis and gain: only warning bits; with no effect on it
 *           equals y * 2^16 - delta rescaled to Q16 (saturating), where
 *           delta comes from sig_tcomp_delta_q; a lag whose frac is not 16
 *           is refused with the struct untouched;
 *   float   finite inputs leave no NaN in the state (lag z, hysteresis p,
 *           creep lag) whatever their size; the stateless outputs are never
 *           NaN while every input and parameter is within 1e18 (beyond, a
 *           product may overflow: inf - inf); non-finite inputs give
 *           SIG_ERR_NONFINITE with the state and outputs untouched. */
#include <stdlib.h>

#include "fuzz_input.h"
#include "sig_effects.h"
#include "sig_tcomp.h"

#define REQUIRE(cond) do { if (!(cond)) abort(); } while (0)
#define STEPS 24

static int moderate(sig_real x) { return x >= (sig_real)-1e18 && x <= (sig_real)1e18; }
static int32_t sat32(int64_t v) { return v > INT32_MAX ? INT32_MAX : v < INT32_MIN ? INT32_MIN : (int32_t)v; }
static int at_rail(int32_t v) { return v == INT32_MAX || v == INT32_MIN; }

static void lag_and_creep_q(fuzz_input *in)
{
    int32_t alpha = fuzz_i32_edgy(in), k = fuzz_i32_edgy(in);
    uint8_t frac = fuzz_u8(in);
    sig_lag_q lag, before;
    sig_creep_q cr, cr_before;
    int64_t lo = INT64_MAX, hi = INT64_MIN;
    int n, saturated = 0;
    if (frac & 0x80u) { frac %= 17u; alpha = 1 + (int32_t)((uint32_t)alpha % 65536u); }
    memset(&lag, 0x29, sizeof lag);
    before = lag;
    if (sig_lag_init_q(&lag, alpha, frac) != SIG_OK) {
        REQUIRE(memcmp(&lag, &before, sizeof lag) == 0);
        REQUIRE(alpha < 1 || alpha > 65536 || frac > 16);
        return;
    }
    REQUIRE(sig_creep_init_q(&cr, alpha, frac, k) == SIG_OK);
    for (n = 0; n < STEPS && fuzz_left(in) > 0; n++) {
        int32_t x = (fuzz_u8(in) & 1u) ? fuzz_i32_edgy(in) : fuzz_i16(in), out, c, y;
        sig_status st = sig_lag_step_q(&lag, x, &out);
        REQUIRE(st == SIG_OK || st == SIG_WARN_SATURATED);
        saturated |= st != SIG_OK;
        if (x < lo) lo = x;
        if (x > hi) hi = x;
        if (!saturated) REQUIRE(out >= lo - 1 && out <= hi + 1);
        st = sig_creep_step_q(&cr, x, &c, &y);
        REQUIRE(st == SIG_OK || st == SIG_WARN_SATURATED);
        REQUIRE(y == sat32((int64_t)x - c));
        if (at_rail(y)) REQUIRE(st == SIG_WARN_SATURATED);
    }
    memset(&cr_before, 0, sizeof cr_before);
    (void)cr_before;
}

static void hyst_q(fuzz_input *in)
{
    int16_t width = fuzz_i16(in);
    int32_t k = fuzz_i32_edgy(in);
    int8_t start = (int8_t)fuzz_u8(in);
    sig_hyst_q h, before;
    int n;
    if (start & 0x40) start = (int8_t)(start % 2);
    memset(&h, 0x29, sizeof h);
    before = h;
    if (sig_hyst_init_q(&h, width, k, start) != SIG_OK) {
        REQUIRE(memcmp(&h, &before, sizeof h) == 0 && (width < 1 || start < -1 || start > 1));
        return;
    }
    for (n = 0; n < STEPS && fuzz_left(in) > 0; n++) {
        int16_t t = fuzz_i16(in), b = 0x7777;
        int32_t c;
        sig_status st = sig_hyst_step_q(&h, t, &b, &c);
        REQUIRE(st == SIG_OK || st == SIG_WARN_SATURATED);
        REQUIRE(b >= -width && b <= width);
        REQUIRE(c == sat32((int64_t)b * k));
        REQUIRE((st == SIG_WARN_SATURATED) == at_rail(c));
    }
}

static void poly_effects_q(fuzz_input *in)
{
    int32_t coef[SIG_POLY_MAX_ORDER + 1u], kq[3], center = fuzz_i32_edgy(in), knl = fuzz_i32_edgy(in);
    uint8_t order = fuzz_u8(in), shift = fuzz_u8(in), n_cross = fuzz_u8(in), k;
    sig_gain_q g;
    sig_nonlin_q m, m_before;
    sig_cross_q cx;
    int valid_order = order <= SIG_POLY_MAX_ORDER, nl_ok, cx_ok, n;
    if (order & 0x80u) order %= SIG_POLY_MAX_ORDER + 1u;
    valid_order = order <= SIG_POLY_MAX_ORDER;
    for (k = 0; k <= SIG_POLY_MAX_ORDER; k++) coef[k] = fuzz_i32_edgy(in);
    for (k = 0; k < 3; k++) kq[k] = fuzz_i32_edgy(in);
    REQUIRE((sig_gain_init_q(&g, coef, order) == SIG_OK) == valid_order);
    memset(&m, 0x29, sizeof m);
    m_before = m;
    nl_ok = sig_nonlin_init_q(&m, coef, order, center, knl, shift) == SIG_OK;
    REQUIRE(nl_ok == (valid_order && knl >= 1 && shift <= 30));
    if (!nl_ok) REQUIRE(memcmp(&m, &m_before, sizeof m) == 0);
    cx_ok = sig_cross_init_q(&cx, kq, n_cross) == SIG_OK;
    REQUIRE(cx_ok == (n_cross >= 1 && n_cross <= 3));
    for (n = 0; n < STEPS && fuzz_left(in) > 0; n++) {
        int32_t x = fuzz_i32_edgy(in), others[3], out, p;
        int16_t u = fuzz_i16(in);
        sig_status st, hs;
        others[0] = fuzz_i32_edgy(in); others[1] = fuzz_i32_edgy(in); others[2] = fuzz_i32_edgy(in);
        if (valid_order) {
            hs = sig_poly_horner_q15(coef, order, u, &p);
            st = sig_gain_apply_q(&g, u, x, &out);
            REQUIRE(out == sig_mul_q16_sat(x, p));
            REQUIRE(st == (sig_status)(hs | (at_rail(out) ? SIG_WARN_SATURATED : 0)));
        }
        if (nl_ok) {
            int32_t v = sig_asr32(sig_mul_q16_sat(sig_sat_sub32(x, center), knl), shift);
            int16_t ux = v > INT16_MAX ? INT16_MAX : v < -INT16_MAX ? (int16_t)-INT16_MAX : (int16_t)v;
            (void)sig_poly_horner_q15(coef, order, ux, &p);
            st = sig_nonlin_apply_q(&m, x, &out);
            REQUIRE(st >= 0 && out == sig_sat_add32(x, p));
            REQUIRE(((st & SIG_WARN_CLAMPED) != 0) == (v > INT16_MAX || v < -INT16_MAX));
            if (at_rail(out)) REQUIRE(st & SIG_WARN_SATURATED);
        }
        if (cx_ok) {
            int64_t exact = x;
            int32_t acc = 0;
            for (k = 0; k < n_cross; k++) {
                int32_t v = sig_mul_q16_sat(others[k], kq[k]);
                acc = sig_sat_add32(acc, v);
                exact -= v;
            }
            st = sig_cross_apply_q(&cx, x, others, &out);
            REQUIRE(out == sig_sat_sub32(x, acc));
            if (!(st & SIG_WARN_SATURATED)) REQUIRE(out == exact);
            if (at_rail(out)) REQUIRE(st & SIG_WARN_SATURATED);
        }
    }
}

static void float_effects(fuzz_input *in)
{
    sig_real alpha = fuzz_real(in), k = fuzz_real(in), width = fuzz_real(in);
    sig_real coef[SIG_POLY_MAX_ORDER + 1u], kx[3];
    uint8_t order = (uint8_t)(fuzz_u8(in) % (SIG_POLY_MAX_ORDER + 1u)), kk;
    sig_lag_f lag, lag_before;
    sig_hyst_f h, h_before;
    sig_creep_f cr;
    sig_gain_f g;
    sig_nonlin_f m;
    sig_cross_f cx;
    int lag_ok, h_ok, cr_ok, g_ok, m_ok, cx_ok, n, params_moderate;
    if (fuzz_u8(in) & 1u) { alpha = (sig_real)(1 + fuzz_u16(in)) / 65536; width = (sig_real)(1 + fuzz_u8(in)) / 10; }
    for (kk = 0; kk <= SIG_POLY_MAX_ORDER; kk++) coef[kk] = fuzz_real(in);
    for (kk = 0; kk < 3; kk++) kx[kk] = fuzz_real(in);
    params_moderate = moderate(k) && moderate(width);
    for (kk = 0; kk <= SIG_POLY_MAX_ORDER; kk++) params_moderate &= moderate(coef[kk]);
    for (kk = 0; kk < 3; kk++) params_moderate &= moderate(kx[kk]);
    memset(&lag, 0x29, sizeof lag);
    lag_before = lag;
    lag_ok = sig_lag_init_f(&lag, alpha) == SIG_OK;
    REQUIRE(lag_ok == (sig_real_isfinite(alpha) && alpha > 0 && alpha <= 1));
    if (!lag_ok) REQUIRE(memcmp(&lag, &lag_before, sizeof lag) == 0);
    memset(&h, 0x29, sizeof h);
    h_before = h;
    h_ok = sig_hyst_init_f(&h, width, k, 0) == SIG_OK;
    if (!h_ok) REQUIRE(memcmp(&h, &h_before, sizeof h) == 0);
    cr_ok = sig_creep_init_f(&cr, alpha, k) == SIG_OK;
    g_ok = sig_gain_init_f(&g, coef, order) == SIG_OK;
    m_ok = sig_nonlin_init_f(&m, coef, order, k, width) == SIG_OK;
    cx_ok = sig_cross_init_f(&cx, kx, 3) == SIG_OK;
    for (n = 0; n < STEPS && fuzz_left(in) > 0; n++) {
        sig_real x = fuzz_real(in), u = fuzz_real(in), o[3], out = 0, b = 0, c = 0, y = 0;
        int fin = sig_real_isfinite(x), small;
        sig_status st;
        o[0] = fuzz_real(in); o[1] = fuzz_real(in); o[2] = fuzz_real(in);
        small = params_moderate && moderate(x) && moderate(u) && moderate(o[0]) && moderate(o[1])
                && moderate(o[2]);
        if (lag_ok) {
            lag_before = lag;
            st = sig_lag_step_f(&lag, x, &out);
            if (!fin) REQUIRE(st == SIG_ERR_NONFINITE && memcmp(&lag, &lag_before, sizeof lag) == 0);
            else REQUIRE(st == SIG_OK && lag.z == lag.z && out == out);
        }
        if (h_ok) {
            h_before = h;
            st = sig_hyst_step_f(&h, x, &b, &c);
            if (!fin) REQUIRE(st == SIG_ERR_NONFINITE && memcmp(&h, &h_before, sizeof h) == 0);
            else REQUIRE(st == SIG_OK && h.p == h.p && (!small || (b == b && c == c)));
        }
        if (cr_ok) {
            st = sig_creep_step_f(&cr, x, &c, &y);
            if (!fin) REQUIRE(st == SIG_ERR_NONFINITE);
            else REQUIRE(st == SIG_OK && cr.lag.z == cr.lag.z && (!small || (c == c && y == y)));
        }
        if (g_ok) {
            out = (sig_real)7;
            st = sig_gain_apply_f(&g, u, x, &out);
            if (st < 0) REQUIRE(st == SIG_ERR_NONFINITE && out == (sig_real)7);
            else REQUIRE(!small || out == out);
        }
        if (m_ok) {
            out = (sig_real)7;
            st = sig_nonlin_apply_f(&m, x, &out);
            if (st < 0) REQUIRE(st == SIG_ERR_NONFINITE && out == (sig_real)7);
            else REQUIRE(!small || out == out);
        }
        if (cx_ok) {
            out = (sig_real)7;
            st = sig_cross_apply_f(&cx, x, o, &out);
            if (st < 0) REQUIRE(st == SIG_ERR_NONFINITE && out == (sig_real)7);
            else REQUIRE(!small || out == out);
        }
    }
}

static void refined_q(fuzz_input *in)
{
    uint8_t n_axes = (uint8_t)(1u + fuzz_u8(in) % 3u), order = (uint8_t)(1u + fuzz_u8(in) % 8u);
    uint8_t u_shift = (uint8_t)(fuzz_u8(in) % 16u), flags = fuzz_u8(in), axis = fuzz_u8(in), q[3];
    int16_t t_lo = fuzz_i16(in), t_hi = fuzz_i16(in), t_c, u_mul;
    int32_t coef[27], half, gcoef[SIG_POLY_MAX_ORDER + 1u];
    int64_t um;
    sig_tcomp_q m;
    sig_lag_q lag;
    sig_hyst_q hyst;
    sig_gain_q gain;
    sig_refined_q r, before;
    sig_status st;
    unsigned k;
    int n;
    if (t_lo > t_hi) { int16_t x = t_lo; t_lo = t_hi; t_hi = x; }
    if (t_lo == t_hi) t_hi = (int16_t)(t_lo == INT16_MAX ? t_lo : t_lo + 1), t_lo = (int16_t)(t_hi - 1);
    t_c = (int16_t)(((int32_t)t_lo + t_hi) / 2);
    half = (int32_t)t_hi - t_c > t_c - (int32_t)t_lo ? (int32_t)t_hi - t_c : t_c - (int32_t)t_lo;
    if (half > 32767) return;
    um = (((int64_t)32767 << u_shift) - ((int64_t)1 << u_shift >> 1)) / half;
    u_mul = (int16_t)(um > 32767 ? 32767 : um < 1 ? 1 : um);
    for (k = 0; k < 27u; k++)
        coef[k] = (flags & 1u) ? fuzz_i32_edgy(in) : (int32_t)fuzz_i16(in) * (INT32_C(1) << (fuzz_u8(in) % 15u));
    for (k = 0; k < 3u; k++) q[k] = (uint8_t)(fuzz_u8(in) % 31u);
    if (sig_tcomp_init_q(&m, n_axes, order, coef, q, t_lo, t_hi, t_c, t_c, u_mul, u_shift) != SIG_OK) return;
    REQUIRE(sig_lag_init_q(&lag, 1 + (int32_t)(fuzz_u16(in)), (flags & 16u) ? (uint8_t)(fuzz_u8(in) % 17u) : 16u)
            == SIG_OK);
    REQUIRE(sig_hyst_init_q(&hyst, (int16_t)(1 + fuzz_u16(in) % 32767u), fuzz_i32_edgy(in),
                            (int8_t)((int)(fuzz_u8(in) % 3u) - 1)) == SIG_OK);
    for (k = 0; k <= SIG_POLY_MAX_ORDER; k++) gcoef[k] = (k == 0) ? 65536 + fuzz_i16(in) : fuzz_i16(in);
    REQUIRE(sig_gain_init_q(&gain, gcoef, (uint8_t)(fuzz_u8(in) % 9u)) == SIG_OK);
    memset(&r, 0x29, sizeof r);
    before = r;
    st = sig_refined_init_q(&r, &m, axis, (flags & 2u) ? &lag : NULL, (flags & 4u) ? &hyst : NULL,
                            (flags & 8u) ? &gain : NULL);
    if (axis >= n_axes || ((flags & 2u) && lag.frac != 16u)) {
        REQUIRE(st == SIG_ERR_ARG && memcmp(&r, &before, sizeof r) == 0);
        return;
    }
    REQUIRE(st == SIG_OK);
    for (n = 0; n < STEPS && fuzz_left(in) > 0; n++) {
        int16_t t = fuzz_i16(in), y = fuzz_i16(in);
        int32_t out = 0, delta, d16;
        st = sig_refined_step_q(&r, t, y, &out);
        REQUIRE(st >= 0 && (st & ~(SIG_WARN_CLAMPED | SIG_WARN_SATURATED)) == 0);
        if (!(flags & 14u)) {
            (void)sig_tcomp_delta_q(&m, axis, t, &delta);
            if (m.q[axis] >= 16u) {
                uint8_t sh = (uint8_t)(m.q[axis] - 16u);
                d16 = sh ? sig_asr32(sig_sat_add32(delta, INT32_C(1) << (sh - 1u)), sh) : delta;
            } else {
                d16 = sig_shl32_sat(delta, (uint8_t)(16u - m.q[axis]));
            }
            REQUIRE(out == sig_sat_sub32((int32_t)y * SIG_Q16_ONE, d16));
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_make(data, size);
    switch (fuzz_u8(&in) % 5u) {
    case 0: lag_and_creep_q(&in); break;
    case 1: hyst_q(&in); break;
    case 2: poly_effects_q(&in); break;
    case 3: float_effects(&in); break;
    default: refined_q(&in);
    }
    return 0;
}
