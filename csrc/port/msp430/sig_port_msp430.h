/* sig_port_msp430.h - csrc/include/sig_port.h hooks on the MSP430's 16x16 hardware
 * multiplier, as plain C volatile accesses (no assembly).  A firmware build
 * selects it with
 *     -DSIG_PORT_HEADER='"sig_port_msp430.h"' -I bench/mcu/msp430
 * (bench/mcu_cost.py: the fixed16_inline rows; the fixed16 rows leave it out
 * and clang calls __mspabi_mpyl_f5hw of rt_hwmul.c instead).
 *
 * MPY_BASE: 0x04C0 on the MSP430F5510 (MPY32 module, the same 16x16
 * registers at the same offsets); mspdebug 0.22's simulated multiplier is at
 * 0x0130: build with -DMPY_BASE=0x0130 for the simulator (same instructions,
 * same cycles).  A build for 0x04C0 run in that simulator reads RAM instead
 * of results: the bench checks every output against the host C.
 *
 * One multiply-accumulate: preload the 32-bit result (RESLO, RESHI) with the
 * constant's two words,
 * write operand 1 to MAC (unsigned) or MACS (signed), write OP2 (starts the
 * operation), read RESHI.  The multiplier does the 32-bit add and its carry;
 * the low result word is never read.
 *
 * Interrupts: as any code that drives the memory-mapped multiplier without
 * disabling interrupts (rt_hwmul.c's helpers too), these hooks assume that no
 * interrupt handler uses the multiplier while a compensation call runs.
 * Saving RESLO/RESHI/SUMEXT in a handler is not enough on the classic 16x16
 * multiplier: the operation selected by the operand-1 address (MAC, MACS)
 * cannot be read back.  If handlers multiply, call the compensation with
 * interrupts disabled (one call: 272-644 cycles, orders 1-5, 3 axes). */
#ifndef SIG_PORT_MSP430_H
#define SIG_PORT_MSP430_H

#include <stdint.h>

#ifndef MPY_BASE
#define MPY_BASE 0x04C0
#endif
#define SIG_MSP430_MPY_REG(off) (*(volatile uint16_t *)(MPY_BASE + (off)))
#define SIG_MSP430_MAC   SIG_MSP430_MPY_REG(0x4)   /* operand 1, unsigned multiply-accumulate */
#define SIG_MSP430_MACS  SIG_MSP430_MPY_REG(0x6)   /* operand 1, signed multiply-accumulate */
#define SIG_MSP430_OP2   SIG_MSP430_MPY_REG(0x8)   /* operand 2: writing it starts the operation */
#define SIG_MSP430_RESLO SIG_MSP430_MPY_REG(0xA)
#define SIG_MSP430_RESHI SIG_MSP430_MPY_REG(0xC)

/* high word of a * b + (c[1]:c[0]) on the multiplier: `op1` is the
 * operand-1 register that picks the operation (MAC unsigned, MACS signed:
 * a, b then two's-complement int16 bits); inlined with a constant register,
 * so each use is the four moves and the read. */
static inline uint16_t sig_msp430_muladd_hi(volatile uint16_t *op1, uint16_t a, uint16_t b,
                                            const uint16_t *c)
{
    SIG_MSP430_RESLO = c[0];
    SIG_MSP430_RESHI = c[1];
    *op1 = a;
    SIG_MSP430_OP2 = b;
    return SIG_MSP430_RESHI;
}

#define SIG_MULADD_HI_U16(a, b, c) sig_msp430_muladd_hi(&SIG_MSP430_MAC, (a), (b), (c))
#define SIG_MULADD_HI_S16(a, b, c) sig_msp430_muladd_hi(&SIG_MSP430_MACS, (a), (b), (c))

#endif /* SIG_PORT_MSP430_H */
