/* sig_learn_solve.c - the learner's fit, held-out validation and commit into
 * a coefficient image (sig_learn.h); apart from the per-sample path so the
 * firmware can place it in a rarely run section. */
#include "sig_learn.h"
#include "sig_image.h"
#include "sig_crc16.h"

#define FRAC_BITS 12u      /* interpolation fraction, Q12 */
#define ERR_MAX   INT32_C(4095)

#if SIG_LEARN_Y_BIAS != 2047
#error "make_points takes the bias off as (count << 11) - count"
#endif

/* floor(num / den) for den < 2^15 and num < den * 2^16 (a quotient below
 * 2^16): 16 steps of shift and subtract on num itself, whose high half is
 * the remainder (< 2 den <= 2^16 after the shift) and whose low half fills
 * with the quotient bits: no 32-bit compare.  ~17 MSP430 instructions a
 * step (clang carries the low half's top bit with a shift; a compare form
 * measured 2 % slower), where a general 32-bit division routine costs ~1200
 * instructions. */
static uint16_t div_q16(uint32_t num, uint16_t den)
{
    uint8_t i;
    for (i = 0u; i < 16u; i++) {
        num <<= 1;
        if ((uint16_t)(num >> 16) >= den) num = num - ((uint32_t)den << 16) + 1u;
    }
    return (uint16_t)(num & 0xFFFFu);
}

/* sign(n) * floor((|n| + d/2) / d), 1 <= d <= 2048, |n| / d < 2^15 (bin means) */
static int32_t rdiv(int32_t n, uint16_t d)
{
    uint32_t mag = n < 0 ? (uint32_t)0 - (uint32_t)n : (uint32_t)n;
    int32_t q = (int32_t)div_q16(mag + (uint32_t)(d >> 1), d);
    return n < 0 ? -q : q;
}

/* Q12 position of x in [a, b] (a < b, a <= x, (x - a) < 3 (b - a), Q4
 * temperatures, b - a < 2^18): both distances halved (floor) until b - a
 * < 2^15, the divisor of div_q16; it then keeps >= 14 bits. */
static int32_t frac_q12(int32_t a, int32_t b, int32_t x)
{
    uint32_t num = (uint32_t)(x - a), den = (uint32_t)(b - a);
    while (den >= UINT32_C(0x8000)) {
        num >>= 1;
        den >>= 1;
    }
    return (int32_t)div_q16(num << FRAC_BITS, (uint16_t)den);
}

static int32_t lerp(int32_t ya, int32_t yb, int32_t f)
{
    return ya + sig_asr32((yb - ya) * f, FRAC_BITS);
}

/* The model's correction at t, Q4 LSB (16 * corr; corr = -apply(0)). */
static void model_q4(const sig_tmodel *m, int16_t t, int32_t *out, uint8_t n_axes)
{
    static const int16_t zero[SIG_LEARN_MAX_AXES] = {0, 0, 0};
    int16_t y[SIG_LEARN_MAX_AXES];
    uint8_t a;
    uint16_t code = m->code_kind == SIG_TCODE_UINT16 ? (uint16_t)((int32_t)t + INT32_C(32768))
                                                      : (uint16_t)t;
    (void)sig_tmodel_apply(m, code, zero, y);
    for (a = 0u; a < n_axes; a++) out[a] = -(int32_t)y[a] * 16;
}

static uint32_t sq_err(int32_t e)
{
    int16_t c;
    if (e > ERR_MAX) e = ERR_MAX;
    if (e < -ERR_MAX) e = -ERR_MAX;
    c = (int16_t)e;
    return (uint32_t)((int32_t)c * c);      /* a 16 x 16 product */
}

/* The temperature (image unit) of a Q4 position from t_base, rounded. */
static int16_t t_of_q4(const sig_learn *s, int32_t tq)
{
    return (int16_t)(s->cfg.t_base + ((tq + 8) >> 4));
}

static uint8_t *put_u16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)(v >> 8);
    return p + 2;
}

static uint8_t *put_u32(uint8_t *p, uint32_t v)
{
    p = put_u16(p, (uint16_t)(v & 0xFFFFu));
    return put_u16(p, (uint16_t)(v >> 16));
}

static void refresh_thresholds(sig_learn *s)
{
    uint8_t a;
    uint32_t sigma, kv, hv;
    if (s->noise_n < SIG_LEARN_NOISE_MIN_N) return;
    for (a = 0u; a < s->cfg.n_axes; a++) {
        /* one sample's sigma (Q4) = 16 E|B - B_prev| sqrt(pi) / 2 / sqrt(8)
         * (B: the sum of 8 samples) ~ (N / 32) * 16 * 0.8862 / 2.828
         * = N * 642 / 2^12 */
        sigma = ((uint32_t)s->noise[a] * 642u) >> 12;
        if (sigma < s->cfg.sigma_floor) sigma = s->cfg.sigma_floor;
        /* limited to SIG_LEARN_CUSUM_MAX: k and h are int16 so that the
         * per-sample CUSUM is (sig_learn.h: width) */
        kv = (sigma * s->cfg.k_sigma) >> 4;
        hv = (sigma * s->cfg.h_sigma) >> 4;
        if (kv > (uint32_t)SIG_LEARN_CUSUM_MAX) kv = (uint32_t)SIG_LEARN_CUSUM_MAX;
        if (hv > (uint32_t)SIG_LEARN_CUSUM_MAX) hv = (uint32_t)SIG_LEARN_CUSUM_MAX;
        s->k[a] = (int16_t)kv;
        s->h[a] = (int16_t)hv;
    }
}

/* Bins of the model's range inside the grid: false when they do not meet. */
static bool model_bins(const sig_learn *s, uint8_t *lo, uint8_t *hi)
{
    int32_t top = (int32_t)s->grid_span;
    int32_t a = (int32_t)s->model_lo - s->cfg.t_base, b = (int32_t)s->model_hi - s->cfg.t_base;
    if (b < 0 || a >= top) return false;
    if (a < 0) a = 0;
    if (b >= top) b = top - 1;
    *lo = (uint8_t)((uint32_t)a >> s->cfg.bin_shift);
    *hi = (uint8_t)((uint32_t)b >> s->cfg.bin_shift);
    return true;
}

/* Keep the longest run of points (the first of equals) whose successive
 * bins have at most SIG_LEARN_GAP_MAX uncovered bins between them: a table
 * is not interpolated across a stretch no still sample has seen (its shape
 * there is unknown and the held-out test cannot see it). */
static void keep_longest_run(sig_learn_points *p, uint8_t n_axes)
{
    uint8_t i, start = 0u, best = 0u, best_n = 0u, a;
    for (i = 1u; i <= p->n; i++) {
        if (i == p->n || p->bin[i] - p->bin[i - 1u] > (int)SIG_LEARN_GAP_MAX + 1) {
            if ((uint8_t)(i - start) > best_n) {
                best_n = (uint8_t)(i - start);
                best = start;
            }
            start = i;
        }
    }
    if (best != 0u) {
        for (i = 0u; i < best_n; i++) {
            p->t[i] = p->t[best + i];
            p->bin[i] = p->bin[best + i];
            for (a = 0u; a < n_axes; a++) p->y[i][a] = p->y[best + i][a];
        }
    }
    p->n = best_n;
}

static void make_points(const sig_learn *s, sig_learn_points *p)
{
    uint8_t b, a, n = s->cfg.n_axes;
    uint16_t c;
    const uint32_t *sum_y = s->sum_y;
    int32_t lo = 0, step = (int32_t)s->bin_mask * 16 + 16;     /* 16 W */
    p->n = 0u;
    for (b = 0u; b < s->cfg.n_bins; b++, lo += step, sum_y++) {
        c = s->count[b];
        if (c < s->cfg.min_count) continue;
        p->t[p->n] = lo + rdiv((int32_t)s->sum_dt[b] * 16, c);
        for (a = 0u; a < n; a++)
            p->y[p->n][a] = (int16_t)rdiv(((int32_t)sum_y[(uint8_t)(a * s->cfg.n_bins)] - (((int32_t)c << 11) - c)) * 16, c);
        p->bin[p->n] = b;
        p->n++;
    }
    keep_longest_run(p, n);
}

/* Q12 position of a held-out point from its two neighbours (a < b): inside
 * as frac_q12; beyond an end (x < a or x > b) extrapolated, the fraction
 * limited to [-8192, 12288] (at most two spacings out). */
static int32_t held_out_frac(int32_t a, int32_t b, int32_t x)
{
    /* the limits are tested first so that every quotient is below 2^16 */
    if (x < a) {
        if (a - x >= 2 * (b - a)) return INT32_C(-8192);
        return -frac_q12(x, x + (b - a), a);
    }
    if (x - a >= 3 * (b - a)) return INT32_C(12288);
    return frac_q12(a, b, x);
}

/* Leave-one-bin-out errors of the candidate and of the model in use: every
 * covered bin is predicted from its two nearest covered neighbours (the end
 * bins by extrapolation from the two next to them, so a candidate that
 * reaches beyond the model's range is judged there too). */
static uint8_t validate(const sig_learn *s, const sig_learn_scratch *work,
                        uint32_t *sse_new, uint32_t *sse_stored)
{
    const sig_learn_points *p = &work->points;
    int32_t f;
    uint8_t i, j, l, a;
    *sse_new = 0u;
    *sse_stored = 0u;
    for (i = 0u; i < p->n; i++) {
        j = i == 0u ? 1u : (i + 1u == p->n ? (uint8_t)(i - 2u) : (uint8_t)(i - 1u));
        l = (uint8_t)(j == i + 1u ? i + 2u : (i + 1u == p->n ? i - 1u : i + 1u));
        f = held_out_frac(p->t[j], p->t[l], p->t[i]);
        for (a = 0u; a < s->cfg.n_axes; a++) {
            *sse_new += sq_err(p->y[i][a] - lerp(p->y[j][a], p->y[l][a], f));
            *sse_stored += sq_err(p->y[i][a] - work->at_point[i][a]);
        }
    }
    return p->n;
}

/* The model's values (Q4) at the points (0 without a model), and into
 * work->knots at the knots k_lo.. beyond the points (the stored shape the
 * table carries on there).  Evaluated here, in a small stack frame, not in
 * validate or knot_values: the 8051's 256-byte stack does not hold the
 * model's call chain below their frames. */
static void model_at_points(const sig_learn *s, const sig_tmodel *m, sig_learn_scratch *work)
{
    uint8_t i, a;
    for (i = 0u; i < work->points.n; i++) {
        if (m != NULL) {
            model_q4(m, t_of_q4(s, work->points.t[i]), work->at_point[i], s->cfg.n_axes);
        } else {
            for (a = 0u; a < SIG_LEARN_MAX_AXES; a++) work->at_point[i][a] = 0;
        }
    }
}

static void model_at_knots(const sig_learn *s, const sig_tmodel *m, sig_learn_scratch *work,
                           uint8_t k_lo, uint8_t k_hi)
{
    const sig_learn_points *p = &work->points;
    int32_t w = (int32_t)s->bin_mask + 1, c = (int32_t)k_lo * w + (w >> 1);
    uint8_t i;
    for (i = 0u; i <= (uint8_t)(k_hi - k_lo); i++, c += w) {
        if (c * 16 >= p->t[0] && c * 16 <= p->t[p->n - 1u]) continue;
        model_q4(m, (int16_t)(s->cfg.t_base + c), work->knots[i], s->cfg.n_axes);
    }
}

/* Knot values per axis (Q4) into work->knots for knots k_lo..k_hi, W
 * apart: see "table" in sig_learn.h.  The points are walked left to right
 * as the knots advance.  Beyond the points work->knots holds the model's
 * values there (model_at_knots) when a model is in use. */
static void knot_values(const sig_learn *s, bool has_model, sig_learn_scratch *work,
                        uint8_t k_lo, uint8_t k_hi)
{
    const sig_learn_points *p = &work->points;
    int32_t w = (int32_t)s->bin_mask + 1, c = (int32_t)k_lo * w + (w >> 1), cq, f;
    int32_t (*v)[SIG_LEARN_MAX_AXES] = work->knots;
    uint8_t a, e, i, j = 0u, n = s->cfg.n_axes, last = (uint8_t)(p->n - 1u);
    for (i = 0u; i <= (uint8_t)(k_hi - k_lo); i++, c += w) {
        cq = c * 16;
        if (cq >= p->t[0] && cq <= p->t[last]) {
            while (j + 2u < p->n && p->t[j + 1u] < cq) j++;
            f = frac_q12(p->t[j], p->t[j + 1u], cq);
            for (a = 0u; a < n; a++) v[i][a] = lerp(p->y[j][a], p->y[j + 1u][a], f);
            continue;
        }
        e = cq < p->t[0] ? 0u : last;
        for (a = 0u; a < n; a++)
            v[i][a] = has_model ? p->y[e][a] + v[i][a] - work->at_point[e][a] : p->y[e][a];
    }
}

/* The largest value_frac 0..4 at which the axis' largest |value| fits. */
static uint8_t value_frac(int32_t max_abs)
{
    uint8_t vf = 4u;
    while (vf > 0u && (max_abs >> (4u - vf)) >= INT16_MAX) vf--;
    return vf;
}

static int16_t entry_of(int32_t v, uint8_t vf)
{
    uint8_t sh = (uint8_t)(4u - vf);
    if (sh > 0u) v = sig_asr32(v + (INT32_C(1) << (sh - 1u)), sh);
    return sig_sat16(v);
}

/* Write the image of the table over bins k_lo..k_hi; returns its length. */
static uint16_t write_image(const sig_learn *s, const sig_learn_scratch *work,
                            uint8_t k_lo, uint8_t k_hi, uint32_t seq, uint8_t *img)
{
    const int32_t (*v)[SIG_LEARN_MAX_AXES] = work->knots;
    int32_t mx;
    uint8_t n_knots = (uint8_t)((uint8_t)(k_hi - k_lo) + 1u), n = s->cfg.n_axes, a, i, vf;
    uint16_t pay_len = (uint16_t)(SIG_PWL_IMAGE_FIXED_LEN + (uint16_t)n * (1u + 2u * (uint16_t)n_knots));
    uint16_t total = (uint16_t)(SIG_IMAGE_HEADER_LEN + SIG_IMAGE_SECTION_HDR_LEN + pay_len +
                                SIG_IMAGE_SECTION_HDR_LEN + SIG_TEMP_CODE_LEN + SIG_IMAGE_CRC_LEN);
    int32_t w = (int32_t)s->bin_mask + 1, c = (int32_t)k_lo * w + (w >> 1);
    int16_t t_lo = (int16_t)(s->cfg.t_base + c);
    uint8_t *q = img;
    *q++ = SIG_IMAGE_MAGIC0;
    *q++ = SIG_IMAGE_MAGIC1;
    *q++ = SIG_IMAGE_MAGIC2;
    *q++ = SIG_IMAGE_MAGIC3;
    *q++ = (uint8_t)SIG_IMAGE_VERSION;
    *q++ = 0u;
    q = put_u16(q, total);
    q = put_u32(q, seq);
    q = put_u16(q, (uint16_t)SIG_SECTION_PWL_TABLE);
    q = put_u16(q, pay_len);
    *q++ = n;
    *q++ = n_knots;
    q = put_u16(q, (uint16_t)t_lo);
    q = put_u16(q, (uint16_t)(int16_t)(t_lo + (int32_t)(n_knots - 1u) * w));
    q = put_u32(q, UINT32_C(1) << (32u - s->cfg.bin_shift));
    for (a = 0u; a < n; a++) {
        mx = 0;
        for (i = 0u; i < n_knots; i++) {
            int32_t mag = sig_abs32_sat(v[i][a]);
            if (mag > mx) mx = mag;
        }
        vf = value_frac(mx);
        *q++ = vf;
        for (i = 0u; i < n_knots; i++) q = put_u16(q, (uint16_t)entry_of(v[i][a], vf));
    }
    q = put_u16(q, (uint16_t)SIG_SECTION_TEMP_CODE);
    q = put_u16(q, (uint16_t)SIG_TEMP_CODE_LEN);
    *q++ = s->cfg.code_kind;
    *q++ = 0u;
    (void)put_u16(q, sig_crc16_ccitt(SIG_CRC16_INIT, img, (size_t)(total - SIG_IMAGE_CRC_LEN)));
    return total;
}

sig_status sig_learn_solve(sig_learn *s, const sig_tmodel *model, uint32_t live_seq,
                           uint8_t *image, uint16_t image_cap, uint16_t *image_len,
                           sig_learn_report *report, sig_learn_scratch *work)
{
    sig_learn_points *p;
    uint8_t k_lo, k_hi, m_lo = 0u, m_hi = 0u;
    if (s == NULL || report == NULL || image == NULL || image_len == NULL || work == NULL)
        return SIG_ERR_ARG;
    p = &work->points;
    if (image_cap < SIG_LEARN_IMAGE_MAX || s->has_model != (model != NULL)) return SIG_ERR_ARG;
    if (model != NULL && model->n_axes != s->cfg.n_axes) return SIG_ERR_ARG;
    refresh_thresholds(s);
    sig_learn_flush(s);
    report->sse_new = 0u;
    report->sse_stored = 0u;
    report->covered = 0u;
    report->validated = 0u;
    report->n_knots = 0u;
    report->t_lo = 0;
    report->t_hi = 0;
    if (s->committed && s->steps - s->last_commit < s->cfg.period) {
        report->outcome = SIG_LEARN_WAIT_PERIOD;
        return SIG_OK;
    }
    make_points(s, p);
    report->covered = p->n;
    if (p->n < s->cfg.min_bins) {
        report->outcome = SIG_LEARN_WAIT_COVERAGE;
        return SIG_OK;
    }
    model_at_points(s, model, work);
    report->validated = validate(s, work, &report->sse_new, &report->sse_stored);
    if (report->sse_stored == 0u ||
        report->sse_new > report->sse_stored - (report->sse_stored >> s->cfg.margin_shift)) {
        report->outcome = SIG_LEARN_NOT_BETTER;
        return SIG_OK;
    }
    k_lo = p->bin[0];
    k_hi = p->bin[p->n - 1u];
    if (model != NULL && model_bins(s, &m_lo, &m_hi)) {
        if (m_lo < k_lo) k_lo = m_lo;
        if (m_hi > k_hi) k_hi = m_hi;
    }
    if (model != NULL) model_at_knots(s, model, work, k_lo, k_hi);
    knot_values(s, model != NULL, work, k_lo, k_hi);     /* not nested in write_image: stack depth */
    *image_len = write_image(s, work, k_lo, k_hi, live_seq + 1u, image);
    s->committed = true;
    s->last_commit = s->steps;
    report->outcome = SIG_LEARN_COMMIT;
    report->n_knots = (uint8_t)((uint8_t)(k_hi - k_lo) + 1u);
    report->t_lo = sig_image_get_i16(image + SIG_IMAGE_HEADER_LEN + SIG_IMAGE_SECTION_HDR_LEN + 2u);
    report->t_hi = sig_image_get_i16(image + SIG_IMAGE_HEADER_LEN + SIG_IMAGE_SECTION_HDR_LEN + 4u);
    return SIG_LEARN_COMMITTED;
}
