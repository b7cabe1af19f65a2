"""Build C for a classic 8051 with sdcc -mmcs51 --model-large --std-c99
--Werror: .ihx, .map and one .rst per module (the simulator scripts read
them); objects cached by preprocessed text and flags.
"""
from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

from lab.mcu.sources import csrc_defining
from lab.mcu.toolchain import (BUILD_DIR, CSRC_INCLUDE, Image, McuError, define_flags, file_key,
                               cache_key, run_tool, tool)


MCS51_CFLAGS = ["-mmcs51", "--model-large", "--std-c99", "--Werror"]
SDCC_LIB_SRC = Path("/usr/share/sdcc/lib/src")     # Debian sdcc-libraries


def mcs51_runtime(extra_flags=()) -> list[Path]:
    """Runtime helpers the build links before sdcc's own libraries.

    sdcc 4.2 ships its hand-written 8051 `__mullong` (MUL AB on bytes, 32x32
    -> low 32) only for the small model; `--model-large --stack-auto` gets the
    generic C version from large-stack-auto/liblong.lib: slower, and its
    stack frame is what pushed the chain's call depth past 0xFF.  The
    assembly routine touches no xdata (a in DPL/DPH/B/A, b on the internal
    stack, result in DPL/DPH/B/A), so the very same code is correct for the
    large model with --stack-auto: built here from sdcc's installed source
    (_mullong.c, its small-stack-auto branch) and cached.  The bit-exact tests
    of the chain and compensation on s51 run through it."""
    flags = list(extra_flags)
    if "--xstack" in flags:
        return _xstack_runtime(flags)
    if "--stack-auto" not in flags:
        return []
    src = SDCC_LIB_SRC / "_mullong.c"
    if not src.exists():
        raise McuError(f"{src} missing (Debian package sdcc-libraries)")
    out = BUILD_DIR / "mcs51-rt" / file_key([src])
    rel = out / "mullong_auto.rel"
    if rel.exists():
        return [rel]
    out.mkdir(parents=True, exist_ok=True)
    text = run_tool([tool("sdcc"), "-mmcs51", "--model-large", "--stack-auto", "--std-c99",
                 "-U__SDCC_MODEL_LARGE", "-D__SDCC_MODEL_SMALL", "-c", src, "-o", rel], cwd=out)
    asm = (out / "mullong_auto.asm").read_text()
    if "warning" in text.lower() or "mul\tab" not in asm:
        raise McuError(f"sdcc did not build the assembly __mullong from {src}:\n{text}")
    return [rel]


# sdcc ships no library for --stack-auto --xstack: the helpers a chain
# build calls are compiled from sdcc's sources for that model (as
# examples/firmware/mcs51/Makefile does; a helper with parameters taken
# from large-stack-auto would read them from the wrong stack); the rest
# (start-up assembly, no frames) links from large-stack-auto
XSTACK_RT = ("_mullong", "_mulint", "_divulong", "_modulong", "_gptrget", "_gptrput", "_startup", "_bp", "_spx",
             "bpx")
XSTACK_LIB = Path("/usr/share/sdcc/lib/large-stack-auto")
# helpers that take parameters on the stack and that only some builds call
# (a struct copy calls __memcpy; the signed and 16-bit divisions): built for
# --xstack into a library, so a build links only the ones it calls and none
# of them comes from large-stack-auto, where they read their parameters from
# the internal stack (a struct copy through its __memcpy copies garbage).
# Soft float is not among them: an --xstack build is fixed-only
# (SIG_NO_FLOAT), and build_mcs51 refuses one that links libfloat.
XSTACK_ON_DEMAND = ("__memcpy", "_divslong", "_modslong", "_divsint", "_modsint", "_divuint", "_moduint")


def _xstack_runtime(flags) -> list[Path]:
    return _xstack_rels(XSTACK_RT, "xstack")


def xstack_library() -> Path:
    """The library of XSTACK_ON_DEMAND, built for --stack-auto --xstack."""
    rels = _xstack_rels(XSTACK_ON_DEMAND, "xstack-lib")
    lib = rels[0].parent / "rtxstack.lib"
    if not lib.exists():
        tmp = lib.with_name(f"rtxstack.lib.tmp{os.getpid()}")
        run_tool([tool("sdar"), "rcs", tmp, *rels], cwd=lib.parent)
        tmp.rename(lib)
    return lib


def _xstack_rels(names, tag) -> list[Path]:
    srcs = [SDCC_LIB_SRC / f"{m}.c" for m in names]
    missing = [s for s in srcs if not s.exists()]
    if missing:
        raise McuError(f"{missing[0]} missing (Debian package sdcc-libraries)")
    out = BUILD_DIR / "mcs51-rt" / f"{tag}-{file_key(srcs)}"
    rels = [out / f"rt{s.stem}.rel" for s in srcs]
    if all(r.exists() for r in rels):
        return rels
    out.mkdir(parents=True, exist_ok=True)
    for s, r in zip(srcs, rels):
        run_tool([tool("sdcc"), "-mmcs51", "--model-large", "--stack-auto", "--xstack", "--std-c99",
                  "-c", s, "-o", r], cwd=out)
    return rels


MCS51_OBJ_OUTPUTS = (".rel", ".asm", ".lst", ".sym")


def _mcs51_compile(sdcc, sources, flags, outdir) -> list[Path]:
    """sdcc -c of each source into outdir, two at a time (sdcc takes up to a
    minute for a large module).  Objects are cached by the preprocessed text
    and the flags, so builds that differ only in the harness (fixed / float,
    another vector set) compile the csrc/ modules once."""
    from concurrent.futures import ThreadPoolExecutor

    def one(src):
        pre = run_tool([sdcc, *flags, "-E", src])
        # -I/-D are in the preprocessed text already
        cache = BUILD_DIR / "mcs51-obj" / f"{src.stem}-{cache_key(pre, *[f for f in flags if f[:2] not in ('-I', '-D')])}"
        if not (cache / (src.stem + ".rel")).exists():
            tmp = cache.with_name(cache.name + f".tmp{os.getpid()}")
            shutil.rmtree(tmp, ignore_errors=True)
            tmp.mkdir(parents=True)
            out = run_tool([sdcc, *flags, "-c", src, "-o", str(tmp) + "/"], cwd=tmp)
            if "warning" in out.lower():
                raise McuError(f"sdcc warning in {src}:\n{out}")
            shutil.rmtree(cache, ignore_errors=True)
            tmp.rename(cache)
        for ext in MCS51_OBJ_OUTPUTS:
            if (cache / (src.stem + ext)).exists():
                shutil.copy(cache / (src.stem + ext), outdir / (src.stem + ext))
        return outdir / (src.stem + ".rel")

    with ThreadPoolExecutor(max_workers=2) as pool:
        return list(pool.map(one, [Path(s) for s in sources]))


def build_mcs51(sources, harness, defines=(), *, name=None, include_dirs=(),
                outdir=None, extra_flags=(), extra_rels=()) -> Image:
    """Compile with sdcc -mmcs51 --model-large --std-c99 --Werror; the harness
    module (main) is linked first.  Produces .ihx, .map and one .rst per module.
    extra_rels: objects linked after the modules; with --stack-auto the
    assembly __mullong of mcs51_runtime() is added."""
    sdcc = tool("sdcc")
    extra_rels = [*extra_rels, *mcs51_runtime(extra_flags)]
    lib_dirs = []
    if "--xstack" in extra_flags:       # searched before sdcc's own libraries
        xlib = xstack_library()
        lib_dirs = ["-L", str(xlib.parent), "-l", xlib.name, "-L", str(XSTACK_LIB)]
    sources = [Path(s).resolve() for s in sources]
    harness = Path(harness).resolve()
    dflags = define_flags(defines)
    inc = [f"-I{d}" for d in [CSRC_INCLUDE, *include_dirs, harness.parent]]
    name = name or harness.stem
    outdir = Path(outdir or BUILD_DIR / "mcs51" / f"{name}-{cache_key(*dflags, *sources, *inc, *extra_flags, *extra_rels)}")
    if outdir.exists():                 # a failed link leaves a stale .ihx: start clean
        shutil.rmtree(outdir)
    outdir.mkdir(parents=True)
    flags = [*MCS51_CFLAGS, *extra_flags, *dflags, *inc]
    rels = _mcs51_compile(sdcc, [harness, *sources], flags, outdir)
    ihx = outdir / f"{harness.stem}.ihx"
    for _ in range(4):      # add the csrc/*.c that define still-undefined symbols
        out = run_tool([sdcc, *MCS51_CFLAGS, *extra_flags, *rels, *extra_rels, *lib_dirs, "-o", ihx], cwd=outdir,
                   check=False)
        extra = csrc_defining([n[1:] for n in re.findall(r"Undefined Global '(\w+)'", out)],
                               sources)
        if not extra:
            break
        rels += _mcs51_compile(sdcc, extra, flags, outdir)
        sources += extra
        if ihx.exists():
            ihx.unlink()
    if "ASlink-Error" in out or "Undefined Global" in out or not ihx.exists():
        raise McuError(f"sdcc link failed in {outdir}:\n{out}")
    if "--xstack" in extra_flags and "libfloat.lib" in ihx.with_suffix(".map").read_text():
        raise McuError(f"{outdir}: an --xstack build linked large-stack-auto's soft float, which reads its "
                       "parameters from the internal stack: build it with SIG_NO_FLOAT")
    img = Image("mcs51", ihx)
    mcs51_symbols(img)
    return img


def mcs51_symbols(img: Image) -> None:
    """name -> (space, address) from the .map; space is code, iram or xram.
    Also records per-area, per-module sizes in img.sizes[(area, module)]."""
    space = "iram"
    area = None
    for line in open(img.path.with_suffix(".map")):
        m = re.match(r"^([A-Z_0-9]+)\s+([0-9A-F]{8})\s+([0-9A-F]{8}) =.*\((.*)\)", line)
        if m:
            area, attrs = m.group(1), m.group(4)
            space = "code" if "CODE" in attrs else "xram" if "XDATA" in attrs else "iram"
            continue
        m = re.match(r"^(?:[A-Z]:)?\s+([0-9A-F]{8})\s+(\S+)(?:\s+(\S+))?\s*$", line)
        if m:
            img.symbols[m.group(2)] = (space, int(m.group(1), 16))
    # module contributions per area, from the .rst-independent "Area ... Size" table
    text = img.path.with_suffix(".map").read_text()
    for m in re.finditer(r"^(\S+)\s+([0-9A-F]{8})\s+([0-9A-F]{8}) =\s+(\d+)\. bytes.*$", text, re.M):
        img.sizes.setdefault(("area", m.group(1)), 0)
        img.sizes[("area", m.group(1))] += int(m.group(4))
