"""Run an MSP430 image in mspdebug 0.22's `sim` driver and measure it: MCLK
cycles and instructions of a call counted between breakpoints (classic
MSP430 table, not CPUX; constant-generator immediates over-counted; no
flash wait states), stack high-water by painting, memory read back at
_exit, instruction profiles by single-stepping.
"""
from __future__ import annotations

import re

from lab.mcu.toolchain import SIM_TIMEOUT, STACK_PATTERN, Image, McuError, hexdump, run_tool, stack_used, tool


def _msp430_call_site(img: Image, target: int, caller="main"):
    """(address of the first 'call #target' in caller, address after it)"""
    dis = run_tool([tool("llvm-objdump-14", "llvm-objdump"), "-d",
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
    return run_tool(["timeout", str(SIM_TIMEOUT + 5), tool("mspdebug"), "-q", "sim", *pre, *cmds])


def _msp430_counts(out: str):
    ins = re.findall(r"Instruction count:\s+(\d+)", out)
    clk = re.findall(r"MCLK:\s+(\d+)", out)
    if not ins or not clk:
        raise McuError("no tracer counts in mspdebug output:\n" + out[-2000:])
    return int(ins[-1]), int(clk[-1])


_MSP_MD = r"^\s+([0-9a-f]{4,5}):((?: [0-9a-f]{2})+)"


def _msp430_md(out, addr, n):
    return hexdump(out, addr, n, _MSP_MD)


def _msp430_sp(out: str) -> int:
    m = re.findall(r"\(\s*SP: ([0-9a-f]{5})\)", out)
    if not m:
        raise McuError("no SP in mspdebug regs output:\n" + out[-2000:])
    return int(m[1], 16)            # registers shown at the 2nd stop: the entry


def measure_msp430(img, funcs, regions, reads, stack):
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
            row["stack_bytes"] = stack_used(_msp430_md(out, lo, n), lo, sp + 2)
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


def profile_msp430(img: Image, func: str, n_instructions: int, by_line: bool) -> list[dict]:
    """Single-step one call of `func` (from main) in mspdebug and attribute
    each executed instruction to its function (rows: function, instructions,
    calls) or, by_line, to its source line (file:line from the debug
    information; runtime helpers without line information by name)."""
    import bisect
    funcs = sorted((a, n) for n, a in img.symbols.items()
                   if img.sizes.get(n, 0) > 0 and a >= 0x8000)
    starts = [a for a, _ in funcs]
    entry = img.symbols[func]
    site, _ = _msp430_call_site(img, entry)
    out = _mspdebug(img, [f"setbreak {site:#x}", "run", "delbreak", f"setbreak {entry:#x}", "run",
                          "delbreak"] + ["step"] * n_instructions)
    pcs = [int(p, 16) for p in re.findall(r"\(\s*PC: ([0-9a-f]{5})\)", out)][1:]
    rows = {}
    if by_line:
        addrs = sorted(set(pcs[:n_instructions]))
        sym = run_tool([tool("llvm-addr2line-14", "llvm-addr2line"), "-e", img.path,
                        *[f"{a:#x}" for a in addrs]])
        where = dict(zip(addrs, (ln.strip() for ln in sym.splitlines())))
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


def run_until_msp430(img: Image, stop: str, reads: dict) -> dict:
    """Run from reset to the entry of `stop`; {symbol: bytes} read there."""
    s = img.symbols
    out = _mspdebug(img, [f"setbreak {s[stop]:#x}", "run", "regs"] +
                    [f"md {s[name]:#x} {n}" for name, n in reads.items()])
    pc = re.findall(r"\(\s*PC: ([0-9a-f]{5})\)", out)
    if not pc or int(pc[-1], 16) != s[stop]:
        raise McuError(f"mspdebug never reached {stop}:\n" + out[-2000:])
    return {name: _msp430_md(out, s[name], n) for name, n in reads.items()}
