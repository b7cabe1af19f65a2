"""Firmware == Python for the compact compensation (csrc/tcomp/sig_tcomp16.c): the
very csrc/ code, built for the MSP430F5510 (clang: multiplier helpers on
mspdebug's simulated 16x16 MPY; the inline build whose csrc/include/sig_port.h hooks
are csrc/port/msp430/sig_port_msp430.h, MAC/MACS on that multiplier; the
no-multiplier build) and for the 8051 (sdcc --model-large), runs 50
temperature/reading pairs in the simulators; the
outputs and statuses read back must equal the host C (Cython) and the Python
spec bit for bit.  Vectors: bench/lab/mcu/tcomp16_vectors.py (the int32 rows'
cases of bench/mcu_cost.py, quantised to the compact form)."""
import struct

import numpy as np
import pytest

from conftest import ROOT, require_tool
from lab.mcu import runner
from lab.mcu import tcomp16_vectors

HARNESS = ROOT / "bench" / "mcu" / "harness" / "tcomp16_harness.c"
SRC = runner.csrc_sources("sig_tcomp16")
PORT_DIR = runner.PORT_MSP430        # sig_port_msp430.h
INLINE_DEFINES = {"SIG_PORT_HEADER": '"sig_port_msp430.h"', "MPY_BASE": runner.MSP430_MPY_BASE_SIM}


@pytest.mark.parametrize("target,hwmult,order", [
    ("msp430", True, 2), ("msp430", True, 5), ("msp430", False, 2),
    ("msp430", "inline", 1), ("msp430", "inline", 2), ("msp430", "inline", 5),
    ("mcs51", None, 2)],
    ids=["msp430-hw-o2", "msp430-hw-o5", "msp430-sw-o2",
         "msp430-inline-o1", "msp430-inline-o2", "msp430-inline-o5", "mcs51-o2"])
def test_tcomp16_firmware_equals_host_and_reference(target, hwmult, order, tmp_path):
    if target == "msp430":
        require_tool("clang-14", "clang")
        require_tool("mspdebug")
        require_tool("ld.lld-14", "ld.lld")
    else:
        require_tool("sdcc")
        require_tool("s51")
    from pysig.tcomp._tcomp16 import Tcomp16Q
    from spec import tcomp16 as ref
    case = tcomp16_vectors.tcomp16_case(order)
    tcomp16_vectors.write_tcomp16_header(case, tmp_path / "tcomp16_vectors.h")
    if target == "msp430" and hwmult == "inline":
        img = runner.build_msp430(SRC, HARNESS, INLINE_DEFINES, hwmult=True,
                                  include_dirs=[tmp_path, PORT_DIR])
        # the hooks took effect: no multiply helper is reachable any more
        assert not [f for f in runner.code_closure(img, "sig_tcomp16_apply_q") if runner.is_helper(f)]
    elif target == "msp430":
        img = runner.build_msp430(SRC, HARNESS, [], hwmult=hwmult, include_dirs=[tmp_path])
    else:
        img = runner.build_mcs51(SRC, HARNESS, [], include_dirs=[tmp_path])
    t, x = case.base.t_q, case.base.in_q
    n, a = x.shape
    r = runner.measure(img, reads={"vec_out": 2 * n * a, "vec_status": 2 * n, "init_status": 2},
                       stack=False)["reads"]
    assert struct.unpack("<h", r["init_status"])[0] == 0
    fw_out = np.frombuffer(r["vec_out"], "<i2").reshape(n, a)
    fw_st = np.frombuffer(r["vec_status"], "<i2")

    h_out, h_st = Tcomp16Q.from_compact(case.compact).apply(t, x)
    np.testing.assert_array_equal(fw_out, h_out)
    np.testing.assert_array_equal(fw_st, h_st)
    for i in range(n):
        out, st = ref.apply_q(case.fields, int(t[i]), [int(v) for v in x[i]])
        assert list(fw_out[i]) == out and fw_st[i] == st, f"vector {i}"
    # the batch exercises clamping and saturation, not only the easy path
    assert (fw_st & 1).any() and (fw_st & 2).any() and (fw_st == 0).any()
