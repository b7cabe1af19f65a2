/* sig_pwl_msp430.S - sig_pwl_eval_q16 (csrc/tcomp/sig_pwl.c) in MSP430
 * assembly for tables whose position mapping needs one 16x16 product:
 * recip = rh * 2^16 (low word 0), i.e. knots 2^16 / rh temperature units
 * apart - with rh a power of two, a power-of-two knot spacing, the segment
 * index a shift done by the multiplier.  Any other recip is handed to the
 * portable sig_pwl_eval_q16 (same arguments).  Same results bit for bit
 * (tests/test_mcu_port.py, bench/mcu_cost.py: every output and status
 * against the host C in mspdebug's simulator).
 *
 *   sig_status sig_pwl_eval_msp430(const sig_pwl_q16 *p, int16_t t, int32_t *out_q16);
 *   R12 p, R13 t, R14 out -> R12 status
 *
 *   d = clamp(t) - t_lo; d * rh on the multiplier: RESHI = segment,
 *   RESLO = position fraction (Q16); frac = RESLO >> 4 (Q12);
 *   acc = lo * (4096 - frac) + hi * frac   (MPYS + MACS, = lo 2^12 + (hi - lo) frac)
 *   out = acc scaled by 2^(4 - value_frac) (arithmetic shifts: floor).
 * Offsets of sig_pwl_q16 are checked in sig_pwl_msp430.h.  MPY_BASE as in
 * sig_tcomp16_msp430.S; interrupts must not use the multiplier meanwhile. */
#include "sig_msp430_asm.h"
#define TABLE   0
#define RECIP_LO 2
#define RECIP_HI 4
#define T_LO    6
#define T_HI    8
#define N_KNOTS 12
#define VFRAC   13

/* The segment of temperature t (register t, clamped first: below/above are
 * the caller's clamping code, which jumps back to `clamped`): d = t - t_lo
 * times recip's high word on the multiplier, segment + 1 into seg, the
 * position fraction (Q16) into frac; on to `last` when segment + 1 >=
 * n_knots (exactly on the last knot).  Both entry points use it. */
    .macro PWL_SEGMENT t, seg, frac, below, above, clamped, last
    cmp     T_LO(r12), \t
    jl      \below
    cmp     \t, T_HI(r12)
    jl      \above
\clamped:
    sub     T_LO(r12), \t          ; d
    mov     \t, &MPY
    mov     RECIP_HI(r12), &OP2
    mov     &RESHI, \seg           ; segment
    mov     &RESLO, \frac          ; fraction, Q16
    inc     \seg
    cmp.b   N_KNOTS(r12), \seg
    jhs     \last
    .endm

/* the fraction Q16 -> Q12: an unsigned shift right by 4 */
    .macro FRAC_Q12 frac
    clrc
    rrc     \frac
    rra     \frac
    rra     \frac
    rra     \frac
    .endm

    .section .text.sig_pwl_eval_msp430,"ax",@progbits
    .global sig_pwl_eval_msp430
    .type   sig_pwl_eval_msp430,@function
    .p2align 1
sig_pwl_eval_msp430:
    tst     r12
    jeq     .Lerr
    tst     r14
    jeq     .Lerr
    mov     TABLE(r12), r15
    tst     r15
    jeq     .Lerr
    tst     RECIP_LO(r12)
    jne     .Lportable
    push    r10
    clr     r11                     ; status
    PWL_SEGMENT r13, r13, r10, .Lbelow, .Labove, .Lclamped, .Llast
    rla     r13
    add     r13, r15                ; &table[segment + 1]
    FRAC_Q12 r10
    mov     -2(r15), &MPYS          ; lo * (4096 - frac)
    mov     #4096, r13
    sub     r10, r13
    mov     r13, &OP2
    mov     @r15, &MACS             ; + hi * frac
    mov     r10, &OP2
.Lscale:
    mov     &RESLO, r13
    mov     &RESHI, r15             ; acc, value_frac + 12 fraction bits
    mov.b   VFRAC(r12), r10
    sub     #4, r10
    jeq     .Lstore
    jl      .Lleft
.Lright:                            ; floor(acc / 2^(value_frac - 4))
    rra     r15
    rrc     r13
    dec     r10
    jnz     .Lright
.Lstore:
    mov     r13, 0(r14)
    mov     r15, 2(r14)
    mov     r11, r12
    pop     r10
    ret
.Lleft:                             ; acc * 2^(4 - value_frac), exact
    rla     r13
    rlc     r15
    inc     r10
    jnz     .Lleft
    jmp     .Lstore
.Llast:                             ; acc = table[n_knots - 1] * 2^12
    mov.b   N_KNOTS(r12), r13
    rla     r13
    add     r13, r15
    mov     -2(r15), &MPYS
    mov     #4096, &OP2
    jmp     .Lscale
.Lbelow:
    mov     T_LO(r12), r13
    mov     #1, r11
    jmp     .Lclamped
.Labove:
    mov     T_HI(r12), r13
    mov     #1, r11
    jmp     .Lclamped
.Lportable:
    br      #sig_pwl_eval_q16
.Lerr:
    mov     #-1, r12
    ret
    .size   sig_pwl_eval_msp430, .-sig_pwl_eval_msp430

/* sig_status sig_pwl_eval_axes_msp430(const sig_pwl_q16 *p, uint8_t n_axes,
 *                                     int16_t t, int32_t *out_q16);
 *   R12 p[0..n_axes-1], R13 n_axes, R14 t, R15 out[0..n_axes-1] -> R12
 * The tables of one coefficient image (sig_pwl_load_image: the same knots,
 * range and recip for every axis, own table and value_frac): the clamp, the
 * segment and the fraction once, then per axis one MPYS + MACS and the
 * scaling.  out[a] == sig_pwl_eval_q16(&p[a], t) for every axis; the
 * status is theirs (SIG_WARN_CLAMPED or SIG_OK).  SIG_ERR_ARG for NULL
 * pointers or n_axes == 0 (a NULL table stops at that axis, the earlier
 * outputs written).  When p[0].recip has a non-zero low word every axis
 * goes through the portable sig_pwl_eval_q16.  The shared fields of
 * p[1..] are not read: they must equal p[0]'s. */
#define PWL_SIZE 14
    .section .text.sig_pwl_eval_axes_msp430,"ax",@progbits
    .global sig_pwl_eval_axes_msp430
    .type   sig_pwl_eval_axes_msp430,@function
    .p2align 1
sig_pwl_eval_axes_msp430:
    tst     r12
    jeq     .Laerr
    tst     r15
    jeq     .Laerr
    and     #0xFF, r13
    jeq     .Laerr
    PUSH_R10_TO_R6
    mov     r13, r7                 ; axes left
    tst     RECIP_LO(r12)
    jne     .Laportable
    clr     r11
    PWL_SEGMENT r14, r9, r10, .Labelow, .Laabove, .Laclamped, .Lalast
    rla     r9                      ; byte offset of table[segment + 1]
    FRAC_Q12 r10
    mov     #4096, r8
    sub     r10, r8                 ; 4096 - frac
.Laxis_loop:
    mov     @r12, r6                ; this axis' table
    tst     r6
    jeq     .Lanull
    add     r9, r6
    mov     -2(r6), &MPYS           ; lo * (4096 - frac)
    mov     r8, &OP2
    mov     @r6, &MACS              ; + hi * frac
    mov     r10, &OP2
    mov     &RESLO, r13
    mov     &RESHI, r14
    mov.b   VFRAC(r12), r6          ; scale by 2^(4 - value_frac): jump into the
    rla     r6                      ; unrolled shifts, value_frac - 4 pairs from
    mov     .Lvf_entry(r6), r0      ; the end (floor: arithmetic right shifts)
.Laleft_by4:                        ; value_frac 0..3: exact left shifts
    rla     r13
    rlc     r14
    rla     r13
    rlc     r14
    rla     r13
    rlc     r14
    rla     r13
    rlc     r14
    jmp     .Lastore
.Laright_by11:
    .rept   11
    rra     r14
    rrc     r13
    .endr
.Lastore:
    mov     r13, 0(r15)
    mov     r14, 2(r15)
    add     #4, r15
    add     #PWL_SIZE, r12
    dec     r7
    jnz     .Laxis_loop
    mov     r11, r12
.Lapop:
    POP_R6_TO_R10
    ret
.Lalast:                            ; on the last knot: hi = table[n - 1], frac = 1
    mov.b   N_KNOTS(r12), r9
    dec     r9
    rla     r9
    mov     #4096, r10
    clr     r8
    jmp     .Laxis_loop
.Labelow:
    mov     T_LO(r12), r14
    mov     #1, r11
    jmp     .Laclamped
.Laabove:
    mov     T_HI(r12), r14
    mov     #1, r11
    jmp     .Laclamped
.Lanull:
    mov     #-1, r12
    jmp     .Lapop
.Laportable:                        ; axis by axis through the C (status: OR)
    mov     r12, r8
    mov     r14, r9
    mov     r15, r10
    clr     r6
.Laport_loop:
    mov     r8, r12
    mov     r9, r13
    mov     r10, r14
    call    #sig_pwl_eval_q16
    tst     r12
    jl      .Lapop
    bis     r12, r6
    add     #PWL_SIZE, r8
    add     #4, r10
    dec     r7
    jnz     .Laport_loop
    mov     r6, r12
    jmp     .Lapop
.Laerr:
    mov     #-1, r12
    ret
    .p2align 1
.Lvf_entry:                         ; entry per value_frac 0..15 (4 bytes per shift pair)
    .word   .Laleft_by4, .Laleft_by4 + 4, .Laleft_by4 + 8, .Laleft_by4 + 12, .Lastore
    .word   .Lastore - 4, .Lastore - 8, .Lastore - 12, .Lastore - 16, .Lastore - 20
    .word   .Lastore - 24, .Lastore - 28, .Lastore - 32, .Lastore - 36, .Lastore - 40
    .word   .Lastore - 44
    .size   sig_pwl_eval_axes_msp430, .-sig_pwl_eval_axes_msp430
