/* rt_builtin.S - MSP430 EABI "special convention" helpers: two 64-bit
 * operands, first in R8:R11, second in R12:R15, result in R12:R15.
 * Each pushes the first operand as a stack argument and calls a plain C
 * function f(second = R12:R15, first = on the stack). R8-R10 are untouched. */
        .text
        .macro  BUILTIN64 name, cfunc
        .global \name
        .type   \name,@function
\name:
        push    r11
        push    r10
        push    r9
        push    r8
        call    #\cfunc
        add     #8, r1
        ret
        .endm

        BUILTIN64 __mspabi_mpyll,  __rt_mpyll
        BUILTIN64 __mspabi_divlli, __rt_divlli
        BUILTIN64 __mspabi_divull, __rt_divull
        BUILTIN64 __mspabi_remlli, __rt_remlli
        BUILTIN64 __mspabi_remull, __rt_remull
