/* sig_learn.c - the learner's per-sample path: bin sums of still samples,
 * the noise estimate and the CUSUM staleness test (sig_learn.h).  No
 * division, no multiply: the CUSUM thresholds come from sig_learn_solve. */
#include "sig_learn.h"

sig_status sig_learn_init(sig_learn *s, const sig_learn_config *cfg)
{
    int32_t top;
    uint8_t a;
    if (s == NULL || cfg == NULL) return SIG_ERR_ARG;
    if (cfg->n_axes < 1u || cfg->n_axes > SIG_LEARN_MAX_AXES) return SIG_ERR_ARG;
    if (cfg->n_bins < SIG_LEARN_MIN_BINS || cfg->n_bins > SIG_LEARN_MAX_BINS) return SIG_ERR_ARG;
    if (cfg->min_bins < SIG_LEARN_MIN_BINS || cfg->min_bins > cfg->n_bins) return SIG_ERR_ARG;
    if (cfg->bin_shift < 1u || cfg->bin_shift > SIG_LEARN_MAX_SHIFT) return SIG_ERR_ARG;
    if (cfg->min_count < 1u || cfg->min_count > SIG_LEARN_COUNT_MAX) return SIG_ERR_ARG;
    if (cfg->margin_shift < 1u || cfg->margin_shift > 8u) return SIG_ERR_ARG;
    if (cfg->sigma_floor < 1u || cfg->h_sigma < 16u || cfg->period < 1u) return SIG_ERR_ARG;
    if (cfg->code_kind > SIG_TCODE_UINT16) return SIG_ERR_ARG;
    top = (int32_t)cfg->t_base + ((int32_t)cfg->n_bins << cfg->bin_shift);
    if (top > INT16_MAX) return SIG_ERR_ARG;
    s->cfg = *cfg;
    s->grid_span = (uint16_t)((uint16_t)cfg->n_bins << cfg->bin_shift);
    s->bin_mask = (uint16_t)((1u << cfg->bin_shift) - 1u);
    for (a = 0u; a < SIG_LEARN_MAX_AXES; a++) {
        s->k[a] = 0;
        s->h[a] = 0;
        s->noise[a] = 0;
        s->prev_r[a] = 0;
    }
    s->steps = 0u;
    s->last_commit = 0u;
    s->noise_n = 0u;
    s->model_lo = 0;
    s->model_hi = 0;
    s->has_model = false;
    s->committed = false;
    s->have_prev = false;
    sig_learn_reset(s);
    return SIG_OK;
}

void sig_learn_reset(sig_learn *s)
{
    uint8_t b, a;
    if (s == NULL) return;
    for (b = 0u; b < SIG_LEARN_MAX_BINS; b++) {
        s->count[b] = 0u;
        s->sum_dt[b] = 0u;
        for (a = 0u; a < SIG_LEARN_MAX_AXES; a++) s->sum_y[b][a] = 0u;
    }
    for (a = 0u; a < SIG_LEARN_MAX_AXES; a++) {
        s->cusum_pos[a] = 0;
        s->cusum_neg[a] = 0;
    }
    s->stale = false;
}

sig_status sig_learn_use_model(sig_learn *s, const sig_tmodel *m)
{
    int16_t lo, hi;
    uint8_t a;
    if (s == NULL) return SIG_ERR_ARG;
    if (m != NULL) {
        if (m->n_axes != s->cfg.n_axes) return SIG_ERR_ARG;
        if (m->family == SIG_TMODEL_POLY) {
            lo = m->m.poly.t_lo;
            hi = m->m.poly.t_hi;
        } else if (m->family == SIG_TMODEL_COMPACT) {
            lo = m->m.compact.t_lo;
            hi = m->m.compact.t_hi;
        } else if (m->family == SIG_TMODEL_TABLE) {
            lo = m->m.table[0].t_lo;
            hi = m->m.table[0].t_hi;
        } else {
            return SIG_ERR_ARG;
        }
        s->model_lo = lo;
        s->model_hi = hi;
    }
    s->has_model = m != NULL;
    for (a = 0u; a < SIG_LEARN_MAX_AXES; a++) {
        s->cusum_pos[a] = 0;
        s->cusum_neg[a] = 0;
    }
    s->stale = false;
    s->have_prev = false;   /* residuals of two models are not one series */
    return SIG_OK;
}

/* Add a still sample to its bin; SIG_LEARN_SKIPPED when it has none.
 * 16-bit index arithmetic: the grid spans at most 16 * 2^10 units. */
static sig_status learn_sample(sig_learn *s, int16_t t, const int16_t *raw)
{
    uint32_t *sum_y;
    uint16_t d16;
    uint8_t a, b, n = s->cfg.n_axes;
    /* 16-bit arithmetic only (the MSP430 widens a signed int16 to 32 bits
     * with a 7-step shift): t >= t_base, so t - t_base is 0..65535 */
    if (t < s->cfg.t_base) return SIG_LEARN_SKIPPED;
    d16 = (uint16_t)((uint16_t)t - (uint16_t)s->cfg.t_base);
    if (d16 >= s->grid_span) return SIG_LEARN_SKIPPED;
    for (a = 0u; a < n; a++)
        if (raw[a] > SIG_LEARN_Y_MAX || raw[a] < -SIG_LEARN_Y_MAX) return SIG_LEARN_SKIPPED;
    b = (uint8_t)(d16 >> s->cfg.bin_shift);
    s->sum_dt[b] += (uint32_t)(d16 & s->bin_mask);
    sum_y = s->sum_y[b];
    for (a = 0u; a < n; a++) sum_y[a] += (uint16_t)(raw[a] + SIG_LEARN_Y_BIAS);
    if (++s->count[b] >= SIG_LEARN_COUNT_MAX) {
        /* halve: the sums keep their width and old samples fade */
        s->count[b] = (uint16_t)(SIG_LEARN_COUNT_MAX / 2u);
        s->sum_dt[b] >>= 1;
        for (a = 0u; a < n; a++) sum_y[a] >>= 1;
    }
    return SIG_OK;
}

static int16_t clamp_y(int16_t r)
{
    if (r > SIG_LEARN_Y_MAX) return SIG_LEARN_Y_MAX;
    if (r < -SIG_LEARN_Y_MAX) return -SIG_LEARN_Y_MAX;
    return r;
}

/* Noise estimate from successive still residuals (r: resid, or raw when no
 * model is in use), then the CUSUM when the model is in range and armed.
 * true when the CUSUM crossed its threshold. */
static bool watch_residual(sig_learn *s, const int16_t *r, bool in_range)
{
    uint8_t a, n = s->cfg.n_axes;
    int16_t x, d;
    int32_t pos, neg;
    bool crossed = false;
    for (a = 0u; a < n; a++) {
        x = clamp_y(r[a]);
        if (s->have_prev) {
            d = (int16_t)(x - s->prev_r[a]);          /* |d| <= 4094 */
            if (d < 0) d = (int16_t)-d;
            if (d > SIG_LEARN_Y_MAX) d = SIG_LEARN_Y_MAX;
            s->noise[a] = (uint16_t)(s->noise[a] + (uint16_t)d - (uint16_t)(s->noise[a] >> 5));
        }
        s->prev_r[a] = x;
        if (!s->has_model || !in_range || s->h[a] == 0) continue;
        x = (int16_t)(x * 16);                       /* |16 x| <= 32752 */
        pos = s->cusum_pos[a] + x - s->k[a];
        neg = s->cusum_neg[a] - x - s->k[a];
        s->cusum_pos[a] = pos > 0 ? pos : 0;
        s->cusum_neg[a] = neg > 0 ? neg : 0;
        if (pos > s->h[a] || neg > s->h[a]) crossed = true;
    }
    if (s->have_prev && s->noise_n < UINT16_MAX) s->noise_n++;
    s->have_prev = true;
    return crossed;
}

sig_status sig_learn_step(sig_learn *s, int16_t t, const int16_t *raw, const int16_t *resid, bool still)
{
    sig_status st = SIG_OK;
    bool in_range = true;
    if (s == NULL || raw == NULL || (s->has_model && resid == NULL)) return SIG_ERR_ARG;
    s->steps++;
    if (s->has_model && (t < s->model_lo || t > s->model_hi)) {
        in_range = false;
        st |= SIG_LEARN_EXTRAPOLATED;
    }
    if (still) {
        st |= learn_sample(s, t, raw);
        if (!s->stale && watch_residual(s, s->has_model ? resid : raw, in_range)) {
            sig_learn_reset(s);
            s->stale = true;
        }
    } else {
        s->have_prev = false;
    }
    if (s->stale) st |= SIG_LEARN_STALE;
    return st;
}
