"""Run an ATmega328P image in simavr and read what it measured on itself.

The harness counts its own cycles with Timer 1 at clk/1 (bench/mcu/avr/
bench_avr.h: the method that works unchanged on a real chip), and
bench_done() writes RAM from .data to the end of .bss on USART0 as
"@ADDR hex" lines, then sleeps with interrupts off, which ends simavr.

    measure_avr(img, funcs=[...], regions=["bench_start:bench_stop"], reads={...})
      funcs[i]  <- the i-th BENCH_CALL() of the run: cycles (the statement
                   between two clock reads: argument set-up, call, return,
                   result store) and stack_bytes (below the caller's stack
                   pointer, return address included)
      regions   <- "a:b": cycles between the markers a and b of
                   bench_marks.h (each marker's own cost subtracted)
      reads     <- {symbol: nbytes}, little-endian raw bytes at the end
      overhead  <- the calibration constants the program measured at start
                   and subtracted (an empty BENCH_CALL(), a marker, one
                   Timer 1 overflow interrupt)

simavr 1.6 counts AVR cycles per instruction as the datasheet's table
(no flash wait states on the AVR); it has no instruction counter, so AVR
rows carry cycles only.
"""
from __future__ import annotations

import re

from lab.mcu.build_avr import AVR_F_CPU, AVR_MCU
from lab.mcu.toolchain import MCU_DIR, SIM_TIMEOUT, Image, McuError, run_tool, tool

_RAM_LINE = re.compile(r"@([0-9a-f]{4}) ((?:[0-9a-f]{2})+)")
BENCH_AVR_MARKS = 8
# marker name -> id, as bench_marks.h defines them (BENCH_MARKER(name, id))
MARKER_IDS = {m.group(1): int(m.group(2)) for m in re.finditer(
    r"^BENCH_MARKER\((\w+), (\d+)\)", (MCU_DIR / "harness" / "bench_marks.h").read_text(), re.M)}
DATA_SPACE = 0x800000          # avr-nm's offset of RAM addresses


def run_avr(img: Image) -> dict:
    """Run to bench_done(); {RAM address: byte} of the dump."""
    out = run_tool(["timeout", str(SIM_TIMEOUT + 5), tool("simavr"), "-m", AVR_MCU,
                    "-f", str(AVR_F_CPU), img.path])
    out = re.sub(r"\x1b\[[0-9;]*m", "", out)
    if "$" not in out:
        raise McuError(f"simavr: {img.path} never reached bench_done():\n" + out[-2000:])
    mem = {}
    for m in _RAM_LINE.finditer(out):
        base = int(m.group(1), 16)
        data = bytes.fromhex(m.group(2))
        mem.update({base + i: b for i, b in enumerate(data)})
    return mem


def read_symbol(img: Image, mem: dict, name: str, n: int) -> bytes:
    addr = img.symbols[name] - DATA_SPACE
    missing = [a for a in range(addr, addr + n) if a not in mem]
    if missing:
        raise McuError(f"{name}: {len(missing)} bytes not in the RAM dump of {img.path}")
    return bytes(mem[a] for a in range(addr, addr + n))


def _u(b: bytes) -> list:
    return [int.from_bytes(b[i:i + 4], "little") for i in range(0, len(b), 4)]


def measure_avr(img: Image, funcs=(), regions=(), reads=None) -> dict:
    mem = run_avr(img)
    rd = lambda name, n: read_symbol(img, mem, name, n)            # noqa: E731
    n_calls = rd("bench_calls", 1)[0]
    if n_calls < len(funcs):
        raise McuError(f"{img.path}: {n_calls} BENCH_CALL()s ran, {len(funcs)} functions asked")
    cycles = _u(rd("bench_call_cycles", 4 * len(funcs)))
    stack = rd("bench_call_stack", 2 * len(funcs))
    res = {"funcs": {}, "regions": {}, "reads": {}}
    for i, fn in enumerate(funcs):
        res["funcs"][fn] = {"cycles": cycles[i],
                            "stack_bytes": int.from_bytes(stack[2 * i:2 * i + 2], "little")}
    marks = _u(rd("bench_mark_cycles", 4 * BENCH_AVR_MARKS))
    for reg in regions:
        a, b = (MARKER_IDS[m] for m in reg.split(":"))
        res["regions"][reg] = {"cycles": marks[b] - marks[a]}
    for name, n in (reads or {}).items():
        res["reads"][name] = rd(name, n)
    u16 = lambda name: int.from_bytes(rd(name, 2), "little")                # noqa: E731
    res["overhead"] = {"empty_call_cycles": u16("bench_call_overhead"),
                       "marker_cycles": u16("bench_mark_overhead"),
                       "overflow_isr_cycles": u16("bench_isr_cycles"),
                       "stack_floor_bytes": u16("bench_call_stack_floor")}
    return res
