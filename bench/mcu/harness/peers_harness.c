/* peers_harness.c - one HX711 library's smoothing (bench/mcu/peers) over
 * the vectors of peers_vectors.h, one output per sample: HX711_ADC steps
 * its ring; the block reads (bogde, RobTillaart) are called on the window
 * of their last `times` samples, as a user calling them once per output
 * would feed them.  PEER_HX711_ADC, PEER_BOGDE, PEER_MEDIAN or PEER_MEDAVG
 * selects one.  The call counted is one more output after the batch. */
#include <stdint.h>
#include "hx711_peers.h"
#include "peers_vectors.h"

#include "bench_marks.h"

#if defined(PEER_MEDIAN) || defined(PEER_MEDAVG)
typedef float out_t;
#else
typedef int32_t out_t;
#endif

out_t vec_out[PV_N];
out_t one_out;
#ifdef PEER_HX711_ADC
hx711_adc_state peer;
#define OUTPUT(i) hx711_adc_step(&peer, pv_codes[(i)])
#elif defined(PEER_BOGDE)
#define WINDOW BOGDE_TIMES
#define OUTPUT(i) bogde_read_average(&pv_codes[(i) - WINDOW + 1u], WINDOW)
#elif defined(PEER_MEDIAN)
#define WINDOW ROB_TIMES
#define OUTPUT(i) rob_read_median(&pv_codes[(i) - WINDOW + 1u], WINDOW)
#else
#define WINDOW ROB_TIMES
#define OUTPUT(i) rob_read_medavg(&pv_codes[(i) - WINDOW + 1u], WINDOW)
#endif
#ifndef WINDOW
#define WINDOW 1u
#endif

NOINLINE void run_batch(void)
{
    uint16_t i;
    bench_start();
    for (i = WINDOW - 1u; i < PV_N; i++)
        vec_out[i] = OUTPUT(i);
    bench_stop();
}

int main(void)
{
#ifdef PEER_HX711_ADC
    hx711_adc_init(&peer, pv_codes[0]);
#endif
    run_batch();
    BENCH_CALL(one_out = OUTPUT(PV_N - 1u));
    bench_done();
    return 0;
}
