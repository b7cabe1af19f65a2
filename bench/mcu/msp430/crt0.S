/* crt0.S - minimal MSP430F5510 start-up for clang/ld.lld (no libc). */
        .section .text.crt0,"ax",@progbits
        .global _start
        .type   _start,@function
_start:
        mov     #__stack_top, r1        ; stack at the top of RAM
        mov     #0x5a80, &0x015c        ; WDTCTL = WDTPW | WDTHOLD (F5xx address)
        ; copy .data initial values from flash (LMA) to RAM (VMA)
        mov     #__data_load, r12
        mov     #__data_start, r13
1:      cmp     #__data_end, r13
        jhs     2f
        mov     @r12+, r14
        mov     r14, 0(r13)
        incd    r13
        jmp     1b
        ; zero .bss
2:      mov     #__bss_start, r13
3:      cmp     #__bss_end, r13
        jhs     4f
        clr     0(r13)
        incd    r13
        jmp     3b
4:      call    #main
        .global _exit
_exit:                                  ; break here: the program has ended
        jmp     _exit

        /* reset vector */
        .section .resetvec,"a",@progbits
        .word   _start
