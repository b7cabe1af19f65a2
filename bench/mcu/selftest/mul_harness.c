/* mul_harness.c - products of operand pairs through the runtime's 32-bit
 * multiply helper (random, sign-extended 16-bit and edge operands, from the
 * generated mul_vectors.h); the test compares them with Python. */
#include <stdint.h>
#include "mul_vectors.h"

int32_t prod[MUL_N];
volatile uint8_t bench_mark;
#if defined(__clang__) || defined(__GNUC__)
__attribute__((noinline))
#endif
void bench_done(void) { bench_mark = 3; }

int main(void)
{
    uint16_t i;
    for (i = 0; i < MUL_N; i++) prod[i] = mul_a[i] * mul_b[i];
    bench_done();
    return 0;
}
