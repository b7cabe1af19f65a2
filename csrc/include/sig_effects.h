/* sig_effects.h - on-device forms of the effects pysig.refine can add to a
 * calibration model: the firmware applies what refine found.
 *
 *   thermal_lag   first-order IIR on the temperature (sig_lag_*): the
 *                 lagged temperature then feeds the offset polynomial
 *                 (sig_tcomp) and the gain polynomial.
 *   creep         the same IIR on the reading, and a coefficient
 *                 (sig_creep_*): contribution = k * (lag(x) - x).
 *   hysteresis    play-operator branch state on the temperature
 *                 (sig_hyst_*): contribution = k * (t - p).
 *   gain_drift    gain polynomial G(u) in the scaled temperature
 *                 (sig_gain_*): out = x * G(u).
 *   nonlinearity  polynomial in the scaled reading (sig_nonlin_*):
 *                 out = x + P(u_x).
 *   cross_axis    other axes' leak (sig_cross_*): out = x - sum k_j o_j.
 *
 * Units: every reading-like value (x, contributions, outputs) is an int32 in
 * one caller-chosen fixed unit (LSB, counts, or Q16.16 LSB: whatever the
 * exporter picked, see pysig/refine/_device.py); coefficients carry that
 * unit.  Temperatures are int16 0.01 °C as in sig_tcomp.h.
 *
 * Fixed-point arithmetic: 32-bit only (no int64), every product through
 * sig_mul_q16_sat (floor(a*b/2^16), saturated) or sig_poly_horner_q15,
 * every sum through sig_sat_add32/sig_sat_sub32, every right shift through
 * sig_asr32 (floor).  A status bit SIG_WARN_SATURATED reports a rail hit.
 * Rounding to a coarser unit is round-half-up: floor((v + 2^(n-1)) / 2^n).
 *
 * Float forms (_f) run the same recurrences in sig_real; they are the
 * forms pysig.refine._effect_models fits with (tolerance, not bits).
 * State lives in caller-owned structs: _init checks and stores parameters
 * (state untouched on error), _reset forgets the history (the next sample
 * primes the state), _step advances one sample.  No malloc, no recursion.
 */
#ifndef SIG_EFFECTS_H
#define SIG_EFFECTS_H

#include "sig_types.h"
#include "sig_poly.h"
#include "sig_tcomp.h"

#define SIG_LAG_MAX_FRAC 16u
#define SIG_CROSS_MAX_AXES 3u

/* ---- first-order lag: thermal lag, creep state -----------------------------
 * z[0] = x[0];  z[k] = z[k-1] + alpha * (x[k] - z[k-1]),  alpha = 1 - exp(-dt/tau)
 * (the float form computes it as (1 - alpha) z + alpha x, which cannot overflow).
 * Fixed: x int32, state z = x in Q(frac) (frac 0..16 extra fraction bits;
 *        16 for int16 temperatures, about 7 for 24-bit ADC counts);
 *        xs = sat(x * 2^frac); z += floor((xs - z) * alpha_q16 / 2^16), saturating;
 *        alpha_q16 = round(alpha * 2^16) in 1..65536 (65536: no lag).
 *        out = floor((z + 2^(frac-1)) / 2^frac)  (the lagged x, input unit). */
typedef struct {
    int32_t z;          /* Q(frac) of the input unit */
    int32_t alpha_q16;  /* 1..65536 */
    uint8_t frac;       /* 0..16 */
    bool primed;        /* false until the first sample */
} sig_lag_q;

typedef struct {
    sig_real z;
    sig_real alpha;     /* (0, 1] */
    bool primed;
} sig_lag_f;

sig_status sig_lag_init_q(sig_lag_q *s, int32_t alpha_q16, uint8_t frac);
sig_status sig_lag_reset_q(sig_lag_q *s);
/* SIG_WARN_SATURATED when x * 2^frac or the state hit a rail. */
sig_status sig_lag_step_q(sig_lag_q *s, int32_t x, int32_t *out);

sig_status sig_lag_init_f(sig_lag_f *s, sig_real alpha);
sig_status sig_lag_reset_f(sig_lag_f *s);
/* SIG_ERR_NONFINITE (state untouched) for a NaN/inf x. */
sig_status sig_lag_step_f(sig_lag_f *s, sig_real x, sig_real *out);

/* ---- hysteresis: play operator on the temperature ---------------------------
 * p before the first sample is t[0] - start * width (start: +1 the last
 * move was heating, -1 cooling, 0 unknown); then p follows t only when
 * |t - p| would exceed width:
 *   t - p >  width  ->  p = t - width;   p - t > width  ->  p = t + width.
 * branch b = t - p in [-width, width]: +width heating, -width cooling.
 * contribution = b * k  (k in reading unit per 0.01 °C, Q16: k_q16)
 *              = sig_mul_q16_sat(b * 2^16, k_q16), exact unless saturated. */
typedef struct {
    int32_t p;          /* 0.01 °C */
    int32_t k_q16;
    int16_t width;      /* 1..32767, 0.01 °C */
    int8_t start;       /* -1, 0, +1: branch before the first sample */
    bool primed;
} sig_hyst_q;

typedef struct {
    sig_real p, width, k;
    int8_t start;
    bool primed;
} sig_hyst_f;

sig_status sig_hyst_init_q(sig_hyst_q *s, int16_t width, int32_t k_q16, int8_t start);
sig_status sig_hyst_reset_q(sig_hyst_q *s);
sig_status sig_hyst_step_q(sig_hyst_q *s, int16_t t, int16_t *branch, int32_t *contribution);

sig_status sig_hyst_init_f(sig_hyst_f *s, sig_real width, sig_real k, int8_t start);
sig_status sig_hyst_reset_f(sig_hyst_f *s);
sig_status sig_hyst_step_f(sig_hyst_f *s, sig_real t, sig_real *branch, sig_real *contribution);

/* ---- creep: lag on the reading and a coefficient ----------------------------
 * contribution = k * (lag(x) - x): in Q(frac) d = z - xs, then
 * floor((sig_mul_q16_sat(d, k_q16) + 2^(frac-1)) / 2^frac), input unit.
 * The corrected reading is x - contribution (sig_creep_step_q returns both). */
typedef struct {
    sig_lag_q lag;
    int32_t k_q16;
} sig_creep_q;

typedef struct {
    sig_lag_f lag;
    sig_real k;
} sig_creep_f;

sig_status sig_creep_init_q(sig_creep_q *s, int32_t alpha_q16, uint8_t frac, int32_t k_q16);
sig_status sig_creep_reset_q(sig_creep_q *s);
sig_status sig_creep_step_q(sig_creep_q *s, int32_t x, int32_t *contribution, int32_t *corrected);

sig_status sig_creep_init_f(sig_creep_f *s, sig_real alpha, sig_real k);
sig_status sig_creep_reset_f(sig_creep_f *s);
sig_status sig_creep_step_f(sig_creep_f *s, sig_real x, sig_real *contribution, sig_real *corrected);

/* ---- gain drift: G(u) by Horner, out = x * G(u) -----------------------------
 * u Q0.15 the scaled temperature (sig_tcomp_scale_q of the lagged t when
 * thermal_lag is on); coef Q16.16 (1.0 = 65536), ascending powers of u;
 * out = sig_mul_q16_sat(x, G). */
typedef struct {
    int32_t coef[SIG_POLY_MAX_ORDER + 1u];
    uint8_t order;
} sig_gain_q;

typedef struct {
    sig_real coef[SIG_POLY_MAX_ORDER + 1u];
    uint8_t order;
} sig_gain_f;

sig_status sig_gain_init_q(sig_gain_q *g, const int32_t *coef, uint8_t order);
sig_status sig_gain_apply_q(const sig_gain_q *g, int16_t u_q15, int32_t x, int32_t *out);
sig_status sig_gain_init_f(sig_gain_f *g, const sig_real *coef, uint8_t order);
sig_status sig_gain_apply_f(const sig_gain_f *g, sig_real u, sig_real x, sig_real *out);

/* ---- nonlinearity: out = x + P(u_x) -----------------------------------------
 * u_x = sat16(floor(sig_mul_q16_sat(sat(x - center), k_q16) / 2^shift))  Q0.15
 * P by sig_poly_horner_q15, coef in the reading unit; out = sat(x + P). */
typedef struct {
    int32_t coef[SIG_POLY_MAX_ORDER + 1u];
    int32_t center;
    int32_t k_q16;      /* > 0 */
    uint8_t shift;      /* 0..30 */
    uint8_t order;
} sig_nonlin_q;

typedef struct {
    sig_real coef[SIG_POLY_MAX_ORDER + 1u];
    sig_real center, inv_scale;
    uint8_t order;
} sig_nonlin_f;

sig_status sig_nonlin_init_q(sig_nonlin_q *m, const int32_t *coef, uint8_t order,
                             int32_t center, int32_t k_q16, uint8_t shift);
sig_status sig_nonlin_apply_q(const sig_nonlin_q *m, int32_t x, int32_t *out);
sig_status sig_nonlin_init_f(sig_nonlin_f *m, const sig_real *coef, uint8_t order,
                             sig_real center, sig_real inv_scale);
sig_status sig_nonlin_apply_f(const sig_nonlin_f *m, sig_real x, sig_real *out);

/* ---- cross-axis: out = x - sum_j k_j * o_j ----------------------------------
 * o_j other axes' readings in the same unit; each product sig_mul_q16_sat. */
typedef struct {
    int32_t k_q16[SIG_CROSS_MAX_AXES];
    uint8_t n;          /* 1..3 */
} sig_cross_q;

typedef struct {
    sig_real k[SIG_CROSS_MAX_AXES];
    uint8_t n;
} sig_cross_f;

sig_status sig_cross_init_q(sig_cross_q *c, const int32_t *k_q16, uint8_t n);
sig_status sig_cross_apply_q(const sig_cross_q *c, int32_t x, const int32_t *others, int32_t *out);
sig_status sig_cross_init_f(sig_cross_f *c, const sig_real *k, uint8_t n);
sig_status sig_cross_apply_f(const sig_cross_f *c, sig_real x, const sig_real *others, sig_real *out);

/* ---- the refined temperature model of one axis --------------------------------
 * What the firmware runs for a model refine extended (constant-field or
 * reference calibration of an int16 sensor):
 *   t'    = lag(t)               when a lag is configured (frac 16), else t
 *   delta = sig_tcomp_delta_q(tcomp, axis, t')   Q(q) LSB, clamped range
 *   acc   = y * 2^16 - delta in Q16.16 (delta rescaled: round_shift(delta,
 *           q - 16) for q >= 16, sig_shl32_sat(delta, 16 - q) below)
 *   acc  -= hysteresis contribution at t' (k_q16: Q16.16 LSB per 0.01 °C)
 *   acc   = acc * G(u(t'))       when a gain polynomial is configured
 * out = acc, the corrected reading in Q16.16 LSB.  Status: OR of the parts'
 * warnings (SIG_WARN_CLAMPED from the offset range, SIG_WARN_SATURATED). */
typedef struct {
    const sig_tcomp_q *tcomp;   /* caller-owned offset model */
    sig_lag_q lag;
    sig_hyst_q hyst;
    sig_gain_q gain;
    uint8_t axis;
    bool use_lag, use_hyst, use_gain;
} sig_refined_q;

/* lag, hyst, gain may be NULL (effect absent); they are copied (the lag
 * must use frac 16).  SIG_ERR_ARG for a NULL r/tcomp, axis >= n_axes or a
 * lag with another frac. */
sig_status sig_refined_init_q(sig_refined_q *r, const sig_tcomp_q *tcomp, uint8_t axis,
                              const sig_lag_q *lag, const sig_hyst_q *hyst, const sig_gain_q *gain);
sig_status sig_refined_reset_q(sig_refined_q *r);
sig_status sig_refined_step_q(sig_refined_q *r, int16_t t, int16_t y, int32_t *out_q16);

#endif /* SIG_EFFECTS_H */
