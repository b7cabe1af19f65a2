/* sig_status.h - every status code and warning bit of the library, in one place.
 *
 * Every function returns a sig_status (int16_t, littlefs style):
 *   == 0  success;
 *   >  0  warnings: the result is valid; bit flags that may be OR-ed
 *         (test with `st & SIG_WARN_CLAMPED`, never with ==);
 *   <  0  errors: nothing was produced and the caller's state is unchanged.
 * Each value is defined here only; other headers include this one and keep
 * no copies.  pysig/status.py mirrors it name by name (a test checks).
 */
#ifndef SIG_STATUS_H
#define SIG_STATUS_H

#include <stdint.h>

typedef int16_t sig_status;

#define SIG_OK              ((sig_status)0)    /* success */

/* ---- warning bits (result valid) ---------------------------------------- */
#define SIG_WARN_CLAMPED    ((sig_status)1)    /* an input was clamped to its valid range (temperature, ADC code, u) */
#define SIG_WARN_SATURATED  ((sig_status)2)    /* an output or state saturated at its integer rail */
#define SIG_WARN_REJECTED   ((sig_status)4)    /* sample rejected as an impulse or non-finite and replaced */
/* bit 8 is free */
#define SIG_LIMIT_RESEEDED  ((sig_status)16)   /* limit stage: the lock-out fix accepted a run and re-seeded Dc */
#define SIG_CHAIN_MOTION    ((sig_status)32)   /* weighing chain: motion detected, window and Kalman P restarted */
#define SIG_CHAIN_TARED     ((sig_status)64)   /* weighing chain: a pending tare was applied on this sample */
#define SIG_CHAIN_NOISE_FLOOR ((sig_status)128) /* weighing chain, measured noise: the estimate sits at its
                                                   floor (a stuck sensor, or noise below a quarter code) */
#define SIG_CHAIN_RAMP      ((sig_status)256)  /* weighing chain: the load is moving steadily (a pour); the
                                                   output follows the samples */
#define SIG_LEARN_STALE     ((sig_status)512)  /* learner: the CUSUM of the still residual says the model in use is stale */
#define SIG_LEARN_SKIPPED   ((sig_status)1024)  /* learner: a still sample outside the bins or beyond +-2047 was not learned */
#define SIG_LEARN_EXTRAPOLATED ((sig_status)2048) /* learner: the temperature is outside the range of the model in use */
#define SIG_LEARN_COMMITTED ((sig_status)4096) /* learner: a validated model was written into a new image */

/* ---- errors (nothing produced, state unchanged) ------------------------- */
#define SIG_ERR_ARG         ((sig_status)-1)   /* NULL pointer or parameter out of range */
#define SIG_ERR_NONFINITE   ((sig_status)-2)   /* NaN or inf where a finite value is needed */
#define SIG_ERR_FORMAT      ((sig_status)-3)   /* malformed data: image magic, version, length, section layout or payload */
#define SIG_ERR_CRC         ((sig_status)-4)   /* checksum mismatch: corrupt or partly written image */
#define SIG_ERR_EMPTY       ((sig_status)-5)   /* nothing to use: no valid slot, no such section, no data yet */
#define SIG_ERR_DEVICE      ((sig_status)-6)   /* a valid image, but made for another device (sig_device_id.h) */

#endif /* SIG_STATUS_H */
