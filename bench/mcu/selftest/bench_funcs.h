#ifndef BENCH_FUNCS_H
#define BENCH_FUNCS_H
#include <stdint.h>
typedef struct { int32_t x, p, q, r; } kf1_q16_t;
typedef struct { float x, p, q, r; } kf1_f_t;
int32_t poly2_q16(const int32_t c[3], int32_t x);
int32_t kf1_update_q16(kf1_q16_t *s, int32_t z);
int32_t poly2_q16_n32(const int32_t c[3], int32_t x);
int32_t kf1_update_q16_n32(kf1_q16_t *s, int32_t z);
float poly2_f(const float c[3], float x);
float kf1_update_f(kf1_f_t *s, float z);
#endif
