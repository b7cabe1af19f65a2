/* rt_hwmul.c - multiply helpers for clang -mhwmult=f5series, using only the
 * 16x16 part of the multiplier (MPY, MPYS, MAC, OP2, RESLO, RESHI, SUMEXT).
 *
 * MPY_BASE: 0x04C0 on the MSP430F5510 (MPY32 module); mspdebug's simulated
 * multiplier sits at the classic 0x0130 with the same register offsets, so
 * build with -DMPY_BASE=0x0130 for the simulator.
 *
 * These helpers do not disable interrupts: an ISR that multiplies would
 * corrupt a multiplication in progress.  Wrap them (push SR; dint; nop ...
 * pop SR) if ISRs use the multiplier.
 *
 * With -mhwmult=f5series clang 14 calls all three with the *normal* C
 * convention (64-bit: a in R12:R15, b on the stack). */
#include <stdint.h>

#ifndef MPY_BASE
#define MPY_BASE 0x04C0
#endif
#define HWREG(off) (*(volatile uint16_t *)(MPY_BASE + (off)))
#define MPY    HWREG(0x0)   /* operand 1, unsigned multiply           */
#define MPYS   HWREG(0x2)   /* operand 1, signed multiply             */
#define MAC    HWREG(0x4)   /* operand 1, unsigned multiply-accumulate */
#define OP2    HWREG(0x8)   /* operand 2, writing it starts the op    */
#define RESLO  HWREG(0xA)
#define RESHI  HWREG(0xC)
#define SUMEXT HWREG(0xE)

int16_t __mspabi_mpyi_f5hw(int16_t a, int16_t b)
{
    MPY = (uint16_t)a;
    OP2 = (uint16_t)b;
    return (int16_t)RESLO;
}

/* low 32 bits of a*b: three 16x16 products */
static uint32_t mul32_lo(uint32_t a, uint32_t b)
{
    uint16_t a0 = (uint16_t)a, a1 = (uint16_t)(a >> 16);
    uint16_t b0 = (uint16_t)b, b1 = (uint16_t)(b >> 16);
    uint16_t lo, hi;
    MPY = a0; OP2 = b0;
    lo = RESLO; hi = RESHI;
    MPY = a0; OP2 = b1;
    MAC = a1; OP2 = b0;       /* RES = a0*b1 + a1*b0 (only RESLO used) */
    hi += RESLO;
    return ((uint32_t)hi << 16) | lo;
}

/* Fast paths: when both operands are zero-extended or both sign-extended
 * 16-bit values (C code writes a 16x16->32 product as (int32_t)x * y or
 * (uint32_t)x * y, and clang 14 has no widening multiply for the MSP430: it
 * calls this 32x32 helper), one 16x16 product gives the exact 32-bit result.
 * Added for the project (not in the shared recipe); checked on random and
 * edge operands by tests/test_mcu_toolchain.py. */
int32_t __mspabi_mpyl_f5hw(int32_t a, int32_t b)
{
    uint16_t a0 = (uint16_t)a, a1 = (uint16_t)((uint32_t)a >> 16);
    uint16_t b0 = (uint16_t)b, b1 = (uint16_t)((uint32_t)b >> 16);
    if ((a1 | b1) == 0u) {
        MPY = a0; OP2 = b0;
        return (int32_t)(((uint32_t)RESHI << 16) | RESLO);
    }
    if (a1 == ((int16_t)a0 < 0 ? 0xFFFFu : 0u) && b1 == ((int16_t)b0 < 0 ? 0xFFFFu : 0u)) {
        MPYS = a0; OP2 = b0;
        return (int32_t)(((uint32_t)RESHI << 16) | RESLO);
    }
    return (int32_t)mul32_lo((uint32_t)a, (uint32_t)b);
}

/* full unsigned 32x32 -> 64: four 16x16 products, column by column */
static uint64_t umul32x32(uint32_t a, uint32_t b)
{
    uint16_t a0 = (uint16_t)a, a1 = (uint16_t)(a >> 16);
    uint16_t b0 = (uint16_t)b, b1 = (uint16_t)(b >> 16);
    uint16_t r0, r1, r2, r3, c;
    MPY = a0; OP2 = b0;
    r0 = RESLO;
    RESLO = RESHI; RESHI = 0;          /* carry into column 1 */
    MAC = a0; OP2 = b1;                 /* cannot overflow 32 bits here */
    MAC = a1; OP2 = b0;
    c = SUMEXT;                         /* carry out of bit 31 (0 or 1) */
    r1 = RESLO;
    RESLO = RESHI; RESHI = c;           /* carry into column 2 */
    MAC = a1; OP2 = b1;
    r2 = RESLO; r3 = RESHI;
    return ((uint64_t)(((uint32_t)r3 << 16) | r2) << 32) | (((uint32_t)r1 << 16) | r0);
}

/* low 64 bits of a*b; fast path when both are sign-extended 32-bit values,
 * i.e. the usual (int64_t)x * y of two int32 */
int64_t __mspabi_mpyll_f5hw(int64_t a, int64_t b)
{
    uint32_t al = (uint32_t)a, ah = (uint32_t)((uint64_t)a >> 32);
    uint32_t bl = (uint32_t)b, bh = (uint32_t)((uint64_t)b >> 32);
    uint64_t r = umul32x32(al, bl);
    uint32_t cross;
    if ((ah == 0 || ah == 0xFFFFFFFFu) && (bh == 0 || bh == 0xFFFFFFFFu)) {
        cross = 0;
        if (ah) cross -= bl;
        if (bh) cross -= al;
    } else {
        cross = mul32_lo(al, bh) + mul32_lo(ah, bl);
    }
    return (int64_t)(r + ((uint64_t)cross << 32));
}
