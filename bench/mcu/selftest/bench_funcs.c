/* Portable C99 test functions: Q16.16 fixed point and float. */
#include <stdint.h>
#include "bench_funcs.h"

#ifndef BENCH_NO_INT64
/* Degree-2 Horner in Q16.16: y = (c2*x + c1)*x + c0, int64 intermediate. */
int32_t poly2_q16(const int32_t c[3], int32_t x)
{
    int32_t y = c[2];
    y = (int32_t)(((int64_t)y * x) >> 16) + c[1];
    y = (int32_t)(((int64_t)y * x) >> 16) + c[0];
    return y;
}

/* Scalar Kalman filter update, all values Q16.16 (P, Q, R >= 0). */
int32_t kf1_update_q16(kf1_q16_t *s, int32_t z)
{
    int32_t p = s->p + s->q;                                  /* predict   */
    int32_t k = (int32_t)(((int64_t)p << 16) / (p + s->r));   /* gain, Q16 */
    s->x += (int32_t)(((int64_t)k * (z - s->x)) >> 16);        /* update x  */
    s->p  = (int32_t)(((int64_t)(INT32_C(65536) - k) * p) >> 16);
    return s->x;
}

#endif /* BENCH_NO_INT64 */

#ifndef BENCH_NO_N32
/* ---- the same two functions without any 64-bit type (bit-exact) ---- */

/* (int32_t)(((int64_t)a * b) >> 16) from 16-bit halves: the >> 16 of the
 * full product is ah*bh*2^16 + ah*bl + al*bh + floor(al*bl / 2^16). */
static int32_t q16_mul(int32_t a, int32_t b)
{
    int16_t ah = (int16_t)(a >> 16), bh = (int16_t)(b >> 16);
    uint16_t al = (uint16_t)a, bl = (uint16_t)b;
    uint32_t r = (uint32_t)((int32_t)ah * bh) << 16;
    r += (uint32_t)((int32_t)ah * (int32_t)bl);
    r += (uint32_t)((int32_t)bh * (int32_t)al);
    r += ((uint32_t)al * bl) >> 16;
    return (int32_t)r;
}

/* floor(n * 2^16 / d) for 0 <= n <= d, d > 0: 16 steps of long division */
static int32_t q16_ratio(uint32_t n, uint32_t d)
{
    uint32_t q = 0;
    uint8_t i, carry;
    if (n >= d) return INT32_C(65536);
    for (i = 0; i < 16; i++) {
        carry = (uint8_t)(n >> 31);
        n <<= 1;
        q <<= 1;
        if (carry || n >= d) { n -= d; q |= 1u; }
    }
    return (int32_t)q;
}

int32_t poly2_q16_n32(const int32_t c[3], int32_t x)
{
    int32_t y = c[2];
    y = q16_mul(y, x) + c[1];
    y = q16_mul(y, x) + c[0];
    return y;
}

int32_t kf1_update_q16_n32(kf1_q16_t *s, int32_t z)
{
    int32_t p = s->p + s->q;
    int32_t k = q16_ratio((uint32_t)p, (uint32_t)(p + s->r));
    s->x += q16_mul(k, z - s->x);
    s->p  = q16_mul(INT32_C(65536) - k, p);
    return s->x;
}

#endif /* BENCH_NO_N32 */

float poly2_f(const float c[3], float x)
{
    return (c[2] * x + c[1]) * x + c[0];
}

float kf1_update_f(kf1_f_t *s, float z)
{
    float p = s->p + s->q;
    float k = p / (p + s->r);
    s->x += k * (z - s->x);
    s->p = (1.0f - k) * p;
    return s->x;
}
