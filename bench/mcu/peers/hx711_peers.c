/* hx711_peers.c - see hx711_peers.h */
#include "hx711_peers.h"

void hx711_adc_init(hx711_adc_state *s, int32_t first)
{
    uint8_t r;
    for (r = 0; r < HX711_ADC_SET; r++)
        s->set[r] = first;
    s->index = 0;
}

int32_t hx711_adc_step(hx711_adc_state *s, int32_t code)
{
    int32_t data = 0, lo = INT32_C(0xFFFFFF), hi = 0;
    uint8_t r;
    s->index = (uint8_t)(s->index == HX711_ADC_SET - 1u ? 0u : s->index + 1u);
    s->set[s->index] = code;
    for (r = 0; r < HX711_ADC_SET; r++) {
        if (lo > s->set[r]) lo = s->set[r];
        if (hi < s->set[r]) hi = s->set[r];
        data += s->set[r];
    }
    data -= lo + hi;
    return (int32_t)((uint32_t)data >> HX711_ADC_DIVB);   /* codes >= 0: a plain shift */
}

int32_t bogde_read_average(const int32_t *codes, uint8_t times)
{
    int32_t sum = 0;
    uint8_t i;
    for (i = 0; i < times; i++)
        sum += codes[i];
    return sum / times;
}

static uint8_t rob_sorted(float *v, const int32_t *codes, uint8_t times)
{
    uint8_t t, z;
    float temp;
    if (times > 15u) times = 15u;
    if (times < 3u) times = 3u;
    for (t = 0; t < times; t++)
        v[t] = (float)codes[t];
    for (t = 1; t < times; t++) {
        z = t;
        temp = v[z];
        while (z > 0u && temp < v[z - 1u]) {
            v[z] = v[z - 1u];
            z--;
        }
        v[z] = temp;
    }
    return times;
}

float rob_read_median(const int32_t *codes, uint8_t times)
{
    float v[15];
    times = rob_sorted(v, codes, times);
    if (times & 1u) return v[times / 2u];
    return (v[times / 2u] + v[times / 2u + 1u]) / 2.0f;
}

float rob_read_medavg(const int32_t *codes, uint8_t times)
{
    float v[15], sum = 0.0f;
    uint8_t i, count = 0, first, last;
    times = rob_sorted(v, codes, times);
    first = (uint8_t)((times + 2u) / 4u);
    last = (uint8_t)(times - first - 1);   /* first <= (15 + 2) / 4 < times */
    for (i = first; i <= last; i++) {
        sum += v[i];
        count++;
    }
    return sum / (float)count;
}
