/* harness_loop.c - N calls between two marker functions. */
#include <stdint.h>
#include "../harness/bench_marks.h"   /* NOINLINE and the marker functions */
#include "bench_funcs.h"
#include "../harness/bench_marks.h"
#define N 8
int32_t z[N] = { INT32_C(6651904), INT32_C(6619136), INT32_C(6684672), INT32_C(6553600),
                 INT32_C(6560000), INT32_C(6600000), INT32_C(6590000), INT32_C(6610000) };
kf1_q16_t kf = { INT32_C(6553600), INT32_C(65536), INT32_C(655), INT32_C(32768) };
volatile int32_t out;
int main(void)
{
    uint8_t i;
    bench_start();
    for (i = 0; i < N; i++) out = kf1_update_q16_n32(&kf, z[i]);
    bench_stop();
    bench_done();
    return 0;
}
