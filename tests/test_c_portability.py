"""Every csrc/ file compiles warning-free for the host (gcc, strict C99), for
the MSP430 (clang --target=msp430), for the 8051 (sdcc -mmcs51) and for the
ATmega328P (gcc-avr -Os, as the Arduino library builds it), in both float
forms, and includes nothing beyond stdint/stddef/stdbool."""
import re
import subprocess

import pytest

from conftest import CSRC, CSRC_INCLUDE, c_sources, require_tool

SOURCES = c_sources()
ALLOWED_SYSTEM_HEADERS = {"stdint.h", "stddef.h", "stdbool.h"}


@pytest.mark.parametrize("src", SOURCES + sorted(CSRC.rglob("*.h")), ids=lambda p: p.name)
def test_only_freestanding_headers(src):
    system = set(re.findall(r'#\s*include\s*<([^>]+)>', src.read_text()))
    assert system <= ALLOWED_SYSTEM_HEADERS, f"{src.name} includes {system - ALLOWED_SYSTEM_HEADERS}"


def _compile(cmd):
    res = subprocess.run(cmd, capture_output=True, text=True)
    out = res.stdout + res.stderr
    assert res.returncode == 0 and "warning" not in out.lower(), " ".join(map(str, cmd)) + "\n" + out


@pytest.mark.parametrize("real", ["float", "double"])
@pytest.mark.parametrize("src", SOURCES, ids=lambda p: p.name)
def test_gcc_strict(src, real, tmp_path):
    gcc = require_tool("gcc")
    defs = ["-DSIG_REAL_DOUBLE"] if real == "double" else []
    _compile([gcc, "-std=c99", "-Wall", "-Wextra", "-Wconversion", "-Wshadow", "-pedantic",
              "-Werror", "-O2", *defs, "-I", str(CSRC_INCLUDE), "-c", str(src), "-o", str(tmp_path / "x.o")])


@pytest.mark.parametrize("src", SOURCES, ids=lambda p: p.name)
def test_clang_msp430(src, tmp_path):
    clang = require_tool("clang-14", "clang")
    _compile([clang, "--target=msp430", "-std=c99", "-ffreestanding", "-Wall", "-Wextra",
              "-Wconversion", "-Wdouble-promotion", "-pedantic", "-Werror", "-O2",
              "-I", str(CSRC_INCLUDE), "-c", str(src), "-o", str(tmp_path / "x.o")])


@pytest.mark.parametrize("src", SOURCES, ids=lambda p: p.name)
def test_sdcc_mcs51(src, tmp_path):
    sdcc = require_tool("sdcc")
    _compile([sdcc, "-mmcs51", "--model-large", "--std-c99", "-I", str(CSRC_INCLUDE),
              "-c", str(src), "-o", str(tmp_path) + "/"])


@pytest.mark.parametrize("src", SOURCES, ids=lambda p: p.name)
def test_gcc_avr(src, tmp_path):
    gcc = require_tool("avr-gcc")
    _compile([gcc, "-mmcu=atmega328p", "-std=c99", "-Wall", "-Wextra", "-Wconversion", "-Wshadow",
              "-pedantic", "-Werror", "-Os", "-I", str(CSRC_INCLUDE), "-c", str(src),
              "-o", str(tmp_path / "x.o")])
