/* check.h - the smallest unit-test kit: CHECK(cond) records a failure with
 * file:line and keeps going; CHECK_EQ_I shows both integers; main returns
 * check_report(), which is non-zero when anything failed. */
#ifndef CHECK_H
#define CHECK_H

#include <stdio.h>

static long check_run, check_failed;

#define CHECK(cond) do { check_run++; if (!(cond)) { check_failed++; \
    fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); } } while (0)

#define CHECK_EQ_I(got, want) do { long long g_ = (long long)(got), w_ = (long long)(want); \
    check_run++; if (g_ != w_) { check_failed++; \
    fprintf(stderr, "%s:%d: %s == %lld, want %s == %lld\n", __FILE__, __LINE__, \
            #got, g_, #want, w_); } } while (0)

static inline int check_report(const char *name)
{
    printf("%s: %ld checks, %ld failed\n", name, check_run, check_failed);
    return check_failed ? 1 : 0;
}

/* Deterministic pseudo-random 32-bit values (xorshift32) for sweeps. */
static unsigned long check_rng_state = 2463534242UL;
static inline unsigned long check_rand32(void)
{
    unsigned long x = check_rng_state & 0xFFFFFFFFUL;
    x ^= (x << 13) & 0xFFFFFFFFUL;
    x ^= x >> 17;
    x ^= (x << 5) & 0xFFFFFFFFUL;
    check_rng_state = x;
    return x;
}

#endif /* CHECK_H */
