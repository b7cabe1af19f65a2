/* sig_learn.c - the learner's per-sample path: bin sums of still samples,
 * the noise estimate and the CUSUM staleness test (sig_learn.h).  No
 * division: the CUSUM thresholds come from sig_learn_solve; the noise
 * estimate and the CUSUM run once per block of 8 still samples (a clamp and
 * an add per sample in between). */
#include "sig_learn.h"

static void break_series(sig_learn *s);

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
    for (a = 0u; a < 4u; a++) s->bin_w[a] = (uint16_t)((s->bin_mask + 1u) << (3u - a));
    for (a = 0u; a < SIG_LEARN_MAX_AXES; a++) {
        s->k[a] = 0;
        s->h[a] = 0;
        s->noise[a] = 0;
        s->prev_r[a] = 0;
        s->block_sum[a] = 0;
    }
    s->steps = 0u;
    s->last_commit = 0u;
    s->noise_n = 0u;
    s->model_lo = 0;
    s->model_hi = 0;
    s->has_model = false;
    s->committed = false;
    s->have_prev = false;
    s->block_n = 0u;
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
        for (a = 0u; a < SIG_LEARN_MAX_AXES; a++) s->sum_y[a][b] = 0u;
    }
    for (a = 0u; a < SIG_LEARN_MAX_AXES; a++) {
        s->cusum_pos[a] = 0;
        s->cusum_neg[a] = 0;
        s->acc_y[a] = 0u;
    }
    s->acc_dt = 0u;
    s->acc_n = 0u;
    s->acc_bin = 0u;
    s->acc_lo = 0u;
    s->acc_room = (uint8_t)SIG_LEARN_ACC_MAX;
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
    break_series(s);        /* residuals of two models are not one series */
    return SIG_OK;
}

/* Move the pending samples of one bin into its 32-bit sums. */
void sig_learn_flush(sig_learn *s)
{
    uint8_t a, b = s->acc_bin, n = s->cfg.n_axes;
    /* the new count in a local, tested there: sdcc 4.2 (mcs51) reloaded
     * s->count[b] for the test with its two bytes swapped through
     * "mov ar6,r7; mov ar7,r6" (both then the low byte), so a bin of 8 or
     * more samples compared as >= 2048 and was halved at every flush */
    uint16_t c = (uint16_t)(s->count[b] + s->acc_n);
    if (s->acc_n == 0u) return;
    s->sum_dt[b] += s->acc_dt;
    for (a = 0u; a < n; a++) {
        s->sum_y[a][b] += s->acc_y[a];
        s->acc_y[a] = 0u;
    }
    s->acc_dt = 0u;
    s->acc_n = 0u;
    if (c >= SIG_LEARN_COUNT_MAX) {
        /* halve: the sums keep their width and old samples fade */
        c >>= 1;
        s->sum_dt[b] >>= 1;
        for (a = 0u; a < n; a++) s->sum_y[a][b] >>= 1;
    }
    s->count[b] = c;
}

/* Add a still sample to the pending sums of its bin; SIG_LEARN_SKIPPED when
 * it has none.  16-bit arithmetic only (the MSP430 widens a signed int16 to
 * 32 bits with a 7-step shift): the grid spans at most 16 * 2^10 units.  The
 * axes are written out (no loop): the loop's control costs the MSP430 as much
 * as the adds; the pending sums of absent axes get 0 and stay 0. */
static sig_status learn_sample(sig_learn *s, int16_t t, const int16_t *raw)
{
    uint16_t y0, y1 = 0u, y2 = 0u;
    uint16_t d16, d0, dt;
    uint8_t a, b, n = s->cfg.n_axes;
    if (t < s->cfg.t_base) return SIG_LEARN_SKIPPED;
    d16 = (uint16_t)((uint16_t)t - (uint16_t)s->cfg.t_base);     /* t >= t_base: 0..65535 */
    if (d16 >= s->grid_span) return SIG_LEARN_SKIPPED;
    /* |raw| <= 2047 as one unsigned compare of raw + 2047 <= 4094 (wraps above otherwise) */
    y0 = (uint16_t)((uint16_t)raw[0] + (uint16_t)SIG_LEARN_Y_BIAS);
    if (y0 > 2u * (uint16_t)SIG_LEARN_Y_MAX) return SIG_LEARN_SKIPPED;
    if (n > 1u) {
        y1 = (uint16_t)((uint16_t)raw[1] + (uint16_t)SIG_LEARN_Y_BIAS);
        if (y1 > 2u * (uint16_t)SIG_LEARN_Y_MAX) return SIG_LEARN_SKIPPED;
        if (n > 2u) {
            y2 = (uint16_t)((uint16_t)raw[2] + (uint16_t)SIG_LEARN_Y_BIAS);
            if (y2 > 2u * (uint16_t)SIG_LEARN_Y_MAX) return SIG_LEARN_SKIPPED;
        }
    }
    dt = (uint16_t)(d16 - s->acc_lo);           /* wraps high below the pending bin */
    if (s->acc_n == 0u || dt >= s->bin_w[3]) {
        sig_learn_flush(s);
        d0 = d16;
        /* d16 < 16 W: four compares give the bin and leave dt in d16 */
        b = 0u;
        for (a = 0u; a < 4u; a++) {
            b = (uint8_t)(b + b);
            if (d16 >= s->bin_w[a]) {
                d16 = (uint16_t)(d16 - s->bin_w[a]);
                b |= 1u;
            }
        }
        dt = d16;
        s->acc_bin = b;
        s->acc_lo = (uint16_t)(d0 - d16);
        /* stop the pending sums where the bin reaches COUNT_MAX: it is then
         * halved at exactly 2048 samples (even), so the solve's bias
         * 2047 * count stays exact; an odd count would leave half a bias
         * (~1 LSB of mean) in the halved sums */
        s->acc_room = (uint8_t)(SIG_LEARN_COUNT_MAX - s->count[b] < SIG_LEARN_ACC_MAX
                                ? SIG_LEARN_COUNT_MAX - s->count[b] : SIG_LEARN_ACC_MAX);
    }
    s->acc_dt = (uint16_t)(s->acc_dt + dt);
    s->acc_y[0] = (uint16_t)(s->acc_y[0] + y0);
    s->acc_y[1] = (uint16_t)(s->acc_y[1] + y1);
    s->acc_y[2] = (uint16_t)(s->acc_y[2] + y2);
    if (++s->acc_n >= s->acc_room) sig_learn_flush(s);
    return SIG_OK;
}

static int16_t clamp16(int16_t r, int16_t lim)
{
    if (r > lim) return lim;
    if (r < -lim) return (int16_t)-lim;
    return r;
}

/* The residual series is broken (a still sample beyond the model's range,
 * another model): the partial block is dropped and the next
 * block starts a new pair. */
static void break_series(sig_learn *s)
{
    uint8_t a;
    for (a = 0u; a < SIG_LEARN_MAX_AXES; a++) s->block_sum[a] = 0;
    s->block_n = 0u;
    s->have_prev = false;
}

/* A full block: the noise estimate from successive block sums, then the
 * CUSUM on the block sum (sig_learn.h: CUSUM); true when it crossed.  Once
 * per 8 still samples, so the per-sample path is a clamp and an add. */
static bool watch_block(sig_learn *s)
{
    uint8_t a, n = s->cfg.n_axes;
    int16_t x, p, x2, pos, neg;
    uint16_t d;
    bool crossed = false;
    /* refresh_thresholds arms every axis at once, each with h >= 1 */
    bool armed = s->has_model && s->h[0] != 0;
    for (a = 0u; a < n; a++) {
        x = s->block_sum[a];
        s->block_sum[a] = 0;
        if (s->have_prev) {
            p = s->prev_r[a];
            d = x >= p ? (uint16_t)(x - p) : (uint16_t)(p - x);    /* <= 8176 */
            if (d > (uint16_t)SIG_LEARN_Y_MAX) d = (uint16_t)SIG_LEARN_Y_MAX;
            s->noise[a] = (uint16_t)(s->noise[a] + d - (uint16_t)(s->noise[a] >> 5));
        }
        s->prev_r[a] = x;
        if (armed) {
            /* Q1, an eighth of the Q4 sums (sig_learn.h: CUSUM): int16 */
            x2 = (int16_t)(x + x);                               /* |x2| <= 8176 */
            pos = (int16_t)(s->cusum_pos[a] + x2 - s->k[a]);
            neg = (int16_t)(s->cusum_neg[a] - x2 - s->k[a]);
            s->cusum_pos[a] = pos > 0 ? pos : 0;
            s->cusum_neg[a] = neg > 0 ? neg : 0;
            if (pos > (s->h[a] >> 3) || neg > (s->h[a] >> 3)) crossed = true;
        }
    }
    if (s->have_prev && s->noise_n < UINT16_MAX) s->noise_n++;
    s->have_prev = true;
    return crossed;
}

/* A still residual (r: resid, or raw when no model is in use) into the
 * block sums, clamped to +-SIG_LEARN_CUSUM_X_MAX (|sum| <= 8 * 511); the
 * axes written out (no loop: its control costs the MSP430 as much as the
 * adds; the sums of absent axes stay 0).  true when the block completed
 * and its CUSUM crossed. */
static bool watch_residual(sig_learn *s, const int16_t *r)
{
    uint8_t n = s->cfg.n_axes;
    s->block_sum[0] = (int16_t)(s->block_sum[0] + clamp16(r[0], SIG_LEARN_CUSUM_X_MAX));
    if (n > 1u) {
        s->block_sum[1] = (int16_t)(s->block_sum[1] + clamp16(r[1], SIG_LEARN_CUSUM_X_MAX));
        if (n > 2u) s->block_sum[2] = (int16_t)(s->block_sum[2] + clamp16(r[2], SIG_LEARN_CUSUM_X_MAX));
    }
    if (++s->block_n < SIG_LEARN_BLOCK) return false;
    s->block_n = 0u;
    return watch_block(s);
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
        /* moving samples are left out of the blocks, not breaking them: a
         * block is 8 still samples however they are spread */
        st |= learn_sample(s, t, raw);
        if (!in_range) {
            break_series(s);
        } else if (!s->stale && watch_residual(s, s->has_model ? resid : raw)) {
            sig_learn_reset(s);
            s->stale = true;
        }
    }
    if (s->stale) st |= SIG_LEARN_STALE;
    return st;
}
