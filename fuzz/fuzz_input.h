/* fuzz_input.h - take typed values off the front of a libFuzzer input.
 *
 * Values are taken little-endian from the raw bytes; when the input runs
 * out, every take returns 0, so a harness never reads past the buffer and
 * short inputs still exercise the code.  Floats are taken from raw bits, so
 * NaN (quiet and signalling), +-inf, subnormals and -0 all occur. */
#ifndef FUZZ_INPUT_H
#define FUZZ_INPUT_H

#include <stdint.h>
#include <stddef.h>
#include <string.h>

typedef struct {
    const uint8_t *data;
    size_t size;
    size_t pos;
} fuzz_input;

static inline fuzz_input fuzz_input_make(const uint8_t *data, size_t size)
{
    fuzz_input in = {data, size, 0};
    return in;
}

static inline size_t fuzz_left(const fuzz_input *in) { return in->size - in->pos; }

static inline uint32_t fuzz_take_bits(fuzz_input *in, unsigned nbytes)
{
    uint32_t v = 0;
    unsigned i;
    for (i = 0; i < nbytes && in->pos < in->size; i++)
        v |= (uint32_t)in->data[in->pos++] << (8 * i);
    return v;
}

static inline uint8_t fuzz_u8(fuzz_input *in) { return (uint8_t)fuzz_take_bits(in, 1); }
static inline uint16_t fuzz_u16(fuzz_input *in) { return (uint16_t)fuzz_take_bits(in, 2); }
static inline int16_t fuzz_i16(fuzz_input *in) { return (int16_t)fuzz_take_bits(in, 2); }
static inline int32_t fuzz_i32(fuzz_input *in) { return (int32_t)fuzz_take_bits(in, 4); }

static inline float fuzz_f32(fuzz_input *in)
{
    uint32_t bits = fuzz_take_bits(in, 4);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

static inline double fuzz_f64(fuzz_input *in)
{
    uint64_t bits = (uint64_t)fuzz_take_bits(in, 4);
    double d;
    bits |= (uint64_t)fuzz_take_bits(in, 4) << 32;
    memcpy(&d, &bits, sizeof d);
    return d;
}

/* An int32 that is a rail or near one more often than uniform bits would
 * give: the selector byte picks INT32_MIN/MAX, +-1 of them, 0, or raw bits. */
static inline int32_t fuzz_i32_edgy(fuzz_input *in)
{
    switch (fuzz_u8(in) & 7u) {
    case 0: return INT32_MIN;
    case 1: return INT32_MAX;
    case 2: return INT32_MIN + 1;
    case 3: return INT32_MAX - 1;
    case 4: return 0;
    default: return fuzz_i32(in);
    }
}

/* The float type the core was built with (sig_real), taken from raw bits. */
#ifdef SIG_REAL_DOUBLE
#define fuzz_real fuzz_f64
#else
#define fuzz_real fuzz_f32
#endif

#endif /* FUZZ_INPUT_H */
