"""Cycle-counter calibration per target: does the simulator count what the
MCU's user guide says?

A short instruction sequence, each instruction with the cycle count its
user guide states, is written out as `cal_seq` (an assembly function),
built with bench/mcu/harness/cycle_cal_harness.c and measured with the
runner the way every bench row is measured:

- entry through return of the call in main (runner.measure funcs): must
  equal the sum of the stated cycles of the sequence and its return;
- between the bench_start/bench_stop markers, minus the same markers with
  nothing between them (the CAL_EMPTY build): must equal the call, the
  sequence and its return.

The results the sequence stores (cal_result) are read back and compared
with what the instructions compute, so the sequence really ran as listed.

Sources of the stated cycles:
- MSP430: MSP430x1xx Family User's Guide (TI SLAU049F), 3.4.4 "Instruction
  Cycles and Lengths": Table 3-15 (format II: RRA, SWPB, PUSH, CALL),
  Table 3-16 (format I, by source and destination addressing mode); every
  jump 2 cycles.  mspdebug 0.22's `sim` implements this classic table (the
  F5510's CPUX timing, SLAU208, differs in places: the bench figures are
  labelled "classic MSP430 timing").  No constant-generator immediate
  (#0 #1 #2 #4 #8 #-1) is in the sequence: the simulator is known to count
  those as a plain immediate (bench/mcu/README.md).
- 8051: Intel MCS-51 instruction set (MCS-51 Microcontroller Family User's
  Manual, "Instruction Set Summary", oscillator periods per instruction):
  machine cycles of 12 oscillator periods; s51 reports clocks.
"""
from __future__ import annotations

from pathlib import Path

from lab.mcu import runner

HARNESS = runner.MCU_DIR / "harness" / "cycle_cal_harness.c"

# Each target's sequence, in order: (target, source line, cycles stated by
# its user guide, times it runs, which row states them)
STATED = (
    ("msp430", "mov #cal_data, r13", 2, 1, "3-16 #N -> Rm"),
    ("msp430", "mov @r13, r12", 2, 1, "3-16 @Rn -> Rm"),
    ("msp430", "add @r13+, r12", 2, 1, "3-16 @Rn+ -> Rm"),
    ("msp430", "add 2(r13), r12", 3, 1, "3-16 x(Rn) -> Rm"),
    ("msp430", "add &cal_data, r12", 3, 1, "3-16 &EDE -> Rm"),
    ("msp430", "mov r12, r14", 1, 1, "3-16 Rn -> Rm"),
    ("msp430", "add r14, r12", 1, 1, "3-16 Rn -> Rm"),
    ("msp430", "mov #cal_result, r15", 2, 1, "3-16 #N -> Rm"),
    ("msp430", "mov r12, 0(r15)", 4, 1, "3-16 Rn -> x(Rm)"),
    ("msp430", "mov r12, &cal_result+2", 4, 1, "3-16 Rn -> &EDE"),
    ("msp430", "mov @r13, 4(r15)", 5, 1, "3-16 @Rn -> x(Rm)"),
    ("msp430", "mov &cal_data+4, &cal_result+6", 6, 1, "3-16 &EDE -> &TONI"),
    ("msp430", "mov #0x5a5a, &cal_result+8", 5, 1, "3-16 #N -> &EDE"),
    ("msp430", "rra r12", 1, 1, "3-15 RRA Rn"),
    ("msp430", "swpb r12", 1, 1, "3-15 SWPB Rn"),
    ("msp430", "rra 8(r15)", 4, 1, "3-15 RRA x(Rn)"),
    ("msp430", "push r12", 3, 1, "3-15 PUSH Rn"),
    ("msp430", "pop r14", 2, 1, "3-16 @Rn+ -> Rm (POP = MOV @SP+, dst)"),
    ("msp430", "mov r14, &cal_result+10", 4, 1, "3-16 Rn -> &EDE"),
    ("msp430", "jmp 1f", 2, 1, "jumps: 2"),
    ("msp430", "1: ret", 3, 1, "3-16 @Rn+ -> PC (RET = MOV @SP+, PC)"),
    ("mcs51", "mov a, #0x12", 1, 1, "MOV A,#data"),
    ("mcs51", "mov r2, a", 1, 1, "MOV Rn,A"),
    ("mcs51", "add a, r2", 1, 1, "ADD A,Rn"),
    ("mcs51", "mov r3, #5", 1, 1, "MOV Rn,#data"),
    ("mcs51", "09001$: inc a", 1, 5, "INC A"),
    ("mcs51", "djnz r3, 09001$", 2, 5, "DJNZ Rn,rel (taken 4 times, then not: 2 either way)"),
    ("mcs51", "mov b, #7", 2, 1, "MOV direct,#data"),
    ("mcs51", "mul ab", 4, 1, "MUL AB"),
    ("mcs51", "mov dptr, #_cal_result", 2, 1, "MOV DPTR,#data16"),
    ("mcs51", "movx @dptr, a", 2, 1, "MOVX @DPTR,A"),
    ("mcs51", "inc dptr", 2, 1, "INC DPTR"),
    ("mcs51", "xch a, b", 1, 1, "XCH A,direct"),
    ("mcs51", "movx @dptr, a", 2, 1, "MOVX @DPTR,A"),
    ("mcs51", "inc dptr", 2, 1, "INC DPTR"),
    ("mcs51", "mov a, b", 1, 1, "MOV A,direct"),
    ("mcs51", "mov b, #3", 2, 1, "MOV direct,#data"),
    ("mcs51", "div ab", 4, 1, "DIV AB"),
    ("mcs51", "movx @dptr, a", 2, 1, "MOVX @DPTR,A"),
    ("mcs51", "nop", 1, 1, "NOP"),
    ("mcs51", "sjmp 09002$", 2, 1, "SJMP rel"),
    ("mcs51", "09002$: ret", 2, 1, "RET"),
)


def _rows(target: str) -> tuple:
    """the rows of STATED for `target`, without the target"""
    return tuple(row[1:] for row in STATED if row[0] == target)


MSP430_SEQUENCE = _rows("msp430")
MCS51_SEQUENCE = _rows("mcs51")
MSP430_CALL = (5, "3-15 CALL #N")
MCS51_CALL = (2, "LCALL addr16")

# Constant-generator immediates (R2/R3 as source: a register, 1 cycle to a
# register in the user guide), which mspdebug 0.22 counts as immediates:
# spliced into the sequence before its jump, they measure the simulator's
# known excess (the bench figures carry it; bench/mcu/README.md): measured
# 4 cycles over the 3 stated for these three.
MSP430_CONSTANT_GENERATOR_EXCESS = 4
MSP430_CONSTANT_GENERATOR = (
    ("mov #1, r14", 1, 1, "3-16 Rn -> Rm (constant generator)"),
    ("add #2, r14", 1, 1, "3-16 Rn -> Rm (constant generator)"),
    ("mov #8, r14", 1, 1, "3-16 Rn -> Rm (constant generator)"),
)

MCS51_CLOCKS_PER_MACHINE_CYCLE = 12


def sequence(target: str, constant_generator: bool = False) -> tuple:
    """the table of `target`; msp430 with constant_generator: the
    MSP430_CONSTANT_GENERATOR lines before the push (r14 is overwritten by
    the pop: the results stay the same)"""
    if target != "msp430":
        return MCS51_SEQUENCE
    if not constant_generator:
        return MSP430_SEQUENCE
    push = next(i for i, row in enumerate(MSP430_SEQUENCE) if row[0].startswith("push"))
    return MSP430_SEQUENCE[:push] + MSP430_CONSTANT_GENERATOR + MSP430_SEQUENCE[push:]


def write_sequence(target: str, outdir: Path, seq=None) -> Path:
    """cal_seq for `target` from its table: msp430 .S, mcs51 .c (naked asm)."""
    seq = seq or sequence(target)
    outdir.mkdir(parents=True, exist_ok=True)
    if target == "msp430":
        body = "".join(f"    {ins}\n" for ins, _, _, _ in seq)
        path = outdir / "cal_seq_msp430.S"
        path.write_text("/* generated by bench/lab/mcu/cycle_calibration.py - do not edit */\n"
                        "    .text\n    .global cal_seq\n    .type cal_seq, @function\n"
                        f"cal_seq:\n{body}    .size cal_seq, .-cal_seq\n")
        return path
    body = "".join(f"    {ins}\n" for ins, _, _, _ in seq)
    path = outdir / "cal_seq_mcs51.c"
    path.write_text("/* generated by bench/lab/mcu/cycle_calibration.py - do not edit */\n"
                    "void cal_seq(void) __naked\n{\n    __asm\n" + body + "    __endasm;\n}\n")
    return path


def stated_cycles(target: str, constant_generator: bool = False) -> dict:
    """the user guide's count: the sequence with its return, and with the call
    (MSP430 MCLK cycles; 8051 oscillator clocks of a 12T part)."""
    seq = sequence(target, constant_generator)
    call = MSP430_CALL if target == "msp430" else MCS51_CALL
    unit = 1 if target == "msp430" else MCS51_CLOCKS_PER_MACHINE_CYCLE
    body = sum(c * times for _, c, times, _ in seq)
    return {"entry_to_return": body * unit, "call_entry_to_return": (body + call[0]) * unit,
            "instructions": sum(times for _, _, times, _ in seq)}


def expected_result(target: str) -> bytes:
    """what cal_seq leaves in cal_result, computed from the instructions' meaning"""
    if target == "msp430":
        d0, d1, d2 = 0x1234, 0x0101, 0x2002                 # cal_data in the harness
        r12 = (d0 + d0 + d2 + d0) & 0xFFFF                  # mov @r13; add @r13+; add 2(r13); add &
        r12 = (r12 + r12) & 0xFFFF                          # mov r12, r14; add r14, r12
        words = [r12, r12, d1, d2, 0x5A5A >> 1]             # 0(r15), &+2, @r13 (now d1), &+6, rra 8(r15)
        r12 = (r12 >> 1) | (r12 & 0x8000)                   # rra: arithmetic
        r12 = ((r12 & 0xFF) << 8) | (r12 >> 8)              # swpb
        words.append(r12)                                   # push / pop / mov to &+10
        return b"".join(w.to_bytes(2, "little") for w in words)
    a = (0x12 + 0x12 + 5) & 0xFF                            # mov, add, 5 x inc
    prod = a * 7                                            # mul ab: a = low, b = high
    low, high = prod & 0xFF, prod >> 8
    return bytes([low, high, low // 3])                     # xch; mov a, b; div ab by 3


def calibrate(target: str, constant_generator: bool = False) -> dict:
    """Build and measure both calibration images of `target`; check the
    results read back.  Returns measured and stated counts."""
    tag = "-cg" if constant_generator else ""
    gen = runner.BUILD_DIR / "gen" / f"cycle-cal-{target}{tag}"
    seq = write_sequence(target, gen, sequence(target, constant_generator))
    want = expected_result(target)
    reads = {"cal_result": len(want)}
    measured = {}
    for empty in (False, True):
        defines = ["CAL_EMPTY"] if empty else []
        name = f"cycle-cal{tag}{'-empty' if empty else ''}"
        if target == "msp430":
            img = runner.build_msp430([seq], HARNESS, defines, hwmult=False, name=name)
        else:
            img = runner.build_mcs51([seq], HARNESS, defines, name=name)
        r = runner.measure(img, funcs=[] if empty else ["cal_seq"], regions=["bench_start:bench_stop"],
                           reads=reads, stack=False, **({} if target == "msp430" else {"one_t": False}))
        if r["reads"]["cal_result"] != want:
            raise runner.McuError(f"cal_seq on {target}: cal_result {r['reads']['cal_result'].hex()}, "
                                  f"the instructions compute {want.hex()}")
        if empty:
            measured["region_empty"] = r["regions"]["bench_start:bench_stop"]["cycles"]
        else:
            measured["entry_to_return"] = r["funcs"]["cal_seq"]["cycles"]
            measured["instructions"] = r["funcs"]["cal_seq"]["instructions"]
            measured["region"] = r["regions"]["bench_start:bench_stop"]["cycles"]
    measured["call_entry_to_return"] = measured["region"] - measured["region_empty"]
    return {"target": target, "measured": measured, "stated": stated_cycles(target, constant_generator)}
