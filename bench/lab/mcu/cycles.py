"""Count the cycles of single function calls in mspdebug's MSP430 simulator
or in ucsim's s51 (8051), and read result variables back.

For each FUNC the harness must call FUNC directly from main(). The script
breaks at FUNC's first instruction, then at the instruction after the call
in main, and reports the difference: the function body up to and including
its return, without the call instruction and the argument set-up.

  mcu_cycles.py msp430 bench.elf  --func poly2_q16 --read res_poly_q16:4 [--hwmult]
  mcu_cycles.py mcs51  bench.ihx  --func poly2_q16 --read res_poly_q16:4 [--cpu C52]
        (mcs51 reads bench.map and the .rst listings next to the .ihx)
  --region bench_start:bench_stop  counts from the entry of one marker
        function to the entry of another, e.g. around a loop of N calls.
Prints one JSON object per line.  Standard library only."""
import argparse, json, os, re, subprocess

def dump_bytes(out, addr, n, line_re):
    """collect n bytes at addr from a hex dump (one 'ADDR b0 b1 ...' per line)"""
    mem = {}
    for m in re.finditer(line_re, out, re.M):
        for i, h in enumerate(m.group(2).split()):
            mem[int(m.group(1), 16) + i] = h
    return [mem.get(addr + i) for i in range(n)]

def run(cmd, timeout=300):
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise SystemExit("timed out: a breakpoint was never reached? %s" % cmd)
    return r.stdout + r.stderr

# ---------------------------------------------------------------- MSP430 ---
def msp430_symbols(elf):
    syms = {}
    for line in run(["llvm-objdump-14", "-t", elf]).splitlines():
        f = line.split()
        if len(f) >= 5 and re.fullmatch(r"[0-9a-f]{8}", f[0]):
            syms[f[-1]] = int(f[0], 16)
    return syms

def msp430_return_after_call(elf, target):
    """address of the instruction after the first 'call #target' in main"""
    dis = run(["llvm-objdump-14", "-d", "--disassemble-symbols=main", elf])
    lines = [l for l in dis.splitlines() if re.match(r"\s+[0-9a-f]+:", l)]
    for i, l in enumerate(lines):
        m = re.search(r"\tcall\t#(\d+)\s*$", l)
        if m and int(m.group(1)) == target:
            return int(lines[i + 1].split(":")[0], 16)
    raise SystemExit("no 'call #%#x' in main" % target)

def mspdebug(elf, hwmult, cmds):
    pre = ["prog " + elf] + (["simio add hwmult mul"] if hwmult else []) + ["simio add tracer tr"]
    if hwmult and os.environ.get("MPY_BASE"):      # newer mspdebug only (simx)
        pre.insert(2, "simio config mul base " + os.environ["MPY_BASE"])
    return run([os.environ.get("MSPDEBUG", "mspdebug"), "-q",
                os.environ.get("MSPDEBUG_DRIVER", "sim")] + pre + cmds)

def msp430_counts(out):
    ins = [int(x) for x in re.findall(r"Instruction count:\s+(\d+)", out)]
    clk = [int(x) for x in re.findall(r"MCLK:\s+(\d+)", out)]
    return ins[-1], clk[-1]

def msp430(a):
    syms = msp430_symbols(a.image)
    for fn in a.func:
        entry = syms[fn]
        ret = msp430_return_after_call(a.image, entry)
        out = mspdebug(a.image, a.hwmult, ["setbreak %#x" % entry, "run",
              "simio config tr clear", "delbreak", "setbreak %#x" % ret, "run",
              "simio info tr"])
        ins, clk = msp430_counts(out)
        print(json.dumps({"target": "msp430", "func": fn, "instructions": ins, "mclk_cycles": clk}))
    for reg in a.region:
        start, stop = reg.split(":")
        out = mspdebug(a.image, a.hwmult, ["setbreak %#x" % syms[start], "run",
              "simio config tr clear", "delbreak", "setbreak %#x" % syms[stop], "run",
              "simio info tr"])
        ins, clk = msp430_counts(out)
        print(json.dumps({"target": "msp430", "region": reg, "instructions": ins, "mclk_cycles": clk}))
    cmds = ["setbreak %#x" % syms["_exit"], "run", "simio info tr"]
    for r in a.read:
        name, n = r.split(":")
        cmds.append("md %#x %d" % (syms[name], int(n)))
    out = mspdebug(a.image, a.hwmult, cmds)
    ins, clk = msp430_counts(out)
    print(json.dumps({"target": "msp430", "func": "<whole program>", "instructions": ins, "mclk_cycles": clk}))
    for r in a.read:
        name, n = r.split(":")
        b = dump_bytes(out, syms[name], int(n), r"^\s+([0-9a-f]{5}):((?: [0-9a-f]{2})+)")
        print(json.dumps({"read": name, "hex_le": b}))

# ----------------------------------------------------------------- 8051 ----
def mcs51_symbols(mapfile):
    """name -> (space, address); space is code, iram or xram; and the modules"""
    syms, space, modules = {}, "iram", set()
    for line in open(mapfile):
        m = re.match(r"^([A-Z_0-9]+)\s+[0-9A-F]{8}\s+[0-9A-F]{8} =.*\((.*)\)", line)
        if m:
            attrs = m.group(2)
            space = "code" if "CODE" in attrs else "xram" if "XDATA" in attrs else "iram"
            continue
        m = re.match(r"^(?:[A-Z]:)?\s+([0-9A-F]{8})\s+(\S+)(?:\s+(\S+))?", line)
        if m:
            syms[m.group(2)] = (space, int(m.group(1), 16))
            if m.group(3):
                modules.add(m.group(3))
    return syms, modules

def mcs51_return_after_call(rst_files, fn):
    pat = re.compile(r"^\s+([0-9A-F]{6}) 12 [0-9A-F]{2} [0-9A-F]{2}\s.*\blcall\s+_%s\s*$" % fn)
    for rst in rst_files:
        for line in open(rst):
            m = pat.match(line)
            if m:
                return int(m.group(1), 16) + 3
    raise SystemExit("no 'lcall _%s' in the .rst listings" % fn)

STATE = re.compile(r"Inst= (\d+) Fetch= (\d+) Read= (\d+) Write= (\d+).*?\((\d+) clks\)", re.S)

def s51(a, script):
    return run(["s51", "-b", "-t", a.cpu, "-X", "12M", "-e", "\n".join(script + ["quit"]), a.image])

def mcs51(a):
    base = os.path.splitext(a.image)[0]
    syms, modules = mcs51_symbols(base + ".map")
    d = os.path.dirname(a.image) or "."
    rst = [os.path.join(d, m + ".rst") for m in sorted(modules) if os.path.exists(os.path.join(d, m + ".rst"))]
    for fn in a.func:
        entry = syms["_" + fn][1]
        ret = mcs51_return_after_call(rst, fn)
        out = s51(a, ["break %#x" % entry, "run", "state", "break %#x" % ret, "run", "state"])
        s = [tuple(map(int, m)) for m in STATE.findall(out)]
        if len(s) < 2:
            raise SystemExit(out)
        d = [y - x for x, y in zip(s[0], s[1])]
        d[0] -= 1          # ucsim's Inst= reads one high across a resumed breakpoint
        print(json.dumps({"target": "mcs51-" + a.cpu, "func": fn, "instructions": d[0],
                          "clocks_12T": d[4], "machine_cycles": d[4] // 12,
                          "code_bytes_fetched": d[1], "data_reads": d[2], "data_writes": d[3]}))
    for reg in a.region:
        start, stop = reg.split(":")
        out = s51(a, ["break %#x" % syms["_" + start][1], "run", "state",
                      "break %#x" % syms["_" + stop][1], "run", "state"])
        s = [tuple(map(int, m)) for m in STATE.findall(out)]
        d = [y - x for x, y in zip(s[0], s[1])]
        d[0] -= 1
        print(json.dumps({"target": "mcs51-" + a.cpu, "region": reg, "instructions": d[0],
                          "clocks_12T": d[4], "machine_cycles": d[4] // 12,
                          "code_bytes_fetched": d[1], "data_reads": d[2], "data_writes": d[3]}))
    script = ["break %#x" % syms["_bench_done"][1], "run", "state"]
    for r in a.read:
        name, n = r.split(":")
        space, addr = syms["_" + name]
        script.append("dump /h %s %#x %#x" % (space, addr, addr + int(n) - 1))
    out = s51(a, script)
    s = [tuple(map(int, m)) for m in STATE.findall(out)][-1]
    print(json.dumps({"target": "mcs51-" + a.cpu, "func": "<whole program>", "instructions": s[0], "clocks_12T": s[4]}))
    for r in a.read:
        name, n = r.split(":")
        addr = syms["_" + name][1]
        b = dump_bytes(out, addr, int(n), r"^0x([0-9a-f]{4,})((?: [0-9a-f]{2})+)")
        print(json.dumps({"read": name, "hex_le": b}))

if __name__ == "__main__":
    p = argparse.ArgumentParser()
    p.add_argument("target", choices=["msp430", "mcs51"])
    p.add_argument("image", help="msp430: .elf; mcs51: .ihx (with .map and .rst beside it)")
    p.add_argument("--func", action="append", default=[])
    p.add_argument("--read", action="append", default=[], help="SYMBOL:NBYTES")
    p.add_argument("--region", action="append", default=[],
                   help="START:STOP - from the entry of function START to the entry of STOP")
    p.add_argument("--hwmult", action="store_true", help="msp430: add mspdebug's multiplier (0x0130)")
    p.add_argument("--cpu", default="C52", help="mcs51: s51 -t type (C52: 256 B IRAM)")
    a = p.parse_args()
    (msp430 if a.target == "msp430" else mcs51)(a)
