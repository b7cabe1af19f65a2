"""Build C for the MSP430F5510 (clang-14 + ld.lld), a classic 8051 (sdcc) or
the ATmega328P (gcc-avr + avr-libc), run it in a simulator non-interactively
and measure it: the one entry point every MCU bench and test uses, which
hands each job to its module.

    img = build_msp430([csrc/tcomp/sig_poly.c, ...], harness, defines={"ORDER": 2}, hwmult=True)
    img = build_avr(sources, harness, defines)          # same harnesses (bench/mcu/harness)
    calls = measure(img, funcs=["sig_tcomp_apply_q"], regions=["bench_start:bench_stop"],
                    reads={"out": 300})
    calls["funcs"]["sig_tcomp_apply_q"]   -> {"instructions", "cycles", "stack_bytes", ...}
    calls["reads"]["out"]                  -> bytes read back after the program ended
    text_bytes(img, "sig_tcomp_apply_q")   -> bytes of .text of one function

Modules: toolchain (paths, tools, Image, compiler-rt fetch), sources
(csrc/ files by name), build_msp430 / build_mcs51 / build_avr, sim_msp430
(mspdebug 0.22 `sim`: MCLK, classic MSP430 table), sim_mcs51 (s51 -t C52:
12T clocks, 1T estimate), sim_avr (simavr: Timer 1 at clk/1 counted by the
harness itself), sizes (code and data bytes).  Timing models:
bench/mcu/README.md.  Every call is wrapped in `timeout`; results must be
read back and checked, a wrong build gives plausible cycles.
"""
from __future__ import annotations

from pathlib import Path

from lab.mcu.build_avr import AVR_F_CPU, AVR_MCU, avr_section_sizes, avr_symbols, build_avr  # noqa: F401
from lab.mcu.build_mcs51 import MCS51_CFLAGS, build_mcs51, mcs51_runtime, mcs51_symbols  # noqa: F401
from lab.mcu.build_msp430 import (MSP430_CFLAGS, MSP430_MPY_BASE_SIM, build_msp430,  # noqa: F401
                                  msp430_symbols)
from lab.mcu.sim_avr import measure_avr
from lab.mcu.sim_mcs51 import measure_mcs51, profile_lines_mcs51, profile_mcs51, run_until_mcs51  # noqa: F401
from lab.mcu.sim_msp430 import measure_msp430, profile_msp430, run_until_msp430
from lab.mcu.sizes import (code_closure, is_helper, mcs51_module_sizes, symbol_size,  # noqa: F401
                           text_bytes)
from lab.mcu.sources import c_source, c_sources, csrc_sources  # noqa: F401
from lab.mcu.toolchain import (BUILD_DIR, CSRC, CSRC_INCLUDE, MCU_DIR, PORT_MSP430, ROOT,  # noqa: F401
                               STACK_PATTERN, THIRD_PARTY, Image, McuError, compiler_rt_builtins, tool)


def measure(img: Image, funcs=(), regions=(), reads=None, stack=True, **kw) -> dict:
    """Run `img` in its simulator.
    funcs:   functions called directly from main(); per function: instructions
             and cycles from its first instruction through its return (MSP430:
             MCLK; 8051: 12T clocks), stack_bytes (return address included).
             AVR: the harness's BENCH_CALL()s in order, cycles of the
             statement (argument set-up and call included), no instruction
             count (sim_avr).
    regions: "start:stop" marker functions; counts from entry to entry.
    reads:   {symbol: nbytes} read back after the program ends (MSP430: at
             _exit; 8051 and AVR: at bench_done()).  Little-endian raw bytes."""
    reads = dict(reads or {})
    if img.target == "msp430":
        return measure_msp430(img, funcs, regions, reads, stack)
    if img.target == "avr":
        return measure_avr(img, funcs, regions, reads)
    return measure_mcs51(img, funcs, regions, reads, stack, **kw)


def profile(img: Image, func: str, n_instructions: int) -> list[dict]:
    """Instruction profile of one call of `func` (called from main): the
    simulator single-steps the call and attributes each executed instruction
    to the function containing its address.  Rows: function, instructions
    (exclusive), calls (entries at its first address), sorted by instructions.
    MSP430: mspdebug `step`.  8051: s51's execution history, rows also carry
    clocks_12T and clocks_1t_stc_y5 (mcs51_timing), sorted by 12T clocks;
    static functions are named from the .rst listings."""
    if img.target == "mcs51":
        return profile_mcs51(img, func, n_instructions)
    if img.target != "msp430":
        raise McuError("profile() is for MSP430 and 8051 images")
    return profile_msp430(img, func, n_instructions, by_line=False)


def profile_lines(img: Image, func: str, n_instructions: int) -> list[dict]:
    """As profile(), per source line (file:line from the debug information,
    inlined code attributed to the line it was inlined from); MSP430 only
    (the 8051's is profile_lines_mcs51)."""
    if img.target != "msp430":
        raise McuError("profile_lines() is for MSP430 images")
    return profile_msp430(img, func, n_instructions, by_line=True)


def run_until(img: Image, stop: str, reads) -> dict:
    """Run `img` from reset until the function `stop` is entered (a firmware's
    own "results ready" hook, not a bench marker) and read back {symbol:
    nbytes} as little-endian raw bytes.  McuError if `stop` is never reached."""
    reads = dict(reads)
    if img.target == "msp430":
        return run_until_msp430(img, stop, reads)
    if img.target == "mcs51":
        return run_until_mcs51(img, stop, reads)
    raise McuError("run_until() is for MSP430 and 8051 images")


def image_from_file(path, hwmult=False) -> Image:
    """An Image for a program built elsewhere (a firmware's own Makefile):
    .elf -> MSP430 (hwmult: its multiplier helpers need the simulated
    multiplier), .ihx -> 8051 (its .map beside it)."""
    path = Path(path)
    img = Image("msp430" if path.suffix == ".elf" else "mcs51", path, hwmult)
    if img.target == "msp430":
        msp430_symbols(img)
    else:
        mcs51_symbols(img)
    return img
