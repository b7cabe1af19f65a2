"""The MCU pipeline itself (bench/lab/mcu/runner.py): both toolchains build the
recipe's reference functions with warnings as errors, the simulators run them,
and the results read back equal a host computation bit for bit.  A missing
hardware multiplier, a wrong MPY_BASE, a missing .data copy or a wrong s51 CPU
all give plausible cycle counts with wrong results: this test catches them."""
import struct

import numpy as np
import pytest

from conftest import ROOT, require_tool
from lab.mcu import runner
from lab.mcu import vectors

SELF = ROOT / "bench" / "mcu" / "selftest"
COEF = [210371, -29930, 806]          # harness.c: 3.21, -0.4567, 0.0123 in Q16.16
X = 1536819                           # 23.45


def poly2_q16_host():
    y = COEF[2]
    for c in (COEF[1], COEF[0]):
        y = ((y * X) >> 16) + c       # Python ints: exact int64 product, floor shift
    return y


def poly2_f_host():
    c = np.array([3.21, -0.4567, 0.0123], dtype=np.float32)
    x = np.float32(23.45)
    return (c[2] * x + c[1]) * x + c[0]


def i32(b):
    return struct.unpack("<i", b)[0]


def f32(b):
    return np.frombuffer(b, dtype="<f4")[0]


@pytest.mark.parametrize("hwmult", [True, False], ids=["hwmult", "no-mult"])
def test_msp430_selftest_bit_exact(hwmult):
    for t in ("clang-14", "mspdebug"):
        require_tool(t)
    img = runner.build_msp430([SELF / "bench_funcs.c"], SELF / "harness.c", hwmult=hwmult)
    r = runner.measure(img, funcs=["poly2_q16"],
                       reads={"res_poly_q16": 4, "res_poly_n32": 4, "res_poly_f": 4})
    assert i32(r["reads"]["res_poly_q16"]) == poly2_q16_host() == i32(r["reads"]["res_poly_n32"])
    assert f32(r["reads"]["res_poly_f"]) == poly2_f_host()
    row = r["funcs"]["poly2_q16"]
    assert row["instructions"] > 0 and row["cycles"] >= row["instructions"]
    assert 2 < row["stack_bytes"] < 200
    assert 0 < runner.text_bytes(img, "poly2_q16") < 1000


def test_mcs51_selftest_bit_exact_and_histogram_matches_s51():
    for t in ("sdcc", "s51"):
        require_tool(t)
    img = runner.build_mcs51([SELF / "bench_funcs.c"], SELF / "harness.c",
                             defines=["BENCH_NO_INT64"])
    # measure() cross-checks the opcode histogram x the Intel table against
    # s51's own clock count and raises on any difference
    r = runner.measure(img, funcs=["poly2_f", "poly2_q16_n32"],
                       reads={"res_poly_n32": 4, "res_poly_f": 4})
    assert i32(r["reads"]["res_poly_n32"]) == poly2_q16_host()
    assert f32(r["reads"]["res_poly_f"]) == poly2_f_host()
    row = r["funcs"]["poly2_f"]
    assert row["cycles"] % 12 == 0 and row["clocks_1t_stc_y5"] < row["cycles"]
    assert row["stack_bytes"] >= 2


def test_warnings_are_errors(tmp_path):
    require_tool("clang-14")
    src = tmp_path / "warn.c"
    src.write_text("int f(int x) { int unused; return x; }\n")
    harness = tmp_path / "main.c"
    harness.write_text("int main(void) { return 0; }\n")
    with pytest.raises(runner.McuError, match="unused"):
        runner.build_msp430([src], harness, outdir=tmp_path / "o")
    require_tool("sdcc")
    src.write_text("int f(long x) { char c = x; return c; }\nint g(void) { int v; return v; }\n")
    with pytest.raises(runner.McuError, match="before initialization"):
        runner.build_mcs51([src], harness, outdir=tmp_path / "o51")


@pytest.mark.parametrize("hwmult", [True, False], ids=["hwmult", "no-mult"])
def test_msp430_int32_multiply_helper(hwmult, tmp_path):
    """__mspabi_mpyl(_f5hw) on random, sign-extended 16-bit (its fast path)
    and edge operands: the low 32 bits of the exact product."""
    for t in ("clang-14", "mspdebug"):
        require_tool(t)
    from lab.mcu import vectors
    rng = np.random.default_rng(5)
    edges = [0, 1, -1, 32767, -32768, 32768, -32769, 65535, -65536, 2**31 - 1, -2**31]
    a = list(rng.integers(-2**31, 2**31, 40)) + list(rng.integers(-32768, 32768, 40)) + edges * 2
    b = list(rng.integers(-2**31, 2**31, 40)) + list(rng.integers(-32768, 32768, 40)) + \
        edges + edges[::-1]
    (tmp_path / "mul_vectors.h").write_text(
        f"#define MUL_N {len(a)}\n"
        + vectors.c_array("int32_t", "mul_a", a, vectors.c_int32, const=False)
        + vectors.c_array("int32_t", "mul_b", b, vectors.c_int32, const=False))
    img = runner.build_msp430([], SELF / "mul_harness.c", hwmult=hwmult,
                              include_dirs=[tmp_path], outdir=tmp_path / "o")
    got = runner.measure(img, reads={"prod": 4 * len(a)})["reads"]["prod"]
    got = struct.unpack(f"<{len(a)}i", got)
    want = [((int(x) * int(y) + 2**31) % 2**32) - 2**31 for x, y in zip(a, b)]
    assert list(got) == want
