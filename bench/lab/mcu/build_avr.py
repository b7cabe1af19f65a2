"""Build C for the ATmega328P (the Arduino Uno's chip) with Debian's gcc-avr
and avr-libc: -Os as the Arduino IDE builds, warnings as errors, the
Timer 1 cycle clock and RAM dump of bench/mcu/avr linked in (the harness
counts itself: simavr has no scripted breakpoints; sim_avr reads the
results).  float is avr-libc's (libm), int64 and division libgcc's."""
from __future__ import annotations

import re
import shutil
from pathlib import Path

from lab.mcu.sources import link_adding_csrc
from lab.mcu.toolchain import (BUILD_DIR, CSRC_INCLUDE, Image, MCU_DIR, McuError, cache_key,
                               define_flags, run_tool, tool)

AVR_MCU = "atmega328p"
AVR_F_CPU = 16_000_000
AVR_CFLAGS = [f"-mmcu={AVR_MCU}", f"-DF_CPU={AVR_F_CPU}UL", "-Os", "-g", "-std=c99", "-Wall",
              "-Wextra", "-Wconversion", "-pedantic", "-Werror", "-ffunction-sections",
              "-fdata-sections"]
AVR_SUPPORT = MCU_DIR / "avr"            # bench_avr.c: Timer 1 clock, stack paint, RAM dump


def build_avr(sources, harness, defines=(), *, name=None, include_dirs=(), outdir=None,
              with_bench=True, extra_flags=()) -> Image:
    """Compile `sources` (code under test) and `harness` (main) for the
    ATmega328P as separate units (no LTO: nothing of the code under test is
    inlined into the harness) and link with --gc-sections, libm and, unless
    with_bench is False (a firmware of its own), bench/mcu/avr/bench_avr.c."""
    gcc = tool("avr-gcc")
    sources = [Path(s).resolve() for s in sources]
    harness = Path(harness).resolve()
    dflags = define_flags(defines)
    inc = [f"-I{d}" for d in [CSRC_INCLUDE, *include_dirs, harness.parent, AVR_SUPPORT]]
    flags = [*AVR_CFLAGS, *extra_flags, *dflags, *inc]
    name = name or harness.stem
    outdir = Path(outdir or BUILD_DIR / "avr" / f"{name}-{cache_key(*flags, *sources, harness)}")
    if outdir.exists():
        shutil.rmtree(outdir)
    outdir.mkdir(parents=True)
    units = [harness, *sources] + ([AVR_SUPPORT / "bench_avr.c"] if with_bench else [])
    objs = []

    def compile_one(src):
        o = outdir / (src.stem + ".o")
        out = run_tool([gcc, *flags, "-c", src, "-o", o])
        if "warning" in out.lower():
            raise McuError(f"avr-gcc warning in {src}:\n{out}")
        objs.append(o)

    for s in units:
        compile_one(s)
    elf = outdir / f"{name}.elf"
    link_adding_csrc(lambda: run_tool([gcc, f"-mmcu={AVR_MCU}", "-Wl,--gc-sections", *objs, "-lm",
                                       "-o", elf]),
                     lambda extra: [compile_one(s) for s in extra], sources,
                     r"undefined reference to `(\w+)'")
    img = Image("avr", elf)
    avr_symbols(img)
    return img


def avr_symbols(img: Image) -> None:
    """name -> address (code: byte address in flash; data: 0x800000 + RAM
    address, as avr-nm prints it) and name -> size."""
    out = run_tool([tool("avr-nm"), "-S", "--defined-only", img.path])
    for line in out.splitlines():
        f = line.split()
        if len(f) == 4:
            img.symbols[f[3]] = int(f[0], 16)
            img.sizes[f[3]] = int(f[1], 16)
        elif len(f) == 3:
            img.symbols[f[2]] = int(f[0], 16)


def avr_section_sizes(img: Image) -> dict:
    """.text, .data, .bss bytes of the whole program (avr-size): flash =
    text + data, static RAM = data + bss."""
    out = run_tool([tool("avr-size"), "-A", img.path])
    return {m.group(1): int(m.group(2)) for m in re.finditer(r"^\.(text|data|bss)\s+(\d+)", out, re.M)}
