"""Code and data sizes from a built image: one function's bytes, the call tree
of a function with each member's size (runtime helpers apart), a data
symbol's size, an 8051 module's area sizes.
"""
from __future__ import annotations

import re

from lab.mcu.sim_mcs51 import mcs51_code_labels
from lab.mcu.toolchain import Image, McuError, run_tool, tool


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


def _mcs51_code_closure(img: Image, func: str) -> dict:
    """8051: code labels reachable from _func through lcall/ljmp/acall/ajmp
    in the .rst listings; size of a label = distance to the next code label
    (sdcc places a module's functions back to back).  Library routines have
    no listing here: their own calls are not followed (the fixed chain's
    __mullong, __gptrget, __gptrput call nothing)."""
    labels = mcs51_code_labels(img)
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
    return {k[1:]: v for k, v in _reachable("_" + func, calls, size).items()}


def _reachable(func, calls, size) -> dict:
    """{name: size[name]} of every function with a known size reachable from
    func through `calls` (name -> names it calls or branches to)."""
    seen, todo = {}, [func]
    while todo:
        f = todo.pop()
        if f in seen or f not in size:
            continue
        seen[f] = size[f]
        todo.extend(calls.get(f, ()))
    return seen


def code_closure(img: Image, func: str) -> dict:
    """Every function reachable from `func` through calls and tail branches,
    with its size in bytes: {name: bytes}.  Runtime helpers (names starting
    with '__' and mem*) are included; split them with is_helper().  MSP430
    from the disassembly; 8051 from the .rst listings (_mcs51_code_closure)."""
    if img.target == "mcs51":
        return _mcs51_code_closure(img, func)
    if img.target == "avr":
        return _avr_code_closure(img, func)
    dis = run_tool([tool("llvm-objdump-14", "llvm-objdump"), "-d", img.path])
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


def _avr_code_closure(img: Image, func: str) -> dict:
    """AVR: from avr-objdump's disassembly, following call/rcall/jmp/rjmp
    to the start of another label; a label's size is the distance to the
    next one (libgcc's and avr-libc's assembly helpers carry no ELF size)."""
    dis = run_tool([tool("avr-objdump"), "-d", "-j", ".text", img.path])
    labels, calls, cur = [], {}, None
    for line in dis.splitlines():
        m = re.match(r"^([0-9a-f]+) <([^>]+)>:", line)
        if m:
            cur = m.group(2)
            labels.append((int(m.group(1), 16), cur))
            calls.setdefault(cur, set())
            continue
        m = re.search(r"\t(?:r?call|r?jmp)\t.*; 0x[0-9a-f]+ <([^>+]+)>\s*$", line)
        if m and cur and m.group(1) != cur:
            calls[cur].add(m.group(1))
        m = re.match(r"^\s+([0-9a-f]+):", line)
        if m:
            end = int(m.group(1), 16)
    size = {n: (labels[i + 1][0] if i + 1 < len(labels) else end + 2) - a
            for i, (a, n) in enumerate(labels)}
    return _reachable(func, calls, size)


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
