/* rt_int.c - integer runtime helpers that clang's MSP430 back end calls
 * (MSP430 EABI names, SLAA534), plain C, no hardware multiplier.
 *
 * Rules for this file: never use *, /, % or a shift by a *variable* count on
 * 32- or 64-bit values here (clang would turn them into calls to these very
 * helpers).  Shifts by a constant are compiled inline and are fine.
 *
 * Helpers that take two 64-bit operands (__mspabi_mpyll, __mspabi_divlli,
 * __mspabi_divull, __mspabi_remlli, __mspabi_remull) use the EABI's special
 * convention (first operand R8:R11, second R12:R15); rt_builtin.S turns that
 * into an ordinary C call to the __rt_* functions at the end of this file. */
#include <stdint.h>
#include <stddef.h>

/* ---- multiply ------------------------------------------------------------ */
int16_t __mspabi_mpyi(int16_t a, int16_t b)
{
    uint16_t x = (uint16_t)a, y = (uint16_t)b, r = 0;
    while (y) {
        if (y & 1u) r += x;
        x <<= 1;
        y >>= 1;
    }
    return (int16_t)r;
}

/* low 32 bits of a*b (same for signed and unsigned operands): multiply the
 * magnitudes, looping over the smaller one, then fix the sign */
static uint32_t umul32_lo(uint32_t a, uint32_t b)
{
    uint32_t r = 0, t;
    uint8_t neg = 0;
    if (a & 0x80000000u) { a = 0u - a; neg ^= 1; }
    if (b & 0x80000000u) { b = 0u - b; neg ^= 1; }
    if (a < b) { t = a; a = b; b = t; }
    while (b) {
        if (b & 1u) r += a;
        a <<= 1;
        b >>= 1;
    }
    return neg ? 0u - r : r;
}

int32_t __mspabi_mpyl(int32_t a, int32_t b)
{
    return (int32_t)umul32_lo((uint32_t)a, (uint32_t)b);
}

/* full unsigned 32x32 -> 64 product, shift and add over the smaller operand */
static uint64_t umul32x32(uint32_t a, uint32_t b)
{
    uint64_t r = 0, x;
    uint32_t t;
    if (a < b) { t = a; a = b; b = t; }
    x = a;
    while (b) {
        if (b & 1u) r += x;
        x <<= 1;
        b >>= 1;
    }
    return r;
}

/* low 64 bits of a*b.  Fast path for the common "(int64_t)int32 * int32",
 * whose upper words are sign extensions: multiply the 32-bit magnitudes. */
uint64_t __rt_mpyll(uint64_t a, uint64_t b)
{
    uint32_t al = (uint32_t)a, ah = (uint32_t)(a >> 32);
    uint32_t bl = (uint32_t)b, bh = (uint32_t)(b >> 32);
    if (ah == (al & 0x80000000u ? 0xFFFFFFFFu : 0u) &&
        bh == (bl & 0x80000000u ? 0xFFFFFFFFu : 0u)) {
        uint8_t neg = 0;
        uint64_t r;
        if (ah) { al = 0u - al; neg ^= 1; }
        if (bh) { bl = 0u - bl; neg ^= 1; }
        r = umul32x32(al, bl);
        return neg ? 0u - r : r;
    }
    return umul32x32(al, bl) + ((uint64_t)(umul32_lo(al, bh) + umul32_lo(ah, bl)) << 32);
}

/* ---- shifts by a variable count: 16 at once if the count has that bit,
 * then one at a time (OP is <<= or >>=; a negative value is shifted right
 * arithmetically, as the helpers' contract says). */
#define SHIFT_REST(a, n, OP) do {               \
        if ((n) & 16) { (a) OP 16; (n) -= 16; } \
        while ((n)-- > 0) (a) OP 1;             \
    } while (0)

/* 32-bit: R12:R13 value, R14 count */
uint32_t __mspabi_slll(uint32_t a, int16_t n) { n &= 31; SHIFT_REST(a, n, <<=); return a; }
uint32_t __mspabi_srll(uint32_t a, int16_t n) { n &= 31; SHIFT_REST(a, n, >>=); return a; }
int32_t __mspabi_sral(int32_t a, int16_t n) { n &= 31; SHIFT_REST(a, n, >>=); return a; }

/* 64-bit shifts: clang 14 calls the libgcc names with the normal C
 * convention (value R12:R15, count on the stack); 32 at once first. */
int64_t __ashldi3(int64_t a, int n)
{
    uint64_t u = (uint64_t)a;
    n &= 63;
    if (n & 32) { u <<= 32; n -= 32; }
    SHIFT_REST(u, n, <<=);
    return (int64_t)u;
}

uint64_t __lshrdi3(uint64_t a, int n)
{
    n &= 63;
    if (n & 32) { a >>= 32; n -= 32; }
    SHIFT_REST(a, n, >>=);
    return a;
}

int64_t __ashrdi3(int64_t a, int n)
{
    n &= 63;
    if (n & 32) { a >>= 32; n -= 32; }
    SHIFT_REST(a, n, >>=);
    return a;
}

/* ---- division: shift-subtract as in libgcc's udivmodsi4 (first align the
 * divisor under the dividend, so small quotients take few steps); a zero
 * divisor gives 0, remainder n. */
#define DEFINE_UDIVMOD(name, U, TOP)                                 \
    static U name(U n, U d, U *rem)                                  \
    {                                                                \
        U bit = 1, q = 0;                                            \
        while (d < n && !(d & (TOP))) { d <<= 1; bit <<= 1; }        \
        while (bit) {                                                \
            if (n >= d) { n -= d; q |= bit; }                        \
            bit >>= 1;                                               \
            d >>= 1;                                                 \
        }                                                            \
        *rem = n;                                                    \
        return q;                                                    \
    }
DEFINE_UDIVMOD(udivmod_uint16_t, uint16_t, 0x8000u)
DEFINE_UDIVMOD(udivmod_uint32_t, uint32_t, 0x80000000u)
DEFINE_UDIVMOD(udivmod64_wide, uint64_t, 0x8000000000000000u)

static uint64_t udivmod_uint64_t(uint64_t n, uint64_t d, uint64_t *rem)
{
    uint32_t r32;
    uint64_t q;
    if ((n >> 32) || (d >> 32)) return udivmod64_wide(n, d, rem);
    q = udivmod_uint32_t((uint32_t)n, (uint32_t)d, &r32);   /* both fit in 32 bits */
    *rem = r32;
    return q;
}

/* Signed quotient and remainder from the unsigned ones, for each width:
 * magnitudes in, the quotient negative when the signs differ, the
 * remainder with the dividend's sign (C99 truncating division). */
#define DEFINE_SDIVMOD(S, U, udivmod)                                          \
    static S sdivmod_##S(S a, S b, S *rem)                                     \
    {                                                                          \
        U r, q = udivmod(a < 0 ? 0u - (U)a : (U)a, b < 0 ? 0u - (U)b : (U)b, &r); \
        *rem = (S)(a < 0 ? 0u - r : r);                                        \
        return (S)(((a < 0) != (b < 0)) ? 0u - q : q);                         \
    }
DEFINE_SDIVMOD(int16_t, uint16_t, udivmod_uint16_t)
DEFINE_SDIVMOD(int32_t, uint32_t, udivmod_uint32_t)
DEFINE_SDIVMOD(int64_t, uint64_t, udivmod_uint64_t)

/* The EABI's four division helpers of one width (a / b, a % b, unsigned and signed). */
#define DEFINE_DIV_HELPERS(divu, remu, divi, remi, U, S)                                       \
    U divu(U a, U b) { U r; return udivmod_##U(a, b, &r); }                                   \
    U remu(U a, U b) { U r; udivmod_##U(a, b, &r); return r; }                                \
    S divi(S a, S b) { S r; return sdivmod_##S(a, b, &r); }                                   \
    S remi(S a, S b) { S r; sdivmod_##S(a, b, &r); return r; }
DEFINE_DIV_HELPERS(__mspabi_divu, __mspabi_remu, __mspabi_divi, __mspabi_remi, uint16_t, int16_t)
DEFINE_DIV_HELPERS(__mspabi_divul, __mspabi_remul, __mspabi_divli, __mspabi_remli, uint32_t, int32_t)

/* 64-bit division: C-convention bodies; rt_builtin.S passes the divisor
 * (R12:R15) first and the dividend (pushed from R8:R11) second. */
uint64_t __rt_divull(uint64_t d, uint64_t n) { uint64_t r; return udivmod_uint64_t(n, d, &r); }
uint64_t __rt_remull(uint64_t d, uint64_t n) { uint64_t r; udivmod_uint64_t(n, d, &r); return r; }
int64_t __rt_divlli(int64_t d, int64_t n) { int64_t r; return sdivmod_int64_t(n, d, &r); }
int64_t __rt_remlli(int64_t d, int64_t n) { int64_t r; sdivmod_int64_t(n, d, &r); return r; }

/* ---- clang may emit these for struct copies / zeroing, even freestanding */
void *memcpy(void *dst, const void *src, size_t n)
{
    uint8_t *d = dst; const uint8_t *s = src;
    while (n--) *d++ = *s++;
    return dst;
}
void *memmove(void *dst, const void *src, size_t n)
{
    uint8_t *d = dst; const uint8_t *s = src;
    if (d < s) { while (n--) *d++ = *s++; }
    else { d += n; s += n; while (n--) *--d = *--s; }
    return dst;
}
void *memset(void *dst, int c, size_t n)
{
    uint8_t *d = dst;
    while (n--) *d++ = (uint8_t)c;
    return dst;
}
