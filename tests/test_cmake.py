"""The CMake build a firmware or host project takes: configure, build the
core library `sigcore` warning-free (gcc -std=c99 -Wall -Wextra -Wconversion
-pedantic -Werror, in both sig_real forms and with optimisation, where more
warnings fire), run the tests/c unit tests through ctest, install the
headers and a CMake package, and build a program against the installed
package with find_package(sigcore).  With clang the libFuzzer harnesses are
targets too, and ctest replays their seed corpora."""
import re
import subprocess

import pytest

from conftest import ROOT, require_tool


def run(cmd, cwd=None):
    res = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, cwd=cwd, timeout=600)
    assert res.returncode == 0, " ".join(map(str, cmd)) + "\n" + res.stdout + res.stderr
    return res.stdout + res.stderr


def configure_build_test(tmp_path, cc, *options, with_tests=True):
    cmake = require_tool("cmake")
    ctest = require_tool("ctest")
    build = tmp_path / "build"
    run([cmake, "-S", ROOT, "-B", build, f"-DCMAKE_C_COMPILER={cc}", *options])
    out = run([cmake, "--build", build, "-j2"])
    assert "warning" not in out.lower(), out
    if not with_tests:
        return build, ""
    tested = run([ctest, "--test-dir", build, "--output-on-failure"])
    assert "100% tests passed" in tested, tested
    return build, tested


@pytest.mark.parametrize("real", ["OFF", "ON"], ids=["float", "double"])
def test_gcc_builds_core_and_unit_tests(tmp_path, real):
    gcc = require_tool("gcc")
    build, tested = configure_build_test(tmp_path, gcc, f"-DSIG_REAL_DOUBLE={real}",
                                         "-DCMAKE_BUILD_TYPE=Release")
    assert (build / "libsigcore.a").exists()
    units = sorted(p.stem for p in (ROOT / "tests" / "c").glob("test_*.c"))
    assert all(f" {u} " in tested for u in units), tested


def test_installed_package_links_into_a_project(tmp_path):
    gcc = require_tool("gcc")
    cmake = require_tool("cmake")
    build, _ = configure_build_test(tmp_path, gcc, f"-DCMAKE_INSTALL_PREFIX={tmp_path / 'prefix'}",
                                    "-DSIG_BUILD_TESTS=OFF", with_tests=False)
    run([cmake, "--install", build])
    assert (tmp_path / "prefix" / "include" / "sigcore" / "sig_status.h").exists()
    app = tmp_path / "app"
    app.mkdir()
    (app / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.16)\nproject(app C)\n"
        "find_package(sigcore REQUIRED)\nadd_executable(app main.c)\n"
        "target_link_libraries(app PRIVATE sigcore::sigcore)\n")
    (app / "main.c").write_text(
        '#include <stdio.h>\n#include "sig_crc16.h"\n#include "sig_status.h"\n'
        "int main(void) {\n"
        '    static const uint8_t msg[] = "123456789";\n'
        "    printf(\"%u %d\\n\", (unsigned)sig_crc16_ccitt(SIG_CRC16_INIT, msg, 9), (int)SIG_ERR_CRC);\n"
        "    return 0;\n}\n")
    run([cmake, "-S", app, "-B", app / "build", f"-DCMAKE_C_COMPILER={gcc}",
         f"-DCMAKE_PREFIX_PATH={tmp_path / 'prefix'}"])
    run([cmake, "--build", app / "build"])
    out = subprocess.run([str(app / "build" / "app")], capture_output=True, text=True).stdout.split()
    assert out == [str(0x29B1), "-4"]        # CRC-16/CCITT-FALSE check value of "123456789"


def test_clang_builds_fuzz_harnesses_and_replays_corpora(tmp_path):
    clang = require_tool("clang-14", "clang")
    _, tested = configure_build_test(tmp_path, clang, "-DSIG_BUILD_FUZZ=ON")
    harnesses = sorted(p.stem for p in (ROOT / "fuzz").glob("fuzz_*.c"))
    assert all(f" {h}_corpus " in tested for h in harnesses), tested


def test_msp430_toolchain_file_cross_builds_the_library(tmp_path):
    require_tool("clang-14", "clang")
    require_tool("llvm-ar-14", "llvm-ar")
    cmake = require_tool("cmake")
    objdump = require_tool("llvm-objdump-14", "llvm-objdump")
    build = tmp_path / "build"
    run([cmake, "-S", ROOT, "-B", build, f"-DCMAKE_TOOLCHAIN_FILE={ROOT / 'cmake' / 'msp430-clang.cmake'}"])
    out = run([cmake, "--build", build, "-j2"])
    assert "warning" not in out.lower(), out
    formats = set(re.findall(r"file format (\S+)", run([objdump, "-f", build / "libsigcore.a"])))
    assert formats == {"elf32-msp430"}
    assert not (build / "CTestTestfile.cmake").exists()     # no host tests in a cross build
