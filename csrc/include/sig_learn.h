/* sig_learn.h - the device learns its own offset-vs-temperature table from
 * still samples seen in the field, validates it on temperatures it was not
 * fitted on, and writes it into the A/B coefficient image (sig_image.h) only
 * when it beats the stored model; a CUSUM test on the still residual says
 * when the stored model has gone stale.
 *
 * What is learned.  The expected still reading of every axis is 0 (a gyro's
 * rate, or any axis after the caller subtracted its known still value), so a
 * still reading IS the offset at that temperature.  The model is the table
 * family of sig_pwl.h / sig_tmodel.h (SIG_SECTION_PWL_TABLE): `pysig apply`
 * and sig_tmodel_load_image read what this module writes.
 *
 * ---- Per-sample path (sig_learn_step): integer sums, no division ---------
 *   temperature  int16 t, the unit of the image (sig_tmodel.h: 0.01 °C or a
 *                raw code read as int16/uint16-32768).
 *   bins         n_bins (3..16) uniform bins of width W = 2^bin_shift
 *                (bin_shift 1..10) from t_base: bin = (t - t_base) >> bin_shift,
 *                dt = (t - t_base) & (W - 1), 0 <= dt < 1024; found by a
 *                4-step search on 8W, 4W, 2W, W (the MSP430 shifts one bit
 *                per instruction: a variable shift costs up to 10 loop turns).
 *   sums         per bin: count (uint16), sum_dt (uint32), sum_y[axis]
 *                (uint32) of y + 2047 for the raw still readings y, |y| <=
 *                SIG_LEARN_Y_MAX (2047; a larger reading is not learned:
 *                SIG_LEARN_SKIPPED; the test is one unsigned compare of
 *                y + 2047 <= 4094).  Biased so that every term is unsigned:
 *                the MSP430 widens a signed int16 with a 7-step shift, an
 *                unsigned one for free; the solve takes 2047 * count off.
 *   pending      successive samples of one bin are summed in 16 bits
 *                (acc_y <= 16 * 4094 < 2^16, acc_dt < 16 * 2^10) and moved
 *                into the bin's 32-bit sums (sig_learn_flush) when the
 *                sample's bin differs, after 16 samples, when the bin
 *                reaches 2048 samples, and by the solve: temperature moves
 *                slowly, so most samples cost 16-bit adds and one range
 *                compare instead of the bin search and 32-bit adds.
 *   width        count <= SIG_LEARN_COUNT_MAX = 2048: sum_y <= 2^11 * 4094
 *                < 2^23, sum_dt < 2^11 * 2^10 = 2^21, and the signed sum and
 *                sum_dt times 16 (the Q4 means of the solve) stay below
 *                2^27.  When a flush takes a bin to exactly 2048 samples
 *                (the pending sums stop there), its count and sums are
 *                halved (floor; 2047 * 2048 is even, so the bias the solve
 *                takes off stays exact: an odd count would leave half a
 *                bias, ~1 LSB of mean, in the halved sums): old samples
 *                fade, the sums never overflow, heating and cooling
 *                samples are summed alike.
 *   still residual  r = the stored model's output for the still sample
 *                (the caller computes it anyway: sig_tmodel_apply), in LSB;
 *                the raw reading when no model is in use.
 *   blocks       the residuals of SIG_LEARN_BLOCK = 8 still samples
 *                (within the model's range), each clamped to
 *                +-SIG_LEARN_CUSUM_X_MAX (511 LSB), are summed (int16,
 *                |B| <= 8 * 511); the noise estimate and the CUSUM run once
 *                per full block, a clamp and an add per sample in between
 *                (the MSP430 cost goal).  Moving samples are left out (a
 *                block is 8 still samples however spread); a still sample
 *                beyond the model's range or a new model drops the partial
 *                block and breaks the series of pairs.
 *   noise        per axis N += d - (N >> 5), uint16, over successive block
 *                sums, d = min(|B - B_prev|, 2047): N / 32 is an EWMA over
 *                32 blocks of d, kept x32 so that the floor of the update
 *                does not bias it (N <= 32 * 2047 < 2^16); for white noise
 *                E|B - B_prev| = 2 sigma_B / sqrt(pi) ~ 1.13 sigma_B and one
 *                sample's sigma is sigma_B / sqrt(8).  (A residual beyond
 *                511 LSB counts as one of 511 here too: the model is then
 *                off by far more than any noise the test is tuned to.)
 *   CUSUM        per axis, two-sided, per block, on the block sum (Q4):
 *                  S+ = max(0, S+ + 16 B - 8 k),  S- = max(0, S- - 16 B - 8 k)
 *                stale when S+ > h or S- > h: the per-sample CUSUM on
 *                x = 16 r - k with max(0, .) taken at block ends only, so
 *                at every block end S is at most the per-sample S (max is
 *                monotone): no more false alarms, a shift found at most a
 *                block (8 still samples) later.  k = k_sigma * sigma and
 *                h = h_sigma * sigma (k_sigma, h_sigma in Q4), both limited
 *                to SIG_LEARN_CUSUM_MAX (16383), sigma (one sample's, Q4)
 *                = max(sigma_floor, N * 642 / 2^12), refreshed by every
 *                sig_learn_solve (no multiply per sample); the test runs once
 *                a solve has set them after >= 32 block pairs.  Width:
 *                every term is a multiple of 8, so the C keeps S / 8 (Q1)
 *                in int16: S1 = max(0, S1 + 2 B - k), stale when S1 > h >> 3
 *                (the same crossings: S1 is an integer); S1 <= 2047 before
 *                a block, |2 B| <= 8176, k <= 16383: |S1 + 2 B - k| < 2^15.
 *                A crossing ends the test until a model is put in use.  Skipped (SIG_LEARN_EXTRAPOLATED) outside the stored
 *                model's range: there its correction is extrapolated, not
 *                learned.
 *   On stale     SIG_LEARN_STALE is returned by every step until a new model
 *                is put in use; the bins are cleared (their samples describe
 *                the sensor before the shift) and learning starts again.
 *
 * ---- Solve (sig_learn_solve): fit, validate, commit ----------------------
 *   coverage     a bin is covered with >= min_count samples; a solve needs
 *                >= min_bins (>= 3) covered bins, else nothing is done.
 *   points       per covered bin i, Q4: T_i = 16 * (bin_lo - t_base) +
 *                rdiv(16 sum_dt, count), Y_i[a] = rdiv(16 sum_y[a], count),
 *                rdiv(n, d) = sign(n) * floor((|n| + d/2) / d).  (One
 *                reciprocal per bin was tried: on the MSP430 its variable
 *                32-bit shifts cost clang 14's helper loops more than the
 *                divisions it saves.)
 *   interpolation between points (Tj, Yj), (Tl, Yl) at T (Q4):
 *                f = floor((n << 12) / d) (Q12, 0..4096) with n = T - Tj,
 *                d = Tl - Tj both halved (floor) until d < 2^15 (the divisor
 *                of a 16-step shift-subtract division; d keeps >= 14 bits),
 *                Y = Yj + asr((Yl - Yj) * f, 12).
 *   validation   held-out by temperature, leave one bin out: every covered
 *                bin is predicted from its two nearest covered bins (the
 *                candidate; an end bin by extrapolation from the two next to
 *                it, f = -floor(((Tj - T) << 12) / (Tl - Tj)) >= -8192 on the
 *                left, f <= 12288 on the right, so a candidate reaching beyond
 *                the model's range is judged there too) and by the model in
 *                use at round(T_i / 16) (16 * -apply(0); 0 when there is no
 *                model); errors in Q4 clamped to +-4095, squared and summed
 *                over bins and axes (< 16 * 3 * 2^24 = 3 * 2^28): sse_new,
 *                sse_stored.
 *                Commit only when sse_new <= sse_stored - (sse_stored >>
 *                margin_shift) (better by the margin 2^-margin_shift) and
 *                sse_stored > 0: a model is never replaced by a worse one,
 *                nor by one that is merely as good.
 *   table        knots at the bin centres c_k = t_base + k W + W/2 for every
 *                bin k from the first to the last that is covered or inside
 *                the stored model's range (so the new model covers the stored
 *                range within the bins).  Knot value: between the first and
 *                last points the interpolation above; beyond them, the stored
 *                model's value at c_k plus the learned minus stored value at
 *                the end point (the stored shape carried on), or the end
 *                point's value when there is no stored model.  Values are Q4
 *                entries (value_frac 4) unless one exceeds int16, then
 *                value_frac drops until all fit (saturated at value_frac 0).
 *                t_lo = first knot, t_hi = last knot, recip = 2^(32 - bin_shift).
 *   commit       at most once per `period` steps (the first commit waits for
 *                none).  The image: header, SIG_SECTION_PWL_TABLE,
 *                SIG_SECTION_TEMP_CODE (code_kind), CRC; sequence = the live
 *                image's + 1.  The caller writes it into the slot
 *                sig_image_select_slot did not select (the A/B power-cut
 *                guarantee), loads it and calls sig_learn_use_model.
 *   cost         divisions: 1 + n_axes per covered bin, 1 per held-out bin,
 *                1 per knot; none in sig_learn_step.
 */
#ifndef SIG_LEARN_H
#define SIG_LEARN_H

#include "sig_types.h"
#include "sig_tmodel.h"

#define SIG_LEARN_MAX_AXES   3u
#define SIG_LEARN_MAX_BINS   16u
#define SIG_LEARN_MIN_BINS   3u
#define SIG_LEARN_COUNT_MAX  2048u
#define SIG_LEARN_Y_MAX      2047
#define SIG_LEARN_Y_BIAS     2047
#define SIG_LEARN_ACC_MAX    16u   /* pending samples of one bin before they go into its sums */
#define SIG_LEARN_BLOCK      8u    /* still samples per block of the noise estimate and the CUSUM */
#define SIG_LEARN_CUSUM_X_MAX 511   /* |residual| a block sum adds, LSB */
#define SIG_LEARN_CUSUM_MAX  16383 /* k and h, Q4 LSB */
#define SIG_LEARN_MAX_SHIFT  10u
#define SIG_LEARN_NOISE_MIN_N 32u   /* block pairs before the CUSUM is armed */
/* bytes of the image sig_learn_solve writes at most (16 knots, 3 axes) */
#define SIG_LEARN_IMAGE_MAX  (12u + 4u + 10u + 3u * (1u + 2u * 16u) + 4u + 2u + 2u)

/* Why a solve did not commit (sig_learn_report.outcome). */
#define SIG_LEARN_COMMIT        0u  /* a new image was written */
#define SIG_LEARN_WAIT_PERIOD   1u  /* the last commit is younger than `period` steps */
#define SIG_LEARN_WAIT_COVERAGE 2u  /* fewer than min_bins covered bins */
#define SIG_LEARN_NOT_BETTER    3u  /* the candidate did not beat the stored model by the margin */

typedef struct {
    uint32_t period;        /* steps between two commits, >= 1 */
    int16_t t_base;         /* lower edge of bin 0 (image t unit) */
    uint16_t min_count;     /* samples that make a bin covered, 1..2048 */
    uint16_t sigma_floor;   /* smallest sigma of the CUSUM, Q4 LSB, >= 1 */
    uint16_t k_sigma;       /* CUSUM allowance k in sigmas, Q4 */
    uint16_t h_sigma;       /* CUSUM threshold h in sigmas, Q4, > 0 */
    uint8_t bin_shift;      /* bin width 2^bin_shift, 1..10 */
    uint8_t n_bins;         /* 3..16; t_base + n_bins * 2^bin_shift <= 32767 */
    uint8_t min_bins;       /* covered bins a solve needs, 3..n_bins */
    uint8_t margin_shift;   /* validation margin 2^-margin_shift, 1..8 */
    uint8_t n_axes;         /* 1..3 */
    uint8_t code_kind;      /* SIG_TCODE_INT16 / SIG_TCODE_UINT16, written into the image */
} sig_learn_config;

typedef struct {
    sig_learn_config cfg;
    uint32_t sum_y[SIG_LEARN_MAX_AXES][SIG_LEARN_MAX_BINS];  /* sum of (y + 2047), axis-major: a bin's offset is a shift */
    uint32_t sum_dt[SIG_LEARN_MAX_BINS];
    uint16_t count[SIG_LEARN_MAX_BINS];
    uint16_t bin_w[4];      /* 8W, 4W, 2W, W: the bin search's steps (no variable shift per sample) */
    uint16_t acc_y[SIG_LEARN_MAX_AXES];  /* pending sums of one bin: <= 16 * 4094 < 2^16 */
    uint16_t acc_dt, acc_lo;             /* pending sum of dt (< 2^14); the bin's lower edge - t_base */
    uint8_t acc_bin, acc_n;              /* the pending bin, its samples (< 16) */
    uint8_t acc_room;                    /* pending samples before a flush: min(16, 2048 - count[acc_bin]) */
    int16_t cusum_pos[SIG_LEARN_MAX_AXES], cusum_neg[SIG_LEARN_MAX_AXES];  /* Q1 LSB: S / 8, <= h / 8 before a block */
    int16_t k[SIG_LEARN_MAX_AXES], h[SIG_LEARN_MAX_AXES];  /* Q4 LSB, <= 16383; h == 0: test not armed */
    uint16_t noise[SIG_LEARN_MAX_AXES];                    /* N: 32 x the EWMA of |d|, LSB */
    int16_t prev_r[SIG_LEARN_MAX_AXES];                    /* the previous block's sum */
    int16_t block_sum[SIG_LEARN_MAX_AXES];                 /* residuals of the block so far */
    uint32_t steps;         /* sig_learn_step calls: the clock of `period` */
    uint32_t last_commit;   /* steps at the last commit */
    uint16_t noise_n;       /* successive still pairs seen, stops at 65535 */
    uint16_t grid_span;     /* n_bins << bin_shift (<= 16384), from the configuration */
    uint16_t bin_mask;      /* 2^bin_shift - 1 */
    int16_t model_lo, model_hi;   /* range of the model in use */
    uint8_t block_n;        /* samples in the block so far */
    bool has_model, committed, stale, have_prev;
} sig_learn;

typedef struct {
    uint32_t sse_new, sse_stored; /* validation sums (Q4 LSB squared) */
    uint8_t outcome;              /* SIG_LEARN_COMMIT, _WAIT_* or _NOT_BETTER */
    uint8_t covered;              /* covered bins */
    uint8_t validated;            /* held-out bins in the sums */
    uint8_t n_knots;              /* knots of the candidate (0 when none was built) */
    int16_t t_lo, t_hi;           /* its range */
} sig_learn_report;

/* Scratch of sig_learn_solve, caller-owned (CMSIS-style), needed only during
 * the call: the 8051 has no room for it on its stack, and firmware may
 * share it with other passing work.  Not part of the learner's state. */
typedef struct {
    int32_t t[SIG_LEARN_MAX_BINS];                          /* T_i, Q4 from t_base */
    int16_t y[SIG_LEARN_MAX_BINS][SIG_LEARN_MAX_AXES];      /* Y_i, Q4 LSB (|Y| <= 32752) */
    uint8_t bin[SIG_LEARN_MAX_BINS];
    uint8_t n;
} sig_learn_points;

typedef struct {
    sig_learn_points points;
    int32_t knots[SIG_LEARN_MAX_BINS][SIG_LEARN_MAX_AXES];  /* knot values, Q4 */
    int32_t at_point[SIG_LEARN_MAX_BINS][SIG_LEARN_MAX_AXES]; /* the model's values at the points, Q4 */
} sig_learn_scratch;

/* Check the configuration and start empty, with no model in use.
 * SIG_ERR_ARG (state untouched) for NULL or a field outside its range. */
sig_status sig_learn_init(sig_learn *s, const sig_learn_config *cfg);

/* Forget every sample and the CUSUM (configuration, model and clock kept). */
void sig_learn_reset(sig_learn *s);

/* Move the pending samples into their bin's sums (sig_learn_solve does it
 * first; for firmware that reads the counts). */
void sig_learn_flush(sig_learn *s);

/* The firmware now applies model m (NULL: none): its range becomes the one
 * beyond which corrections count as extrapolated; the CUSUM and the stale
 * flag are cleared.  SIG_ERR_ARG (state untouched) for NULL s, a model with
 * another number of axes or an unknown family. */
sig_status sig_learn_use_model(sig_learn *s, const sig_tmodel *m);

/* One sample: temperature t, raw readings raw[n_axes], the model's output
 * resid[n_axes] for them (may be NULL when no model is in use), still: the
 * caller's stillness gate.  Returns SIG_OK or an OR of SIG_LEARN_STALE,
 * SIG_LEARN_SKIPPED (still but outside the bins or |raw| > 2047: not
 * learned) and SIG_LEARN_EXTRAPOLATED (t outside the model's range).
 * SIG_ERR_ARG (state untouched) for NULL s or raw, or NULL resid while a
 * model is in use. */
sig_status sig_learn_step(sig_learn *s, int16_t t, const int16_t *raw, const int16_t *resid, bool still);

/* Fit, validate and maybe commit (see the header comment).  model: the model
 * in use (NULL when none); live_seq: the sequence number of its image (0 when
 * none); image: room for image_cap bytes (>= SIG_LEARN_IMAGE_MAX is always
 * enough).  Returns SIG_LEARN_COMMITTED with *image_len set when an image was
 * written, SIG_OK when not (report->outcome says why; too few samples is
 * SIG_LEARN_WAIT_COVERAGE, not an error); SIG_ERR_ARG (state untouched) for
 * NULL s, report, image_len, image or work, image_cap < SIG_LEARN_IMAGE_MAX, or
 * model NULL while one is in use (or given while none is) or with another
 * number of axes.  The CUSUM thresholds are refreshed on every call that
 * does not fail. */
sig_status sig_learn_solve(sig_learn *s, const sig_tmodel *model, uint32_t live_seq,
                           uint8_t *image, uint16_t image_cap, uint16_t *image_len,
                           sig_learn_report *report, sig_learn_scratch *work);

#endif /* SIG_LEARN_H */
