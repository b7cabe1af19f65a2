/* sig_tcomp16_msp430.S - sig_tcomp16_apply_q (csrc/tcomp/sig_tcomp16.c) in
 * MSP430 assembly on the 16x16 hardware multiplier: the same results bit for
 * bit (bench/mcu_cost.py and tests/test_mcu_port.py check every output and
 * status against the host C in mspdebug's simulator).
 *
 *   sig_status sig_tcomp16_apply_msp430(const sig_tcomp16_q *m, int16_t t,
 *                                       const int16_t *in, int16_t *out);
 *   R12 m, R13 t, R14 in, R15 out -> R12 status (MSP430 EABI; R4-R10 saved)
 *
 * Each Horner level is one multiply-accumulate: RESLO/RESHI preloaded with
 * the level's constant straight from the coefficient stream (@R12+), operand
 * 1 to MAC (inner levels, unsigned) or MACS (last level, signed), operand 2
 * starts it, the high result word is the level's value.  Orders 2 (the
 * common case) run an unrolled axis loop; orders 1, 3-5 a counted inner loop.
 * The saturating subtract is one SUB with its V flag.
 *
 * The struct offsets below are those of sig_tcomp16_q; sig_tcomp16_msp430.h
 * checks them at compile time.  MPY_BASE: 0x04C0 on the F5510 (MPY32's 16x16
 * registers), 0x0130 for mspdebug 0.22's simulated multiplier.  Interrupt
 * handlers must not use the multiplier during a call (as sig_port_msp430.h). */
#include "sig_msp430_asm.h"
#define T_LO   66
#define T_HI   68
#define W_SHIFT 70
#define ORDER  71
#define N_AXES 72

/* mov @Rn+, &addr: a valid MSP430 instruction (As = 3, absolute destination)
 * that clang 14's assembler does not parse, so spelt as its two words */
    .macro  mov_postinc_abs reg, addr
    .word   0x40B2 | (\reg << 8)
    .word   \addr
    .endm

    .section .text.sig_tcomp16_apply_msp430,"ax",@progbits
    .global sig_tcomp16_apply_msp430
    .type   sig_tcomp16_apply_msp430,@function
    .p2align 1
sig_tcomp16_apply_msp430:
    tst     r12
    jeq     .Lerr
    tst     r14
    jeq     .Lerr
    tst     r15
    jeq     .Lerr
    PUSH_R10_TO_R6
    clr     r11                     ; status
    /* v = clamp(t) - t_lo */
    cmp     T_LO(r12), r13
    jl      .Lbelow
    cmp     r13, T_HI(r12)
    jl      .Labove
    sub     T_LO(r12), r13
    jmp     .Lhave_v
.Lbelow:
    clr     r13
    mov     #1, r11
    jmp     .Lhave_v
.Labove:
    mov     T_HI(r12), r13
    sub     T_LO(r12), r13
    mov     #1, r11
.Lhave_v:
    /* w = v << w_shift (r10), w/2 (r9) */
    mov     r13, r10
    mov.b   W_SHIFT(r12), r9
    tst     r9
    jz      .Lw_done
.Lw_loop:
    rla     r10
    dec     r9
    jnz     .Lw_loop
.Lw_done:
    mov     r10, r9
    clrc
    rrc     r9
    /* r7 = end of in[]; r8 = order - 1 inner levels; order 1: x = v ^ 0x8000 */
    mov.b   N_AXES(r12), r7
    rla     r7
    add     r14, r7
    mov.b   ORDER(r12), r8
    dec     r8
    jz      .Lorder1
    cmp     #1, r8
    jne     .Lgeneral

/* ---- order 2: one inner level, one last level per axis ---- */
.Laxis2:
    mov_postinc_abs 12, MAC             ; operand 1 first: the RESLO/RESHI preload below
    mov_postinc_abs 12, RESLO           ; does not depend on it (the MAC starts at OP2)
    mov_postinc_abs 12, RESHI
    mov     r10, &OP2
    mov     &RESHI, r6
    sub     r9, r6                  ; h_1 (two's complement) for the signed level
    mov_postinc_abs 12, RESLO
    mov_postinc_abs 12, RESHI
    mov     r6, &MACS
    mov     r13, &OP2
    mov     &RESHI, r6              ; corr + 2^15
    xor     #0x8000, r6             ; corr
    mov     @r14+, r8
    sub     r6, r8                  ; in - corr, V on overflow
    bit     #0x100, r2
    jnz     .Lsat2
.Lstore2:
    mov     r8, 0(r15)
    incd    r15
    cmp     r7, r14
    jne     .Laxis2
    jmp     .Ldone

.Lsat2:
    bis     #2, r11
    mov     #0x7FFF, r8
    tst     -2(r14)
    jge     .Lstore2
    mov     #0x8000, r8
    jmp     .Lstore2

/* ---- order 1: x = v - 2^15 ---- */
.Lorder1:
    xor     #0x8000, r13
/* ---- orders 1, 3..5: r8 inner levels, counted in r5 ---- */
.Lgeneral:
    push    r5
.Laxis:
    mov     @r12+, r6               ; u = top
    mov     r8, r5
    tst     r5
    jz      .Llast
.Linner:
    mov     r6, &MAC
    mov_postinc_abs 12, RESLO
    mov_postinc_abs 12, RESHI
    mov     r10, &OP2
    mov     &RESHI, r6
    sub     r9, r6
    dec     r5
    jnz     .Linner
.Llast:
    mov_postinc_abs 12, RESLO
    mov_postinc_abs 12, RESHI
    mov     r6, &MACS
    mov     r13, &OP2
    mov     &RESHI, r6
    xor     #0x8000, r6
    mov     @r14+, r5
    sub     r6, r5
    bit     #0x100, r2
    jnz     .Lsat
.Lstore:
    mov     r5, 0(r15)
    incd    r15
    cmp     r7, r14
    jne     .Laxis
    pop     r5
    jmp     .Ldone

.Lsat:
    bis     #2, r11
    mov     #0x7FFF, r5
    tst     -2(r14)
    jge     .Lstore
    mov     #0x8000, r5
    jmp     .Lstore

.Ldone:
    mov     r11, r12
    POP_R6_TO_R10
    ret
.Lerr:
    mov     #-1, r12
    ret
    .size   sig_tcomp16_apply_msp430, .-sig_tcomp16_apply_msp430
