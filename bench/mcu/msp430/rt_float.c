/* rt_float.c - float <-> int32 conversions for clang's MSP430 EABI calls.
 * The arithmetic (__mspabi_addf/subf/mpyf/divf/cmpf) comes from compiler-rt's
 * generic soft-float C files, compiled with -D__builtin_clz=__builtin_clzl and
 * bound to the __mspabi_ names at link time with ld.lld --defsym.
 * (compiler-rt's own floatsisf/fixsfsi assume a 32-bit int: not usable.)
 * Only constant shifts on 32-bit values here, or calls to the shift helpers. */
#include <stdint.h>

typedef union { float f; uint32_t u; } fbits;

static float u32_to_f(uint32_t a, uint32_t sign)
{
    fbits r;
    int16_t e = 31;
    uint32_t m, rest;
    if (a == 0) { r.u = sign; return r.f; }
    while (!(a & 0x80000000u)) { a <<= 1; e--; }     /* normalise */
    m = a >> 8;                                       /* 24 significant bits */
    rest = a & 0xFFu;                                 /* round to nearest even */
    if (rest > 0x80u || (rest == 0x80u && (m & 1u))) {
        m++;
        if (m == 0x01000000u) { m >>= 1; e++; }
    }
    r.u = sign | ((uint32_t)(uint16_t)(e + 127) << 23) | (m & 0x007FFFFFu);
    return r.f;
}

float __mspabi_fltlif(int32_t i)
{
    return i < 0 ? u32_to_f(0u - (uint32_t)i, 0x80000000u) : u32_to_f((uint32_t)i, 0);
}

float __mspabi_fltulf(uint32_t u) { return u32_to_f(u, 0); }

/* truncate toward zero; out of range (and NaN) saturates */
int32_t __mspabi_fixfli(float f)
{
    fbits v;
    int16_t e;
    uint32_t m;
    v.f = f;
    e = (int16_t)((v.u >> 23) & 0xFFu) - 127;
    if (e < 0) return 0;
    if (e >= 31) return (v.u & 0x80000000u) ? INT32_MIN : INT32_MAX;
    m = (v.u & 0x007FFFFFu) | 0x00800000u;
    m = e >= 23 ? m << (e - 23) : m >> (23 - e);
    return (v.u & 0x80000000u) ? -(int32_t)m : (int32_t)m;
}

uint32_t __mspabi_fixful(float f)
{
    fbits v;
    int16_t e;
    uint32_t m;
    v.f = f;
    if (v.u & 0x80000000u) return 0;
    e = (int16_t)((v.u >> 23) & 0xFFu) - 127;
    if (e < 0) return 0;
    if (e >= 32) return 0xFFFFFFFFu;
    m = (v.u & 0x007FFFFFu) | 0x00800000u;
    return e >= 23 ? m << (e - 23) : m >> (23 - e);
}
