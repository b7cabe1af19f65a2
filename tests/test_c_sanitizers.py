"""The plain-C unit tests (tests/c/test_*.c, no Python) under AddressSanitizer
+ UndefinedBehaviorSanitizer (gcc, or clang), and under MemorySanitizer
(clang: reads of uninitialised values, which ASan does not see), with no
recovery: each test is compiled with all of csrc/*.c, in the firmware's float
form and in the host's double form, and must exit 0 with no sanitizer report."""
import os
import subprocess

import pytest

from conftest import CSRC_INCLUDE, ROOT, c_sources, require_tool

TESTS_C = ROOT / "tests" / "c"
UNIT_TESTS = sorted(TESTS_C.glob("test_*.c"))
FLAGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-g", "-O1", "-fno-omit-frame-pointer",
         "-fno-sanitize-recover=all"]
SANITIZERS = {"asan-ubsan": ["-fsanitize=address,undefined"],
              "msan": ["-fsanitize=memory", "-fsanitize-memory-track-origins"]}


# Unit tests that fail because another owner's fix has not landed: strict
# xfail naming the file and the fix, keyed by (test stem, sanitizer or None
# for both).  An XPASS means the fix landed and the entry must go.
KNOWN_GAPS = {
}


def gap_marks(stem, sanitizer):
    reason = KNOWN_GAPS.get((stem, sanitizer)) or KNOWN_GAPS.get((stem, None))
    return [pytest.mark.xfail(strict=True, reason=reason)] if reason else []


CASES = [pytest.param(src, real, san, id=f"{src.stem}-{real}-{san}", marks=gap_marks(src.stem, san))
         for src in UNIT_TESTS for real in ("float", "double") for san in sorted(SANITIZERS)]


DEFS = {"float": [], "double": ["-DSIG_REAL_DOUBLE"]}


@pytest.fixture(scope="module")
def core_objects(tmp_path_factory):
    """csrc/*.c compiled once per (compiler, real, sanitizer) and linked into
    every unit test of that build: compiling the core for each test was
    most of this file's run time."""
    cache = {}

    def get(cc, real, sanitizer):
        if (cc, real, sanitizer) not in cache:
            sources = c_sources()
            objdir = tmp_path_factory.mktemp(f"core-{real}-{sanitizer}")
            cmd = [cc, *FLAGS, *SANITIZERS[sanitizer], *DEFS[real], "-I", str(CSRC_INCLUDE), "-c", *map(str, sources)]
            res = subprocess.run(cmd, capture_output=True, text=True, cwd=objdir)
            assert res.returncode == 0, " ".join(cmd) + "\n" + res.stdout + res.stderr
            cache[cc, real, sanitizer] = [objdir / (c.stem + ".o") for c in sources]
        return cache[cc, real, sanitizer]
    return get


@pytest.mark.parametrize("src,real,sanitizer", CASES)
def test_c_unit_under_sanitizers(src, real, sanitizer, tmp_path, core_objects):
    if sanitizer == "msan":
        cc = require_tool("clang-14", "clang")      # gcc has no MemorySanitizer
    else:
        cc = require_tool("gcc", "clang-14", "clang")
    exe = tmp_path / src.stem
    cmd = [cc, *FLAGS, *SANITIZERS[sanitizer], *DEFS[real], "-I", str(CSRC_INCLUDE), "-I", str(TESTS_C), str(src),
           *map(str, core_objects(cc, real, sanitizer)), "-lm", "-o", str(exe)]
    res = subprocess.run(cmd, capture_output=True, text=True)
    assert res.returncode == 0, " ".join(cmd) + "\n" + res.stdout + res.stderr
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1:abort_on_error=0",
               UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1")
    run = subprocess.run([str(exe)], capture_output=True, text=True, env=env, timeout=300)
    out = run.stdout + run.stderr
    print(out)
    assert run.returncode == 0 and "runtime error" not in out and "Sanitizer" not in out, \
        f"{src.name} ({sanitizer}, {real}):\n{out}"
    assert " 0 failed" in run.stdout, out
