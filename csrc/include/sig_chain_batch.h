/* sig_chain_batch.h - the weighing chain over a buffer of samples: the batch
 * form of sig_chain_step_f / sig_chain_step_q (sig_chain.h), with the same
 * results bit for bit.  For hosts and for firmware that filters a block of
 * samples at once (the float form keeps the chain's hot state in registers
 * in its steady state).  A separate module: a firmware that steps one sample
 * at a time links none of it.  Not for the 8051: sdcc --stack-auto would need
 * more than its 256-byte internal RAM for the fast path's frame, so
 * sig_chain_batch.c stops an sdcc build with #error. */
#ifndef SIG_CHAIN_BATCH_H
#define SIG_CHAIN_BATCH_H

#include "sig_chain.h"

/* n samples x -> out, stable (0/1), exactly as n calls of sig_chain_step_f;
 * returns the last sample's status (SIG_OK for n = 0; SIG_ERR_ARG for a NULL
 * pointer, nothing changed).  A non-finite sample before the first finite
 * one gives out NaN, stable 0.  In the steady state (every stage seeded,
 * |sample| and the window within 1e300 (double) / 1e36 (float), so that no
 * sum can overflow, and no lock-out re-seed on the sample) the sample runs on
 * a fast path with the stage state in locals (with noise_auto the drift
 * blocks, the backing of `stable`, the noise estimate and the thresholds
 * that follow it too; a ramp and a second rejection on one side, where a
 * ramp may start, are not the steady state);
 * every other sample, and the last one, goes through sig_chain_step_f.
 * Stack: besides the locals, the Kalman gains it keeps along P's course after
 * a restart, SIG_CHAIN_BATCH_GAINS of them (default 256: 2 KB as double, 1 KB
 * as float; a firmware short of stack defines it lower, 0 keeps none).  On
 * x86-64 with gcc or clang the loop is also compiled for AVX and chosen at
 * run time (the same operations in a shorter encoding, no FMA: the same
 * bits); SIG_CHAIN_BATCH_NO_AVX leaves that copy out. */
sig_status sig_chain_process_f(sig_chain_f *c, const sig_real *x, size_t n, sig_real *out, uint8_t *stable);

/* n codes -> out_q7, stable (0/1), as n calls of sig_chain_step_q; returns
 * the last sample's status. */
sig_status sig_chain_process_q(sig_chain_q *c, const int32_t *x, size_t n, int32_t *out_q7, uint8_t *stable);

#endif /* SIG_CHAIN_BATCH_H */
