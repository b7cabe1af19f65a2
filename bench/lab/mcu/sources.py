"""The C library's sources by name: every csrc/<area>/*.c, one module by
stem, the closure of a module over its #include lines, and the files that
define still-undefined symbols (the builds' link retry).
"""
from __future__ import annotations

import re
from pathlib import Path

from lab.mcu.toolchain import CSRC, McuError


def csrc_defining(symbols, have) -> list[Path]:
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


def link_adding_csrc(link, compile_more, sources: list, undefined: str):
    """link() (raises McuError naming undefined symbols); while it fails on
    symbols that csrc/*.c files not yet in `sources` define,
    compile_more(those files), add them to `sources` and link again.
    undefined: a regular expression whose group 1 is a symbol in the
    linker's message."""
    for _ in range(4):
        try:
            return link()
        except McuError as e:
            extra = csrc_defining(re.findall(undefined, str(e)), sources)
            if not extra:
                raise
            compile_more(extra)
            sources.extend(extra)
    return link()


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
