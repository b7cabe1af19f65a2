"""pysig.status mirrors csrc/include/sig_status.h: the same names with the
same values, every C code in Python and every Python member in C; and the
registry is the only header that defines a status value."""
import pathlib
import re

import pytest

from pysig.status import Status, Warn, describe

ROOT = pathlib.Path(__file__).resolve().parents[1]
INCLUDE = ROOT / "csrc" / "include"
DEFINE = re.compile(r"^#define\s+SIG_(\w+)\s+\(\(sig_status\)\s*(-?\d+)\)", re.M)


def header_codes():
    return {name: int(value) for name, value in DEFINE.findall((INCLUDE / "sig_status.h").read_text())}


def test_header_defines_codes():
    codes = header_codes()
    assert codes["OK"] == 0 and codes["ERR_CRC"] == -4 and len(codes) >= 12


def test_python_mirror_equals_header():
    python = {m.name: int(m.value) for m in Status} | {m.name: int(m.value) for m in Warn}
    assert python == header_codes()


def test_errors_negative_warnings_distinct_bits():
    codes = header_codes()
    assert all(v < 0 for k, v in codes.items() if k.startswith("ERR_"))
    bits = [v for k, v in codes.items() if k != "OK" and not k.startswith("ERR_")]
    assert all(v > 0 and v & (v - 1) == 0 for v in bits) and len(set(bits)) == len(bits)


@pytest.mark.parametrize("path", sorted(p for p in (ROOT / "csrc").rglob("*.[ch]") if p.name != "sig_status.h"),
                         ids=lambda p: p.name)
def test_no_other_file_defines_a_status(path):
    assert not DEFINE.findall(path.read_text()), f"{path.name} defines a status code outside sig_status.h"


def test_describe_every_code():
    for code in Status:
        assert describe(code) and "unknown" not in describe(code)
    for bit in Warn:
        assert describe(bit).startswith("warning: ") and "unknown" not in describe(bit)
    assert describe(-99) == "unknown error status -99"
    assert "unknown bits 0x8" in describe(8)
    assert describe(Status.ERR_EMPTY, "offset-polynomial") == "no offset-polynomial section"
    assert "compact payload" in describe(Status.ERR_FORMAT, "compact")


def test_reference_spec_constants_equal_the_registry():
    from spec import chain, effects, image
    codes = header_codes()
    spec = {"OK": chain.OK, "WARN_CLAMPED": chain.WARN_CLAMPED, "WARN_REJECTED": chain.WARN_REJECTED,
            "LIMIT_RESEEDED": chain.LIMIT_RESEEDED, "CHAIN_MOTION": chain.CHAIN_MOTION,
            "CHAIN_TARED": chain.CHAIN_TARED, "ERR_NONFINITE": chain.ERR_NONFINITE,
            "WARN_SATURATED": effects.SIG_WARN_SATURATED, "ERR_ARG": image.SIG_ERR_ARG,
            "ERR_FORMAT": image.SIG_ERR_FORMAT, "ERR_CRC": image.SIG_ERR_CRC, "ERR_EMPTY": image.SIG_ERR_EMPTY}
    assert {k: codes[k] for k in spec} == spec
