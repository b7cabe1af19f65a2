"""Run an 8051 image in ucsim's s51 (-t C52, 12T) and measure it: 12T clocks,
instructions, code bytes fetched and data accesses of a call between
breakpoints, the internal-RAM stack high-water, the 1T estimate (opcode
histogram x STC-Y5 table of mcs51_timing), profiles from s51's execution
history, memory read back at bench_done().
"""
from __future__ import annotations

import re
from pathlib import Path

from lab.mcu.toolchain import Image, McuError, SIM_TIMEOUT, STACK_PATTERN, hexdump, run_tool, tool


_STATE = re.compile(r"Inst= (\d+) Fetch= (\d+) Read= (\d+) Write= (\d+).*?\((\d+) clks\)", re.S)
_S51_DUMP = r"^0x([0-9a-f]{2,})((?: [0-9a-f]{2}(?= |$))+)"


def _s51(img: Image, script, cpu="C52") -> str:
    return run_tool(["timeout", str(SIM_TIMEOUT + 5), tool("s51"), "-b", "-t", cpu, "-X", "12M",
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


def mcs51_code_labels(img: Image) -> list:
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
    labels = mcs51_code_labels(img)
    starts = [a for a, _ in labels]
    for seg in re.split(r"^Host usage:.*$", out, flags=re.M)[1:]:
        for m in timing._HIST_LINE.finditer(seg.split("Stop at")[0]):
            pc, op = int(m.group(1), 16), int(m.group(2).split()[0], 16)
            i = bisect.bisect_right(starts, pc) - 1
            if i < 0:
                yield pc, op, f"{pc:#x}", False
            else:
                yield pc, op, labels[i][1][1:], pc == labels[i][0]


def profile_mcs51(img, func, n_instructions, cpu="C52"):
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


def measure_mcs51(img, funcs, regions, reads, stack, one_t=True, cpu="C52"):
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
            dump = hexdump(out, sp + 1, 0xff - sp, _S51_DUMP)
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
        res["reads"][name] = hexdump(out, s["_" + name][1], n, _S51_DUMP)
    return res


def run_until_mcs51(img: Image, stop: str, reads: dict) -> dict:
    """Run from reset to the entry of `stop`; {symbol: bytes} read there."""
    s = img.symbols
    script = [f"break {s['_' + stop][1]:#x}", "run", "state"]
    for name, n in reads.items():
        space, addr = s["_" + name]
        script.append(f"dump /h {space} {addr:#x} {addr + n - 1:#x}")
    out = _s51(img, script)
    if not re.search(r"Stop at 0x0*%x" % s["_" + stop][1], out, re.I) or "Stack overflow" in out:
        raise McuError(f"s51 never reached {stop} or overflowed the stack:\n" + out[-2000:])
    return {name: hexdump(out, s["_" + name][1], n, _S51_DUMP) for name, n in reads.items()}
