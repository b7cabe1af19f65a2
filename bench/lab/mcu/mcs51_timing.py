"""Per-opcode 8051 timing tables, applied to an opcode histogram taken from
ucsim's execution history (`history list`).

classic_machine_cycles(op)  Intel MCS-51 (12T) machine cycles per instruction
    (Intel MCS-51 user's manual, instruction set summary).  Used to validate
    the histogram: sum over the history x 12 must equal s51's clock count.

stc_y5_clocks(op)  1T clocks of the STC-Y5 core (STC15 series), as published
    in the STC15F2K60S2 datasheet's instruction table (transcribed from the
    CC0 machine-readable copy in github.com/cyrozap/8051-timing-db,
    cycles_STC-Y5_published.csv).  The STC12C5A60S2 has the older STC-Y3
    core whose table was not available offline: the product histogram x
    STC-Y5 is an ESTIMATE for the STC12, one number per instruction (taken
    and not-taken branches alike), internal XRAM for MOVX.
"""
from __future__ import annotations

import re
from collections import Counter


def opcode_class(op: int) -> int:
    """Masked opcode: Rn forms (low nibble 8..F) -> op & 0xF8, @Ri forms
    (low nibble 6/7, MOVX @Ri) -> op & 0xFE, AJMP/ACALL (xxx00001/xxx10001)
    -> 0x01 / 0x11; other opcodes are their own class."""
    if op & 0x1F == 0x01:
        return 0x01
    if op & 0x1F == 0x11:
        return 0x11
    lo = op & 0x0F
    if lo >= 8:
        return op & 0xF8
    if lo in (6, 7) or (op & 0xFE) in (0xE2, 0xF2):
        return op & 0xFE
    return op


# Intel MCS-51: every instruction takes 1, 2 or 4 machine cycles of 12 clocks.
_CLASSIC_TWO = {
    0x01, 0x11, 0x02, 0x12, 0x22, 0x32, 0x80, 0x73,            # jumps, calls, returns
    0x40, 0x50, 0x60, 0x70, 0x20, 0x30, 0x10,                  # JC JNC JZ JNZ JB JNB JBC
    0xB4, 0xB5, 0xB6, 0xB8, 0xD5, 0xD8,                        # CJNE, DJNZ
    0x90, 0x93, 0x83, 0xE0, 0xF0, 0xE2, 0xF2, 0xC0, 0xD0, 0xA3,  # DPTR, MOVC, MOVX, PUSH/POP, INC DPTR
    0xA8, 0x88, 0x85, 0x86, 0xA6, 0x75,                        # MOV with two memory operands
    0x43, 0x53, 0x63,                                          # ORL/ANL/XRL direct,#data
    0x82, 0xB0, 0x72, 0xA0, 0x92,                              # ANL/ORL C,(/)bit; MOV bit,C
}
_CLASSIC_FOUR = {0xA4, 0x84}                                   # MUL AB, DIV AB


def classic_machine_cycles(op: int) -> int:
    c = opcode_class(op)
    return 4 if c in _CLASSIC_FOUR else 2 if c in _CLASSIC_TWO else 1


# STC-Y5 clocks per masked opcode (STC15F2K60S2 datasheet instruction table).
_STC_Y5 = {
    0x28: 1, 0x25: 2, 0x26: 2, 0x24: 2, 0x38: 1, 0x35: 2, 0x36: 2, 0x34: 2,
    0x98: 1, 0x95: 2, 0x96: 2, 0x94: 2, 0x04: 1, 0x08: 2, 0x05: 3, 0x06: 3,
    0x14: 1, 0x18: 2, 0x15: 3, 0x16: 3, 0xA3: 1, 0xA4: 2, 0x84: 6, 0xD4: 3,
    0x58: 1, 0x55: 2, 0x56: 2, 0x54: 2, 0x52: 3, 0x53: 3,
    0x48: 1, 0x45: 2, 0x46: 2, 0x44: 2, 0x42: 3, 0x43: 3,
    0x68: 1, 0x65: 2, 0x66: 2, 0x64: 2, 0x62: 3, 0x63: 3,
    0xE4: 1, 0xF4: 1, 0x23: 1, 0x33: 1, 0x03: 1, 0x13: 1, 0xC4: 1,
    0xE8: 1, 0xE5: 2, 0xE6: 2, 0x74: 2, 0xF8: 1, 0xA8: 3, 0x78: 2, 0xF5: 2,
    0x88: 2, 0x85: 3, 0x86: 3, 0x75: 3, 0xF6: 2, 0xA6: 3, 0x76: 2, 0x90: 3,
    0x93: 5, 0x83: 4, 0xE2: 3, 0xF2: 4, 0xE0: 2, 0xF0: 3, 0xC0: 3, 0xD0: 2,
    0xC8: 2, 0xC5: 3, 0xC6: 3, 0xD6: 3,
    0xC3: 1, 0xC2: 3, 0xD3: 1, 0xD2: 3, 0xB3: 1, 0xB2: 3,
    0x82: 2, 0xB0: 2, 0x72: 2, 0xA0: 2, 0xA2: 2, 0x92: 3,
    0x40: 3, 0x50: 3, 0x20: 5, 0x30: 5, 0x10: 5, 0x11: 4, 0x12: 4, 0x22: 4,
    0x32: 4, 0x01: 3, 0x02: 4, 0x80: 3, 0x73: 5, 0x60: 4, 0x70: 4,
    0xB5: 5, 0xB4: 4, 0xB8: 4, 0xB6: 5, 0xD8: 4, 0xD5: 5, 0x00: 1,
}


def stc_y5_clocks(op: int) -> int:
    return _STC_Y5[opcode_class(op)]


_HIST_LINE = re.compile(r"^0x([0-9a-f]{4,}) [ F?]\s+((?:[0-9a-f]{2} )+)\s*[A-Z]{2,}", re.M)


def histogram(s51_output: str) -> Counter:
    """Opcode histogram of the `history list` dumps in an s51 session that
    alternates `history clear`, `step N`, `history list N`: each listing
    follows a step's "Host usage:" line and ends at the next "Stop at"."""
    hist = Counter()
    for seg in re.split(r"^Host usage:.*$", s51_output, flags=re.M)[1:]:
        for m in _HIST_LINE.finditer(seg.split("Stop at")[0]):
            hist[int(m.group(2).split()[0], 16)] += 1
    return hist


def weigh(hist: Counter) -> dict:
    return {"instructions": sum(hist.values()),
            "clocks_12T": 12 * sum(n * classic_machine_cycles(op) for op, n in hist.items()),
            "clocks_stc_y5": sum(n * stc_y5_clocks(op) for op, n in hist.items())}
