/* hx711_peers.h - the smoothing of the Arduino HX711 libraries people use,
 * in C for the cost comparison with the chain on the same chip.  Written
 * from their published sources (bench/lab/studies/peers.py names the
 * commits, files and defaults); none of their code is copied.  Inputs are the codes
 * those libraries hold: 24-bit offset binary (HX711 two's complement ^
 * 0x800000), non-negative. */
#ifndef HX711_PEERS_H
#define HX711_PEERS_H

#include <stdint.h>

/* olkal/HX711_ADC: SAMPLES 16 + IGN_HIGH_SAMPLE 1 + IGN_LOW_SAMPLE 1 */
#define HX711_ADC_SET 18u
#define HX711_ADC_DIVB 4u
typedef struct {
    int32_t set[HX711_ADC_SET];   /* the library's dataSampleSet (long) */
    uint8_t index;                /* readIndex */
} hx711_adc_state;

void hx711_adc_init(hx711_adc_state *s, int32_t first);
/* conversion24bit()'s ring insert + getData()'s smoothedData() >> DIVB */
int32_t hx711_adc_step(hx711_adc_state *s, int32_t code);

/* bogde/HX711 read_average(times = 10): long sum / times */
#define BOGDE_TIMES 10u
int32_t bogde_read_average(const int32_t *codes, uint8_t times);

/* RobTillaart/HX711 read_median / read_medavg (times = 7, at most 15):
 * the samples as float (read() returns float), insertion sort */
#define ROB_TIMES 7u
float rob_read_median(const int32_t *codes, uint8_t times);
float rob_read_medavg(const int32_t *codes, uint8_t times);

#endif
