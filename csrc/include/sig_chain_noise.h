/* sig_chain_noise.h - the rules by which the weighing chain follows the
 * noise it measures (noise_auto, sig_chain.h), as macros: written once for
 * the float and fixed step paths (csrc/weigh/sig_chain.c) and for any code
 * that keeps the chain's state in another layout (locals, a port's own
 * struct).  Macros, not functions: on the 8051 a call, even an inlined one,
 * costs more than the test. */
#ifndef SIG_CHAIN_NOISE_H
#define SIG_CHAIN_NOISE_H

#include "sig_chain.h"

/* noise_auto, after the stages: whether this sample may update the noise
 * estimate (bool `update`) - not on a motion, re-seed or ramp event nor for
 * a window (n samples) after it, not on a rejected sample nor the one after
 * it, not while a motion run is under way (sig_chain.h) - and the escape
 * when updates have been held too long (the estimator's update count
 * `noise_count` drops back to 8: large steps again).  A ramp sample (a pour
 * is never noise) is skipped and leaves the escape count as it is.  g: the
 * gate's fields (rejected_prev, holdoff, frozen: a sig_chain_gate, or
 * locals so named). */
#define SIG_CHAIN_NOISE_GATE(g, ret, n, motion_run, noise_count, update) do {           \
        bool event_ = ((ret) & (SIG_CHAIN_MOTION | SIG_LIMIT_RESEEDED | SIG_CHAIN_RAMP)) != 0; \
        bool rejected_ = ((ret) & SIG_WARN_REJECTED) != 0;                               \
        if (event_) (g).holdoff = (n);                                                   \
        else if ((g).holdoff > 0u) (g).holdoff--;                                        \
        if (((ret) & SIG_CHAIN_RAMP) != 0) {                                             \
            (update) = false;                                                            \
        } else if (!event_ && !rejected_ && !(g).rejected_prev && (g).holdoff == 0u      \
                   && (motion_run) == 0u) {                                              \
            if ((g).frozen > 0u) (g).frozen--;                                           \
            (update) = true;                                                             \
        } else {                                                                         \
            if ((g).frozen < 2u * SIG_CHAIN_NOISE_FROZEN_MAX) (g).frozen++;              \
            if ((g).frozen == SIG_CHAIN_NOISE_FROZEN_MAX && (noise_count) > 8u)          \
                (noise_count) = 8u;                                                      \
            (update) = (g).frozen >= SIG_CHAIN_NOISE_FROZEN_MAX                          \
                       || (noise_count) < SIG_NOISE_WARMUP;                              \
        }                                                                                \
        (g).rejected_prev = rejected_;                                                   \
    } while (0)

/* The fixed thresholds from the measured sigma s (Q24.7, <= 2^27: 6 s fits)
 * by shifts and adds: A0 = 6 s rounded to codes (>= 1; `none`: no
 * difference seen yet, A0 takes every sample), motion band 1.5 s,
 * stability step s / 4, zero band s, zero rate s / 16 per sample, near
 * band 2 s (how far sample and output may be apart on a stable sample). */
#define SIG_CHAIN_THRESHOLDS_Q(s, none, a0, band, step, zband, zrate, nband) do {       \
        int32_t s2_ = (s) << 1;                                                          \
        int32_t a_ = (s2_ + s2_ + s2_ + 64) >> 7;                                        \
        (a0) = (none) ? 2 * SIG_CODE_MAX : (a_ > 0 ? a_ : 1);                            \
        (band) = (s) + ((s) >> 1);                                                       \
        (step) = (s) >> 2;                                                               \
        (zband) = (s);                                                                   \
        (zrate) = (s) >> 4;                                                              \
        (nband) = s2_;                                                                   \
    } while (0)

#endif /* SIG_CHAIN_NOISE_H */
