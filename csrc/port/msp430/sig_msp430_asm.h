/* sig_msp430_asm.h - what the MSP430 port's assembly files share: the
 * multiplier's registers and the save/restore of the callee-saved registers
 * R6-R10 (MSP430 EABI).  Included by the .S files after the preprocessor's
 * MPY_BASE (0x04C0 on the F5510: MPY32's 16x16 registers; 0x0130 for
 * mspdebug 0.22's simulated multiplier). */
#ifndef MPY_BASE
#define MPY_BASE 0x04C0
#endif
    .set MPY,   MPY_BASE + 0x0
    .set MPYS,  MPY_BASE + 0x2
    .set MAC,   MPY_BASE + 0x4
    .set MACS,  MPY_BASE + 0x6
    .set OP2,   MPY_BASE + 0x8
    .set RESLO, MPY_BASE + 0xA
    .set RESHI, MPY_BASE + 0xC

    .macro  PUSH_R10_TO_R6
    push    r10
    push    r9
    push    r8
    push    r7
    push    r6
    .endm

    .macro  POP_R6_TO_R10
    pop     r6
    pop     r7
    pop     r8
    pop     r9
    pop     r10
    .endm
