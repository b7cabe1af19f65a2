/* harness.c - calls each test function once; results land in globals that
 * the simulator script reads back.  Inputs live in RAM (.data) so nothing
 * can be constant-folded. */
#include <stdint.h>
#include "bench_funcs.h"
#include "../harness/bench_marks.h"

int32_t coef_q16[3] = { INT32_C(210371), INT32_C(-29930), INT32_C(806) };  /* 3.21, -0.4567, 0.0123 */
int32_t x_q16 = INT32_C(1536819);                                          /* 23.45 */
kf1_q16_t kf_q16 = { INT32_C(6553600), INT32_C(65536), INT32_C(655), INT32_C(32768) };
kf1_q16_t kf_q16b = { INT32_C(6553600), INT32_C(65536), INT32_C(655), INT32_C(32768) };
int32_t z_q16 = INT32_C(6651904);                                          /* 101.5 */

float coef_f[3] = { 3.21f, -0.4567f, 0.0123f };
float x_f = 23.45f;
kf1_f_t kf_f = { 100.0f, 1.0f, 0.01f, 0.5f };
float z_f = 101.5f;

int32_t res_poly_q16, res_kf_q16, res_poly_n32, res_kf_n32;
float res_poly_f, res_kf_f;

/* The 8051 run stops at bench_done: the program has finished. */

int main(void)
{
#ifndef BENCH_NO_INT64
    res_poly_q16 = poly2_q16(coef_q16, x_q16);
    res_kf_q16 = kf1_update_q16(&kf_q16, z_q16);
#endif
#ifndef BENCH_NO_N32
    res_poly_n32 = poly2_q16_n32(coef_q16, x_q16);
    res_kf_n32 = kf1_update_q16_n32(&kf_q16b, z_q16);
#endif
    res_poly_f = poly2_f(coef_f, x_f);
    res_kf_f = kf1_update_f(&kf_f, z_f);
    bench_done();
    return 0;
}
