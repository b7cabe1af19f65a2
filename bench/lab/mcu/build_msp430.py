"""Build C for the MSP430F5510 with clang-14 + ld.lld: warnings as errors,
the start-up, linker script and runtime helpers of bench/mcu/msp430, the
hardware-multiplier helpers built for mspdebug's simulated multiplier at
0x0130 (the F5510 has it at 0x04C0: same code and cycles).
"""
from __future__ import annotations

import re
import shutil
from pathlib import Path

from lab.mcu.sources import link_adding_csrc
from lab.mcu.toolchain import (BUILD_DIR, CRT_FLOAT_FILES, CSRC_INCLUDE, Image, MCU_DIR,
                               define_flags, file_key, cache_key, run_tool, compiler_rt_builtins,
                               tool)


MSP430_CFLAGS = ["--target=msp430", "-O2", "-g", "-ffreestanding", "-nostdlib", "-std=c99",
                 "-Wall", "-Wextra", "-Wconversion", "-Wdouble-promotion", "-pedantic",
                 "-Werror", "-ffunction-sections", "-fdata-sections"]


MSP430_MPY_BASE_SIM = "0x0130"     # mspdebug 0.22's simulated multiplier


def _msp430_runtime(hwmult: bool) -> list[Path]:
    """Start-up + helper objects for one multiplier choice, cached by content."""
    clang = tool("clang-14", "clang")
    m = MCU_DIR / "msp430"
    crt = compiler_rt_builtins()
    hw = ["-mhwmult=f5series"] if hwmult else []
    srcs = [m / "crt0.S", m / "rt_builtin.S", m / "rt_int.c", m / "rt_float.c"] + \
           ([m / "rt_hwmul.c"] if hwmult else [])
    out = BUILD_DIR / "msp430-rt" / (("hw-" if hwmult else "sw-") + file_key(srcs))
    objs = [out / (s.name + ".o") for s in srcs] + [out / f"crt_{f}.o" for f in CRT_FLOAT_FILES]
    if all(o.exists() for o in objs):
        return objs
    out.mkdir(parents=True, exist_ok=True)
    for s in srcs:
        if s.suffix == ".S":
            run_tool([clang, "--target=msp430", "-c", s, "-o", out / (s.name + ".o")])
        else:
            extra = ["-DMPY_BASE=" + MSP430_MPY_BASE_SIM] if s.name == "rt_hwmul.c" else []
            run_tool([clang, *MSP430_CFLAGS, *hw, *extra, "-c", s, "-o", out / (s.name + ".o")])
    for f in CRT_FLOAT_FILES:   # third-party code, unmodified: its warnings are not ours
        run_tool([clang, *[x for x in MSP430_CFLAGS if x not in ("-Werror", "-pedantic")], *hw,
              "-w", "-D__builtin_clz=__builtin_clzl", "-I", crt, "-c", crt / f"{f}.c",
              "-o", out / f"crt_{f}.o"])
    return objs


def build_msp430(sources, harness, defines=(), *, hwmult=True, name=None,
                 include_dirs=(), outdir=None) -> Image:
    """Compile `sources` (code under test) and `harness` (main) with clang-14
    for the MSP430F5510, warnings as errors, and link with the start-up and
    helpers of bench/mcu/msp430.  hwmult: -mhwmult=f5series and the 16x16
    multiplier helpers built for the simulator's 0x0130."""
    clang, lld = tool("clang-14", "clang"), tool("ld.lld-14", "ld.lld")
    sources = [Path(s).resolve() for s in sources]
    harness = Path(harness).resolve()
    dflags = define_flags(defines)
    inc = [f"-I{d}" for d in [CSRC_INCLUDE, *include_dirs, harness.parent]]
    name = name or harness.stem
    outdir = Path(outdir or BUILD_DIR / "msp430" /
                  f"{name}-{'hw' if hwmult else 'sw'}-{cache_key(*dflags, *sources, *inc)}")
    if outdir.exists():
        shutil.rmtree(outdir)
    outdir.mkdir(parents=True)
    hw = ["-mhwmult=f5series"] if hwmult else []
    objs = []
    for s in [harness, *sources]:       # harness and code under test: separate units, no LTO
        o = outdir / (s.stem + ".o")
        if s.suffix == ".S":            # port-layer assembly: preprocessed, warnings as errors
            run_tool([clang, "--target=msp430", "-Werror", *dflags, *inc, "-c", s, "-o", o])
        else:
            run_tool([clang, *MSP430_CFLAGS, *hw, *dflags, *inc, "-c", s, "-o", o])
        objs.append(o)
    elf = outdir / f"{name}.elf"
    link = [lld, "-T", MCU_DIR / "msp430" / "msp430f5510.ld", "--gc-sections",
            "--defsym=__mspabi_addf=__addsf3", "--defsym=__mspabi_subf=__subsf3",
            "--defsym=__mspabi_mpyf=__mulsf3", "--defsym=__mspabi_divf=__divsf3",
            "--defsym=__mspabi_cmpf=__lesf2", *_msp430_runtime(hwmult)]
    def compile_more(extra):
        for s in extra:
            o = outdir / (s.stem + ".o")
            run_tool([clang, *MSP430_CFLAGS, *hw, *dflags, *inc, "-c", s, "-o", o])
            objs.append(o)

    link_adding_csrc(lambda: run_tool([*link, *objs, "-o", elf]), compile_more, sources,
                     r"undefined symbol: (\w+)")
    img = Image("msp430", elf, hwmult)
    msp430_symbols(img)
    return img


def msp430_symbols(img: Image) -> None:
    out = run_tool([tool("llvm-objdump-14", "llvm-objdump"), "-t", img.path])
    for line in out.splitlines():
        f = line.split()
        if len(f) >= 5 and re.fullmatch(r"[0-9a-f]{8}", f[0]):
            img.symbols[f[-1]] = int(f[0], 16)
            if re.fullmatch(r"[0-9a-f]{8}", f[-2]):
                img.sizes[f[-1]] = int(f[-2], 16)
