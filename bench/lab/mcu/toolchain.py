"""The MCU lab's common ground: where the sources, harnesses and build
outputs are, finding and running a tool (every call under a timeout), the
Image record a build returns, cache keys for build outputs, reading a
simulator's hex dump, and fetching compiler-rt's soft-float C (the MSP430
build's float helpers).  Standard library only.
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
SIM_TIMEOUT = 120          # seconds per simulator run
STACK_PATTERN = (0xA5, 0x5A)


class McuError(RuntimeError):
    """A build or simulator run failed (message carries the command output)."""


def tool(*names: str) -> str:
    for n in names:
        p = shutil.which(n)
        if p:
            return p
    raise McuError(f"none of {', '.join(names)} is installed (apt: clang-14 lld-14 llvm-14 "
                   "mspdebug sdcc sdcc-ucsim)")


def run_tool(cmd, timeout=SIM_TIMEOUT, cwd=None, check=True) -> str:
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


@dataclass
class Image:
    target: str                      # "msp430" or "mcs51"
    path: Path                       # .elf or .ihx
    hwmult: bool = False             # msp430: built for the hardware multiplier
    symbols: dict = field(default_factory=dict)   # name -> address (mcs51: (space, addr))
    sizes: dict = field(default_factory=dict)     # msp430: name -> symbol size


def cache_key(*parts) -> str:
    h = hashlib.sha1()
    for p in parts:
        h.update(str(p).encode())
        h.update(b"\0")
    return h.hexdigest()[:12]


def file_key(paths) -> str:
    return cache_key(*[Path(p).read_bytes() for p in paths])


def define_flags(defines) -> list[str]:
    items = defines.items() if isinstance(defines, dict) else [(d, None) for d in defines]
    return [f"-D{k}" if v is None else f"-D{k}={v}" for k, v in items]


def hexdump(out: str, addr: int, n: int, line_re: str) -> bytes:
    mem = {}
    for m in re.finditer(line_re, out, re.M):
        for i, h in enumerate(m.group(2).split()):
            mem[int(m.group(1), 16) + i] = int(h, 16)
    missing = [addr + i for i in range(n) if addr + i not in mem]
    if missing:
        raise McuError(f"memory dump lacks {len(missing)} bytes from {missing[0]:#x}")
    return bytes(mem[addr + i] for i in range(n))


def stack_used(dump: bytes, base: int, top: int) -> int:
    """bytes between `top` and the lowest byte that no longer holds the pattern"""
    for i, b in enumerate(dump):
        if b != STACK_PATTERN[(base + i) % 2]:
            return top - (base + i)
    return 0


CRT_VERSION = "0.0.post6206"
CRT_WHEEL = f"pythondata_software_compiler_rt-{CRT_VERSION}-py3-none-any.whl"
CRT_FLOAT_FILES = ("addsf3", "subsf3", "mulsf3", "divsf3", "comparesf2")


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
        run_tool([sys.executable, "-m", "pip", "download", "--no-deps", "-q",
              f"pythondata-software-compiler-rt=={CRT_VERSION}", "-d", THIRD_PARTY], timeout=300)
    with zipfile.ZipFile(wheel) as z:
        z.extractall(THIRD_PARTY / "crt")
    if not (crt / "LICENSE.TXT").exists() or not builtins.exists():
        raise McuError(f"{wheel} does not contain lib/builtins and LICENSE.TXT")
    return builtins
