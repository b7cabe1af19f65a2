"""Build C for the MSP430F5510 (clang-14 + ld.lld) or a classic 8051 (sdcc),
run it in a simulator non-interactively and measure it.

Reusable by every MCU bench (bench/mcu_cost.py, later ones):

    img = build_msp430([csrc/tcomp/sig_poly.c, ...], harness, defines={"ORDER": 2}, hwmult=True)
    calls = measure(img, funcs=["sig_tcomp_apply_q"], regions=["bench_start:bench_stop"],
                    reads={"out": 300})
    calls["funcs"]["sig_tcomp_apply_q"]   -> {"instructions", "cycles", "stack_bytes", ...}
    calls["reads"]["out"]                  -> bytes read back after the program ended
    text_bytes(img, "sig_tcomp_apply_q")   -> bytes of .text of one function

Timing models (see bench/mcu/README.md): MSP430 cycles are mspdebug 0.22
`sim` MCLK (classic MSP430 table, not CPUX; constant-generator immediates
over-counted; no flash wait states); the hardware-multiplier build runs its
helpers on the simulated 16x16 multiplier at 0x0130 (MPY_BASE=0x0130; the
F5510 has it at 0x04C0, same code and cycles).  8051 clocks are s51 -t C52
12T oscillator clocks.  Every call is wrapped in `timeout`; results must be
read back and checked, a wrong build gives plausible cycles.

Tools are found as clang-14/clang, ld.lld-14/ld.lld, llvm-objdump-14/
llvm-objdump, mspdebug, sdcc, s51.  Standard library only.
"""
from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
import sys
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

def _source_root() -> Path:
    """The source checkout this lab package lives in (bench/lab/mcu/ ->
    the root): the MCU builds need csrc/ and bench/mcu/."""
    return Path(__file__).resolve().parents[3]


ROOT = _source_root()
MCU_DIR = ROOT / "bench" / "mcu"          # harnesses, start-up code, linker scripts
CSRC = ROOT / "csrc"
CSRC_INCLUDE = CSRC / "include"           # the public headers of every area
PORT_MSP430 = CSRC / "port" / "msp430"    # sig_port_msp430.h
BUILD_DIR = Path(os.environ.get("PYSIG_MCU_BUILD", MCU_DIR / "build"))
THIRD_PARTY = ROOT / "third_party"

CRT_VERSION = "0.0.post6206"
CRT_WHEEL = f"pythondata_software_compiler_rt-{CRT_VERSION}-py3-none-any.whl"
CRT_FLOAT_FILES = ("addsf3", "subsf3", "mulsf3", "divsf3", "comparesf2")

SIM_TIMEOUT = 120          # seconds per simulator run
STACK_PATTERN = (0xA5, 0x5A)

MSP430_CFLAGS = ["--target=msp430", "-O2", "-g", "-ffreestanding", "-nostdlib", "-std=c99",
                 "-Wall", "-Wextra", "-Wconversion", "-Wdouble-promotion", "-pedantic",
                 "-Werror", "-ffunction-sections", "-fdata-sections"]
MSP430_MPY_BASE_SIM = "0x0130"     # mspdebug 0.22's simulated multiplier
MCS51_CFLAGS = ["-mmcs51", "--model-large", "--std-c99", "--Werror"]


class McuError(RuntimeError):
    """A build or simulator run failed (message carries the command output)."""


def tool(*names: str) -> str:
    for n in names:
        p = shutil.which(n)
        if p:
            return p
    raise McuError(f"none of {', '.join(names)} is installed (apt: clang-14 lld-14 llvm-14 "
                   "mspdebug sdcc sdcc-ucsim)")


def _run(cmd, timeout=SIM_TIMEOUT, cwd=None, check=True) -> str:
    cmd = [str(c) for c in cmd]
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=cwd)
    except subprocess.TimeoutExpired as e:
        raise McuError(f"timed out after {timeout} s (breakpoint never reached?): "
                       + " ".join(cmd)) from e
    out = r.stdout + r.stderr
    if check and r.returncode != 0:
        raise McuError(f"failed ({r.returncode}): {' '.join(cmd)}\n{out}")
    return out


# ------------------------------------------------------------ compiler-rt ---
def compiler_rt_builtins() -> Path:
    """compiler-rt's generic soft-float C (PyPI pythondata-software-compiler-rt,
    NCSA/MIT, LICENSE.TXT kept beside it), fetched into third_party/ (git-ignored)."""
    crt = THIRD_PARTY / "crt" / "pythondata_software_compiler_rt" / "data"
    builtins = crt / "lib" / "builtins"
    if all((builtins / f"{f}.c").exists() for f in CRT_FLOAT_FILES):
        return builtins
    THIRD_PARTY.mkdir(parents=True, exist_ok=True)
    wheel = THIRD_PARTY / CRT_WHEEL
    if not wheel.exists():
        _run([sys.executable, "-m", "pip", "download", "--no-deps", "-q",
              f"pythondata-software-compiler-rt=={CRT_VERSION}", "-d", THIRD_PARTY], timeout=300)
    with zipfile.ZipFile(wheel) as z:
        z.extractall(THIRD_PARTY / "crt")
    if not (crt / "LICENSE.TXT").exists() or not builtins.exists():
        raise McuError(f"{wheel} does not contain lib/builtins and LICENSE.TXT")
    return builtins


# ------------------------------------------------------------------ images ---
@dataclass
class Image:
    target: str                      # "msp430" or "mcs51"
    path: Path                       # .elf or .ihx
    hwmult: bool = False             # msp430: built for the hardware multiplier
    symbols: dict = field(default_factory=dict)   # name -> address (mcs51: (space, addr))
    sizes: dict = field(default_factory=dict)     # msp430: name -> symbol size


def _key(*parts) -> str:
    h = hashlib.sha1()
    for p in parts:
        h.update(str(p).encode())
        h.update(b"\0")
    return h.hexdigest()[:12]


def _file_key(paths) -> str:
    return _key(*[Path(p).read_bytes() for p in paths])


def _msp430_runtime(hwmult: bool) -> list[Path]:
    """Start-up + helper objects for one multiplier choice, cached by content."""
    clang = tool("clang-14", "clang")
    m = MCU_DIR / "msp430"
    crt = compiler_rt_builtins()
    hw = ["-mhwmult=f5series"] if hwmult else []
    srcs = [m / "crt0.S", m / "rt_builtin.S", m / "rt_int.c", m / "rt_float.c"] + \
           ([m / "rt_hwmul.c"] if hwmult else [])
    out = BUILD_DIR / "msp430-rt" / (("hw-" if hwmult else "sw-") + _file_key(srcs))
    objs = [out / (s.name + ".o") for s in srcs] + [out / f"crt_{f}.o" for f in CRT_FLOAT_FILES]
    if all(o.exists() for o in objs):
        return objs
    out.mkdir(parents=True, exist_ok=True)
    for s in srcs:
        if s.suffix == ".S":
            _run([clang, "--target=msp430", "-c", s, "-o", out / (s.name + ".o")])
        else:
            extra = ["-DMPY_BASE=" + MSP430_MPY_BASE_SIM] if s.name == "rt_hwmul.c" else []
            _run([clang, *MSP430_CFLAGS, *hw, *extra, "-c", s, "-o", out / (s.name + ".o")])
    for f in CRT_FLOAT_FILES:   # third-party code, unmodified: its warnings are not ours
        _run([clang, *[x for x in MSP430_CFLAGS if x not in ("-Werror", "-pedantic")], *hw,
              "-w", "-D__builtin_clz=__builtin_clzl", "-I", crt, "-c", crt / f"{f}.c",
              "-o", out / f"crt_{f}.o"])
    return objs


def _defs(defines) -> list[str]:
    items = defines.items() if isinstance(defines, dict) else [(d, None) for d in defines]
    return [f"-D{k}" if v is None else f"-D{k}={v}" for k, v in items]


def build_msp430(sources, harness, defines=(), *, hwmult=True, name=None,
                 include_dirs=(), outdir=None) -> Image:
    """Compile `sources` (code under test) and `harness` (main) with clang-14
    for the MSP430F5510, warnings as errors, and link with the start-up and
    helpers of bench/mcu/msp430.  hwmult: -mhwmult=f5series and the 16x16
    multiplier helpers built for the simulator's 0x0130."""
    clang, lld = tool("clang-14", "clang"), tool("ld.lld-14", "ld.lld")
    sources = [Path(s).resolve() for s in sources]
    harness = Path(harness).resolve()
    dflags = _defs(defines)
    inc = [f"-I{d}" for d in [CSRC_INCLUDE, *include_dirs, harness.parent]]
    name = name or harness.stem
    outdir = Path(outdir or BUILD_DIR / "msp430" /
                  f"{name}-{'hw' if hwmult else 'sw'}-{_key(*dflags, *sources, *inc)}")
    if outdir.exists():
        shutil.rmtree(outdir)
    outdir.mkdir(parents=True)
    hw = ["-mhwmult=f5series"] if hwmult else []
    objs = []
    for s in [harness, *sources]:       # harness and code under test: separate units, no LTO
        o = outdir / (s.stem + ".o")
        if s.suffix == ".S":            # port-layer assembly: preprocessed, warnings as errors
            _run([clang, "--target=msp430", "-Werror", *dflags, *inc, "-c", s, "-o", o])
        else:
            _run([clang, *MSP430_CFLAGS, *hw, *dflags, *inc, "-c", s, "-o", o])
        objs.append(o)
    elf = outdir / f"{name}.elf"
    link = [lld, "-T", MCU_DIR / "msp430" / "msp430f5510.ld", "--gc-sections",
            "--defsym=__mspabi_addf=__addsf3", "--defsym=__mspabi_subf=__subsf3",
            "--defsym=__mspabi_mpyf=__mulsf3", "--defsym=__mspabi_divf=__divsf3",
            "--defsym=__mspabi_cmpf=__lesf2", *_msp430_runtime(hwmult)]
    for _ in range(4):      # add the csrc/*.c that define still-undefined symbols
        try:
            _run([*link, *objs, "-o", elf])
            break
        except McuError as e:
            extra = _csrc_defining(re.findall(r"undefined symbol: (\w+)", str(e)), sources)
            if not extra:
                raise
            for s in extra:
                o = outdir / (s.stem + ".o")
                _run([clang, *MSP430_CFLAGS, *hw, *dflags, *inc, "-c", s, "-o", o])
                objs.append(o)
                sources.append(s)
    img = Image("msp430", elf, hwmult)
    _msp430_symbols(img)
    return img


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
    if "--stack-auto" not in flags or "--xstack" in flags:
        return []
    src = SDCC_LIB_SRC / "_mullong.c"
    if not src.exists():
        raise McuError(f"{src} missing (Debian package sdcc-libraries)")
    out = BUILD_DIR / "mcs51-rt" / _file_key([src])
    rel = out / "mullong_auto.rel"
    if rel.exists():
        return [rel]
    out.mkdir(parents=True, exist_ok=True)
    text = _run([tool("sdcc"), "-mmcs51", "--model-large", "--stack-auto", "--std-c99",
                 "-U__SDCC_MODEL_LARGE", "-D__SDCC_MODEL_SMALL", "-c", src, "-o", rel], cwd=out)
    asm = (out / "mullong_auto.asm").read_text()
    if "warning" in text.lower() or "mul\tab" not in asm:
        raise McuError(f"sdcc did not build the assembly __mullong from {src}:\n{text}")
    return [rel]


MCS51_OBJ_OUTPUTS = (".rel", ".asm", ".lst", ".sym")


def _mcs51_compile(sdcc, sources, flags, outdir) -> list[Path]:
    """sdcc -c of each source into outdir, two at a time (sdcc takes up to a
    minute for a large module).  Objects are cached by the preprocessed text
    and the flags, so builds that differ only in the harness (fixed / float,
    another vector set) compile the csrc/ modules once."""
    from concurrent.futures import ThreadPoolExecutor

    def one(src):
        pre = _run([sdcc, *flags, "-E", src])
        # -I/-D are in the preprocessed text already
        cache = BUILD_DIR / "mcs51-obj" / f"{src.stem}-{_key(pre, *[f for f in flags if f[:2] not in ('-I', '-D')])}"
        if not (cache / (src.stem + ".rel")).exists():
            tmp = cache.with_name(cache.name + f".tmp{os.getpid()}")
            shutil.rmtree(tmp, ignore_errors=True)
            tmp.mkdir(parents=True)
            out = _run([sdcc, *flags, "-c", src, "-o", str(tmp) + "/"], cwd=tmp)
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
    sources = [Path(s).resolve() for s in sources]
    harness = Path(harness).resolve()
    dflags = _defs(defines)
    inc = [f"-I{d}" for d in [CSRC_INCLUDE, *include_dirs, harness.parent]]
    name = name or harness.stem
    outdir = Path(outdir or BUILD_DIR / "mcs51" / f"{name}-{_key(*dflags, *sources, *inc, *extra_flags, *extra_rels)}")
    if outdir.exists():                 # a failed link leaves a stale .ihx: start clean
        shutil.rmtree(outdir)
    outdir.mkdir(parents=True)
    flags = [*MCS51_CFLAGS, *extra_flags, *dflags, *inc]
    rels = _mcs51_compile(sdcc, [harness, *sources], flags, outdir)
    ihx = outdir / f"{harness.stem}.ihx"
    for _ in range(4):      # add the csrc/*.c that define still-undefined symbols
        out = _run([sdcc, *MCS51_CFLAGS, *extra_flags, *rels, *extra_rels, "-o", ihx], cwd=outdir,
                   check=False)
        extra = _csrc_defining([n[1:] for n in re.findall(r"Undefined Global '(\w+)'", out)],
                               sources)
        if not extra:
            break
        rels += _mcs51_compile(sdcc, extra, flags, outdir)
        sources += extra
        if ihx.exists():
            ihx.unlink()
    if "ASlink-Error" in out or "Undefined Global" in out or not ihx.exists():
        raise McuError(f"sdcc link failed in {outdir}:\n{out}")
    img = Image("mcs51", ihx)
    _mcs51_symbols(img)
    return img


# ------------------------------------------------------------- symbols -------
def _msp430_symbols(img: Image) -> None:
    out = _run([tool("llvm-objdump-14", "llvm-objdump"), "-t", img.path])
    for line in out.splitlines():
        f = line.split()
        if len(f) >= 5 and re.fullmatch(r"[0-9a-f]{8}", f[0]):
            img.symbols[f[-1]] = int(f[0], 16)
            if re.fullmatch(r"[0-9a-f]{8}", f[-2]):
                img.sizes[f[-1]] = int(f[-2], 16)


def _mcs51_symbols(img: Image) -> None:
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


def text_bytes(img: Image, func: str) -> int:
    """Bytes of code of one function.  MSP430: the ELF symbol size.  8051:
    distance to the next code symbol in the .map (static helpers that sdcc
    places right after the function are included: state it)."""
    if img.target == "msp430":
        if func not in img.sizes:
            raise McuError(f"{func} not in {img.path}")
        return img.sizes[func]
    code = sorted(a for s, a in img.symbols.values() if s == "code")
    sp, addr = img.symbols["_" + func]
    nxt = [a for a in code if a > addr]
    if not nxt:
        raise McuError(f"no code symbol after _{func}")
    return nxt[0] - addr


# ---------------------------------------------------------------- MSP430 run --
def _msp430_call_site(img: Image, target: int, caller="main"):
    """(address of the first 'call #target' in caller, address after it)"""
    dis = _run([tool("llvm-objdump-14", "llvm-objdump"), "-d",
                f"--disassemble-symbols={caller}", img.path])
    lines = [ln for ln in dis.splitlines() if re.match(r"\s+[0-9a-f]+:", ln)]
    for i, ln in enumerate(lines):
        m = re.search(r"\tcall\t#(\d+)\s*$", ln)
        if m and int(m.group(1)) == target:
            return int(ln.split(":")[0], 16), int(lines[i + 1].split(":")[0], 16)
    raise McuError(f"no 'call #{target:#x}' in {caller} of {img.path}")


def _mspdebug(img: Image, cmds) -> str:
    pre = ["prog " + str(img.path)] + (["simio add hwmult mul"] if img.hwmult else []) + \
          ["simio add tracer tr"]
    return _run(["timeout", str(SIM_TIMEOUT + 5), tool("mspdebug"), "-q", "sim", *pre, *cmds])


def _msp430_counts(out: str):
    ins = re.findall(r"Instruction count:\s+(\d+)", out)
    clk = re.findall(r"MCLK:\s+(\d+)", out)
    if not ins or not clk:
        raise McuError("no tracer counts in mspdebug output:\n" + out[-2000:])
    return int(ins[-1]), int(clk[-1])


def _hexdump(out: str, addr: int, n: int, line_re: str) -> bytes:
    mem = {}
    for m in re.finditer(line_re, out, re.M):
        for i, h in enumerate(m.group(2).split()):
            mem[int(m.group(1), 16) + i] = int(h, 16)
    missing = [addr + i for i in range(n) if addr + i not in mem]
    if missing:
        raise McuError(f"memory dump lacks {len(missing)} bytes from {missing[0]:#x}")
    return bytes(mem[addr + i] for i in range(n))


_MSP_MD = r"^\s+([0-9a-f]{4,5}):((?: [0-9a-f]{2})+)"


def _msp430_md(out, addr, n):
    return _hexdump(out, addr, n, _MSP_MD)


def _msp430_sp(out: str) -> int:
    m = re.findall(r"\(\s*SP: ([0-9a-f]{5})\)", out)
    if not m:
        raise McuError("no SP in mspdebug regs output:\n" + out[-2000:])
    return int(m[1], 16)            # registers shown at the 2nd stop: the entry


def _stack_used(dump: bytes, base: int, top: int) -> int:
    """bytes between `top` and the lowest byte that no longer holds the pattern"""
    for i, b in enumerate(dump):
        if b != STACK_PATTERN[(base + i) % 2]:
            return top - (base + i)
    return 0


def _measure_msp430(img, funcs, regions, reads, stack):
    s = img.symbols
    res = {"funcs": {}, "regions": {}, "reads": {}}
    for fn in funcs:
        entry = s[fn]
        site, ret = _msp430_call_site(img, entry)
        # first stop at the call in main, then at the entry: other callers
        # of fn (a batch loop before the call) are not counted
        to_entry = [f"setbreak {site:#x}", "run", "delbreak", f"setbreak {entry:#x}", "run"]
        out = _mspdebug(img, to_entry + ["regs", "simio config tr clear",
                              "delbreak", f"setbreak {ret:#x}", "run", "simio info tr"])
        ins, clk = _msp430_counts(out)
        row = {"instructions": ins, "cycles": clk}
        if stack:
            sp = _msp430_sp(out)            # at entry: SP points at the return address
            lo = s["__bss_end"]
            n = sp - lo
            out = _mspdebug(img, to_entry + [
                                  f"fill {lo:#x} {n} {STACK_PATTERN[0]:#x} {STACK_PATTERN[1]:#x}",
                                  "delbreak", f"setbreak {ret:#x}", "run", f"md {lo:#x} {n}"])
            row["stack_bytes"] = _stack_used(_msp430_md(out, lo, n), lo, sp + 2)
        res["funcs"][fn] = row
    for reg in regions:
        a, b = reg.split(":")
        out = _mspdebug(img, [f"setbreak {s[a]:#x}", "run", "simio config tr clear", "delbreak",
                              f"setbreak {s[b]:#x}", "run", "simio info tr"])
        ins, clk = _msp430_counts(out)
        res["regions"][reg] = {"instructions": ins, "cycles": clk}
    cmds = [f"setbreak {s['_exit']:#x}", "run", "simio info tr"]
    for name, n in reads.items():
        cmds.append(f"md {s[name]:#x} {n}")
    out = _mspdebug(img, cmds)
    res["total"] = dict(zip(("instructions", "cycles"), _msp430_counts(out)))
    for name, n in reads.items():
        res["reads"][name] = _msp430_md(out, s[name], n)
    return res


# ------------------------------------------------------------------ 8051 run --
_STATE = re.compile(r"Inst= (\d+) Fetch= (\d+) Read= (\d+) Write= (\d+).*?\((\d+) clks\)", re.S)
_S51_DUMP = r"^0x([0-9a-f]{2,})((?: [0-9a-f]{2}(?= |$))+)"


def _s51(img: Image, script, cpu="C52") -> str:
    return _run(["timeout", str(SIM_TIMEOUT + 5), tool("s51"), "-b", "-t", cpu, "-X", "12M",
                 "-e", "\n".join(list(script) + ["quit"]), img.path])


def _mcs51_call_site(img: Image, fn: str, caller: str = "main"):
    """(address of the first 'lcall _fn' inside `caller` (main) in the .rst
    listings, return address).  Only calls in main count: a batch loop in
    another harness function (run_batch) calls fn first.  fn may name its
    caller as "fn@caller" (the call of fn inside that harness function)."""
    if "@" in fn:
        fn, caller = fn.split("@")
    pat = re.compile(r"^\s+([0-9A-F]{6}) 12 [0-9A-F]{2} [0-9A-F]{2}\s.*\blcall\s+_%s\s*$" % fn)
    label = re.compile(r"^\s+[0-9A-F]{6}\s+\d+ (_[A-Za-z0-9_]+):\s*$")
    for rst in sorted(img.path.parent.glob("*.rst")):
        inside = False
        for line in open(rst):
            m = label.match(line)
            if m:
                inside = m.group(1) == "_" + caller
                continue
            m = pat.match(line)
            if m and inside:
                return int(m.group(1), 16), int(m.group(1), 16) + 3
    raise McuError(f"no 'lcall _{fn}' in _{caller} of the .rst listings of {img.path}")


def _state_delta(out: str):
    st = [tuple(map(int, m)) for m in _STATE.findall(out)]
    if len(st) < 2:
        raise McuError("s51 did not reach both breakpoints:\n" + out[-2000:])
    d = [y - x for x, y in zip(st[-2], st[-1])]
    d[0] -= 1             # ucsim's Inst= reads one high across a resumed breakpoint
    return {"instructions": d[0], "cycles": d[4], "machine_cycles": d[4] // 12,
            "code_bytes_fetched": d[1], "data_reads": d[2], "data_writes": d[3]}


def _mcs51_sp(out: str) -> int:
    m = re.findall(r"^0x81 ([0-9a-f]{2})", out, re.M)
    if not m:
        raise McuError("no SP dump in s51 output:\n" + out[-2000:])
    return int(m[-1], 16)


def _mcs51_history(img, to_entry, n_instructions, cpu, chunk=4000) -> str:
    """s51 output listing the execution history of n instructions from the
    stop reached by `to_entry` (stepped in chunks that fit s51's
    10000-entry ring)."""
    script = list(to_entry) + ["delete"]       # a breakpoint would stop a step early
    left = n_instructions
    while left > 0:
        k = min(chunk, left)
        script += ["history clear", f"step {k}", f"history list {k}"]
        left -= k
    out = _s51(img, script, cpu)
    # from the first step on: the echo of `break` before it shows an
    # instruction line too, which the histogram would count
    m = re.search(r"^Stop at 0x[0-9a-f]+: \(\d+\) stepped", out, re.M)
    if not m:
        raise McuError("s51 did not step:\n" + out[-2000:])
    return out[m.start():]


def _timing():
    from lab.mcu import mcs51_timing
    return mcs51_timing


def _mcs51_1t(img, to_entry, n_instructions, cpu):
    """Opcode histogram of one call (s51 execution history) weighed with the
    per-opcode tables of mcs51/timing.py."""
    timing = _timing()
    return timing.weigh(timing.histogram(_mcs51_history(img, to_entry, n_instructions, cpu)))


def _mcs51_code_labels(img: Image) -> list:
    """(address, name) of every code label: functions of the modules (static
    ones too, from the .rst listings) and library routines (from the .map)."""
    labels = {}
    for line in open(img.path.with_suffix(".map")):
        m = re.match(r"^C:\s+([0-9A-F]{8})\s+(\S+)", line)
        if m and not m.group(2).startswith(("s_", "l_")):
            labels.setdefault(int(m.group(1), 16), m.group(2))
    for rst in img.path.parent.glob("*.rst"):
        code = False
        for line in open(rst):
            m = re.search(r"\.area\s+(\S+)(.*)$", line)
            if m:                   # labels of data areas share the addresses
                code = "CODE" in m.group(2)
                continue
            m = re.match(r"^\s+([0-9A-F]{6})\s+\d+ (_[A-Za-z0-9_]+):", line)
            if m and code:          # .map names first (__mullong, not _mullong_dummy)
                labels.setdefault(int(m.group(1), 16), m.group(2))
    return sorted(labels.items())


def _mcs51_code_lines(img: Image) -> dict:
    """address -> "file.c:line" of every instruction sdcc listed under a C
    source comment in the .rst listings (runtime libraries have none)."""
    where = {}
    src = re.compile(r";\s+(\S+\.c):(\d+):")
    ins = re.compile(r"^\s+([0-9A-F]{6}) ([0-9A-F]{2} )+")
    for rst in img.path.parent.glob("*.rst"):
        loc = None
        for line in open(rst):
            m = src.search(line)
            if m:
                loc = f"{Path(m.group(1)).name}:{m.group(2)}"
                continue
            m = ins.match(line)
            if m and loc:
                where[int(m.group(1), 16)] = loc
    return where


def profile_lines_mcs51(img: Image, func: str, n_instructions: int) -> list[dict]:
    """As profile() for an 8051 image, per C source line: 12T clocks and
    instructions of one call, each instruction attributed to the source
    comment sdcc put above it (library routines by name)."""
    timing = _timing()
    where = _mcs51_code_lines(img)
    rows = {}
    for pc, op, name, _ in _mcs51_trace(img, func, n_instructions, "C52"):
        loc = where.get(pc, name)
        r = rows.setdefault(loc, {"line": loc, "instructions": 0, "clocks_12T": 0})
        r["instructions"] += 1
        r["clocks_12T"] += 12 * timing.classic_machine_cycles(op)
    return sorted(rows.values(), key=lambda r: -r["clocks_12T"])


def _mcs51_trace(img, func, n_instructions, cpu):
    """(pc, opcode, function name, whether pc is the function's first
    instruction) of each instruction the simulator executes in the first
    n_instructions of one call of func."""
    import bisect
    timing = _timing()
    entry = img.symbols["_" + func.split("@")[0]][1]
    site, _ = _mcs51_call_site(img, func)
    to_entry = [f"break {site:#x}", "run", "delete", f"break {entry:#x}", "run"]
    out = _mcs51_history(img, to_entry, n_instructions, cpu)
    labels = _mcs51_code_labels(img)
    starts = [a for a, _ in labels]
    for seg in re.split(r"^Host usage:.*$", out, flags=re.M)[1:]:
        for m in timing._HIST_LINE.finditer(seg.split("Stop at")[0]):
            pc, op = int(m.group(1), 16), int(m.group(2).split()[0], 16)
            i = bisect.bisect_right(starts, pc) - 1
            if i < 0:
                yield pc, op, f"{pc:#x}", False
            else:
                yield pc, op, labels[i][1][1:], pc == labels[i][0]


def _profile_mcs51(img, func, n_instructions, cpu="C52"):
    timing = _timing()
    rows = {}
    for pc, op, name, entered in _mcs51_trace(img, func, n_instructions, cpu):
        r = rows.setdefault(name, {"function": name, "instructions": 0, "calls": 0,
                                   "clocks_12T": 0, "clocks_1t_stc_y5": 0})
        r["instructions"] += 1
        r["clocks_12T"] += 12 * timing.classic_machine_cycles(op)
        r["clocks_1t_stc_y5"] += timing.stc_y5_clocks(op)
        r["calls"] += entered
    return sorted(rows.values(), key=lambda r: -r["clocks_12T"])


def _measure_mcs51(img, funcs, regions, reads, stack, one_t=True, cpu="C52"):
    s = img.symbols
    res = {"funcs": {}, "regions": {}, "reads": {}}
    for fn in funcs:
        entry = s["_" + fn.split("@")[0]][1]
        site, ret = _mcs51_call_site(img, fn)
        to_entry = [f"break {site:#x}", "run", "delete", f"break {entry:#x}", "run"]
        script = to_entry + ["state"]
        sp = None
        if stack:   # internal RAM above SP is free: paint it, find the highest byte touched
            sp = _mcs51_sp(_s51(img, to_entry + ["dump /h sfr 0x81 0x81"], cpu))
            script += [f"fill iram {sp + 1:#x} 0xff {STACK_PATTERN[0]:#x}"]
        script += [f"break {ret:#x}", "run", "state"]
        if stack:
            script += [f"dump /h iram {sp + 1:#x} 0xff"]
        out = _s51(img, script, cpu)
        row = _state_delta(out)
        if stack:
            dump = _hexdump(out, sp + 1, 0xff - sp, _S51_DUMP)
            hi = max([i for i, b in enumerate(dump) if b != STACK_PATTERN[0]], default=-1)
            row["stack_bytes"] = hi + 1 + 2      # + the 2-byte return address at SP-1..SP
        if one_t:
            w = _mcs51_1t(img, to_entry, row["instructions"], cpu)
            if w["instructions"] != row["instructions"] or w["clocks_12T"] != row["cycles"]:
                raise McuError(f"{fn}: opcode histogram x 8051 table = {w}, s51 counted {row}")
            row["clocks_1t_stc_y5"] = w["clocks_stc_y5"]
        res["funcs"][fn] = row
    for reg in regions:
        a, b = reg.split(":")
        out = _s51(img, [f"break {s['_' + a][1]:#x}", "run", "state",
                         f"break {s['_' + b][1]:#x}", "run", "state"], cpu)
        res["regions"][reg] = _state_delta(out)
    script = [f"break {s['_bench_done'][1]:#x}", "run", "state"]
    for name, n in reads.items():
        space, addr = s["_" + name]
        script.append(f"dump /h {space} {addr:#x} {addr + n - 1:#x}")
    out = _s51(img, script, cpu)
    st = [tuple(map(int, m)) for m in _STATE.findall(out)]
    if not st:
        raise McuError("s51 never reached _bench_done:\n" + out[-2000:])
    res["total"] = {"instructions": st[-1][0], "cycles": st[-1][4]}
    sp = re.findall(r"Max value of stack pointer= 0x([0-9a-f]+)", out)
    if sp:      # whole run; s51 also reports "Stack overflow" if SP passed 0xFF
        res["total"]["max_sp"] = int(sp[-1], 16)
    res["total"]["stack_overflow"] = "Stack overflow" in out
    for name, n in reads.items():
        res["reads"][name] = _hexdump(out, s["_" + name][1], n, _S51_DUMP)
    return res


def measure(img: Image, funcs=(), regions=(), reads=None, stack=True, **kw) -> dict:
    """Run `img` in its simulator.
    funcs:   functions called directly from main(); per function: instructions
             and cycles from its first instruction through its return (MSP430:
             MCLK; 8051: 12T clocks), stack_bytes (return address included).
    regions: "start:stop" marker functions; counts from entry to entry.
    reads:   {symbol: nbytes} read back after the program ends (MSP430: at
             _exit; 8051: at bench_done()).  Little-endian raw bytes."""
    reads = dict(reads or {})
    if img.target == "msp430":
        return _measure_msp430(img, funcs, regions, reads, stack)
    return _measure_mcs51(img, funcs, regions, reads, stack, **kw)


# ---------------------------------------------------------------- profile ---
def profile(img: Image, func: str, n_instructions: int) -> list[dict]:
    """Instruction profile of one call of `func` (called from main): the
    simulator single-steps the call and attributes each executed instruction
    to the function containing its address.  Rows: function, instructions
    (exclusive), calls (entries at its first address), sorted by instructions.
    MSP430: mspdebug `step`.  8051: s51's execution history, rows also carry
    clocks_12T and clocks_1t_stc_y5 (mcs51/timing.py), sorted by 12T clocks;
    static functions are named from the .rst listings."""
    return _profile(img, func, n_instructions, by_line=False)


def profile_lines(img: Image, func: str, n_instructions: int) -> list[dict]:
    """As profile(), per source line (file:line from the debug information,
    inlined code attributed to the line it was inlined from)."""
    return _profile(img, func, n_instructions, by_line=True)


def _profile(img, func, n_instructions, by_line):
    if img.target == "mcs51" and not by_line:
        return _profile_mcs51(img, func, n_instructions)
    if img.target != "msp430":
        raise McuError("profile_lines() is for MSP430 images")
    funcs = sorted((a, n) for n, a in img.symbols.items()
                   if img.sizes.get(n, 0) > 0 and a >= 0x8000)
    starts = [a for a, _ in funcs]
    import bisect
    entry = img.symbols[func]
    site, _ = _msp430_call_site(img, entry)
    out = _mspdebug(img, [f"setbreak {site:#x}", "run", "delbreak", f"setbreak {entry:#x}", "run",
                          "delbreak"] + ["step"] * n_instructions)
    pcs = [int(p, 16) for p in re.findall(r"\(\s*PC: ([0-9a-f]{5})\)", out)][1:]
    rows = {}
    if by_line:
        addrs = sorted(set(pcs[:n_instructions]))
        sym = _run([tool("llvm-addr2line-14", "llvm-addr2line"), "-e", img.path,
                    *[f"{a:#x}" for a in addrs]])
        where = dict(zip(addrs, (ln.strip() for ln in sym.splitlines())))
        import bisect
        funcs = sorted((a, n) for n, a in img.symbols.items() if img.sizes.get(n, 0) > 0)
        starts = [a for a, _ in funcs]
        for pc in pcs[:n_instructions]:
            loc = re.sub(r"^.*/", "", where.get(pc, "?"))
            if loc.startswith("??"):              # no line info (runtime helpers)
                i = bisect.bisect_right(starts, pc) - 1
                loc = funcs[i][1] if i >= 0 else f"{pc:#x}"
            r = rows.setdefault(loc, {"line": loc, "instructions": 0})
            r["instructions"] += 1
        return sorted(rows.values(), key=lambda r: -r["instructions"])
    for pc in pcs[:n_instructions]:           # the first PC is the entry: executed next
        i = bisect.bisect_right(starts, pc) - 1
        name = funcs[i][1] if i >= 0 else f"{pc:#x}"
        r = rows.setdefault(name, {"function": name, "instructions": 0, "calls": 0})
        r["instructions"] += 1
        if i >= 0 and pc == funcs[i][0]:
            r["calls"] += 1
    return sorted(rows.values(), key=lambda r: -r["instructions"])


def _mcs51_code_closure(img: Image, func: str) -> dict:
    """8051: code labels reachable from _func through lcall/ljmp/acall/ajmp
    in the .rst listings; size of a label = distance to the next code label
    (sdcc places a module's functions back to back).  Library routines have
    no listing here: their own calls are not followed (the fixed chain's
    __mullong, __gptrget, __gptrput call nothing)."""
    labels = _mcs51_code_labels(img)
    addrs = [a for a, _ in labels]
    size = {n: (addrs[i + 1] - a if i + 1 < len(addrs) else 0) for i, (a, n) in enumerate(labels)}
    calls, cur = {}, None
    for rst in img.path.parent.glob("*.rst"):
        for line in open(rst):
            m = re.match(r"^\s+[0-9A-F]{6}\s+\d+ (_[A-Za-z0-9_]+):", line)
            if m:
                cur = m.group(1)
                continue
            m = re.search(r"\b(?:lcall|ljmp|acall|ajmp)\s+(_[A-Za-z0-9_]+)\s*$", line)
            if m and cur:
                calls.setdefault(cur, set()).add(m.group(1))
    by_name = {n: a for a, n in labels}
    seen, todo = {}, ["_" + func]
    while todo:
        f = todo.pop()
        if f in seen or f not in by_name:
            continue
        seen[f] = size[f]
        todo.extend(calls.get(f, ()))
    return {k[1:]: v for k, v in seen.items()}


def code_closure(img: Image, func: str) -> dict:
    """Every function reachable from `func` through calls and tail branches,
    with its size in bytes: {name: bytes}.  Runtime helpers (names starting
    with '__' and mem*) are included; split them with is_helper().  MSP430
    from the disassembly; 8051 from the .rst listings (_mcs51_code_closure)."""
    if img.target == "mcs51":
        return _mcs51_code_closure(img, func)
    dis = _run([tool("llvm-objdump-14", "llvm-objdump"), "-d", img.path])
    by_addr = {a: n for n, a in img.symbols.items() if img.sizes.get(n, 0) > 0}
    calls, cur = {}, None
    for line in dis.splitlines():
        m = re.match(r"^([0-9a-f]+) <([^>]+)>:", line)
        if m:
            cur = m.group(2)
            calls.setdefault(cur, set())
            continue
        m = re.search(r"\t(?:call|br)\t#(\d+)\s*$", line)
        if m and cur and int(m.group(1)) in by_addr:
            calls[cur].add(by_addr[int(m.group(1))])
    seen, todo = {}, [func]
    while todo:
        f = todo.pop()
        if f in seen:
            continue
        seen[f] = img.sizes.get(f, 0)
        todo.extend(calls.get(f, ()))
    return seen


def is_helper(name: str) -> bool:
    """Runtime helpers: MSP430 __mspabi_*, __addsf3, mem*; 8051 (C-level
    names from code_closure) _mullong, _gptrget, ___fsadd, ..."""
    return name.startswith("_") or name in ("memcpy", "memset", "memmove")


def symbol_size(img: Image, name: str) -> int:
    """bytes of a data symbol (MSP430: ELF size; 8051: not available -> KeyError)"""
    return img.sizes[name]


def mcs51_module_sizes(img: Image, module: str) -> dict:
    """Area sizes of one module's .rel (CSEG code, CONST, XSEG/DSEG/OSEG data)."""
    text = (img.path.parent / f"{module}.rel").read_text()
    return {m.group(1): int(m.group(2), 16)
            for m in re.finditer(r"^A (\S+) size ([0-9A-F]+)", text, re.M)}


def _csrc_defining(symbols, have) -> list[Path]:
    """csrc/*.c files (not yet in `have`) that define one of `symbols`."""
    found = []
    for f in c_sources():
        if f in have or f in found:
            continue
        text = f.read_text()
        if any(re.search(r"^[A-Za-z_][^;{}()]*\b%s\s*\([^;]*$" % re.escape(n), text, re.M)
               for n in symbols):
            found.append(f)
    return found


def c_sources() -> list[Path]:
    """Every .c file of the C library (csrc/<area>/*.c)."""
    return sorted(CSRC.glob("*/*.c"))


def c_source(module: str) -> Path:
    """The path of one C module by name: c_source("sig_pwl") -> csrc/tcomp/sig_pwl.c."""
    found = [f for f in c_sources() if f.stem == module]
    if len(found) != 1:
        raise McuError(f"no single C module named {module!r} under {CSRC}")
    return found[0]


def csrc_sources(*modules: str) -> list[Path]:
    """The csrc .c files a module needs: the closure over `#include "x.h"`
    (in headers and sources) of x.c files that exist.  csrc_sources("sig_chain")
    follows the files as they are today, so a helper moved into its own .c
    is picked up without touching the benches."""
    by_stem = {f.stem: f for f in c_sources()}
    headers = {h.name: h for h in CSRC.rglob("*.h")}
    todo = [by_stem[m] for m in modules]
    seen, out = set(), []
    while todo:
        f = todo.pop()
        if f in seen:
            continue
        seen.add(f)
        if f.suffix == ".c":
            out.append(f)
        for inc in re.findall(r'^\s*#\s*include\s+"([^"]+)"', f.read_text(), re.M):
            name = Path(inc).name
            todo += [x for x in (headers.get(name), by_stem.get(Path(name).stem)) if x is not None]
    return sorted(out)


def run_until(img: Image, stop: str, reads) -> dict:
    """Run `img` from reset until the function `stop` is entered (a firmware's
    own "results ready" hook, not a bench marker) and read back {symbol:
    nbytes} as little-endian raw bytes.  McuError if `stop` is never reached."""
    reads = dict(reads)
    s = img.symbols
    if img.target == "msp430":
        out = _mspdebug(img, [f"setbreak {s[stop]:#x}", "run", "regs"] +
                        [f"md {s[name]:#x} {n}" for name, n in reads.items()])
        pc = re.findall(r"\(\s*PC: ([0-9a-f]{5})\)", out)
        if not pc or int(pc[-1], 16) != s[stop]:
            raise McuError(f"mspdebug never reached {stop}:\n" + out[-2000:])
        return {name: _msp430_md(out, s[name], n) for name, n in reads.items()}
    script = [f"break {s['_' + stop][1]:#x}", "run", "state"]
    for name, n in reads.items():
        space, addr = s["_" + name]
        script.append(f"dump /h {space} {addr:#x} {addr + n - 1:#x}")
    out = _s51(img, script)
    if not re.search(r"Stop at 0x0*%x" % s["_" + stop][1], out, re.I) or "Stack overflow" in out:
        raise McuError(f"s51 never reached {stop} or overflowed the stack:\n" + out[-2000:])
    return {name: _hexdump(out, s["_" + name][1], n, _S51_DUMP) for name, n in reads.items()}


def image_from_file(path, hwmult=False) -> Image:
    """An Image for a program built elsewhere (a firmware's own Makefile):
    .elf -> MSP430 (hwmult: its multiplier helpers need the simulated
    multiplier), .ihx -> 8051 (its .map beside it)."""
    path = Path(path)
    img = Image("msp430" if path.suffix == ".elf" else "mcs51", path, hwmult)
    if img.target == "msp430":
        _msp430_symbols(img)
    else:
        _mcs51_symbols(img)
    return img
