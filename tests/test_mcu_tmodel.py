"""The one firmware entry point for any model (sig_tmodel) in the MCU
simulators: an image fitted by `pysig fit --model` (a table on raw uint16
codes, a polynomial on 0.01 °C), stored as a const array, loaded by
sig_tmodel_load_image on the MSP430F5510 (clang), the 8051 (sdcc) and the
ATmega328P (gcc-avr, simavr), applied
to a batch of codes and readings: the outputs read back equal the host C
(through Cython) and the reference (spec.tmodel) bit for bit."""
import struct

import numpy as np
import pytest

from conftest import ROOT, require_target_tools
from lab.mcu import runner
from lab.mcu.tmodel_vectors import N, tmodel_case as _case, write_tmodel_header as _header
from spec import tmodel as ref
from pysig.tcomp import _tmodel

HARNESS = ROOT / "bench" / "mcu" / "harness"
SOURCES = runner.csrc_sources("sig_tmodel", "sig_tmodel_image")


@pytest.mark.parametrize("target", ["msp430", "mcs51", "avr"])
@pytest.mark.parametrize("family", ["table", "poly"])
def test_firmware_equals_host_and_reference(target, family, tmp_path):
    require_target_tools(target)
    img, codes, readings = _case(family)
    _header(tmp_path / "tmodel_vectors.h", img, codes, readings)
    if target == "msp430":
        fw = runner.build_msp430(SOURCES, HARNESS / "tmodel_harness.c", [], include_dirs=[tmp_path])
    elif target == "avr":
        fw = runner.build_avr(SOURCES, HARNESS / "tmodel_harness.c", [], include_dirs=[tmp_path])
    else:
        fw = runner.build_mcs51(SOURCES, HARNESS / "tmodel_harness.c", [], include_dirs=[tmp_path],
                                extra_flags=["--stack-auto"])
    n, a = readings.shape
    r = runner.measure(fw, reads={"vec_out": 2 * n * a, "vec_status": 2 * n, "init_status": 2,
                                  "loaded_family": 1}, stack=False)["reads"]
    assert struct.unpack("<h", r["init_status"])[0] == 0
    host = _tmodel.TModel.from_image(img)
    assert r["loaded_family"][0] == {"poly": 1, "compact": 2, "table": 3}[host.family] \
        and host.family == family
    fw_out = np.frombuffer(r["vec_out"], "<i2").reshape(n, a)
    fw_st = np.frombuffer(r["vec_status"], "<i2")
    h_out, h_st = host.apply(codes, readings)
    np.testing.assert_array_equal(fw_out, h_out)
    np.testing.assert_array_equal(fw_st, h_st)
    _, m = ref.load(img)
    for i in range(n):
        out, st = ref.apply(m, int(codes[i]), [int(v) for v in readings[i]])
        assert list(fw_out[i]) == out and fw_st[i] == st, f"vector {i}"
    assert (fw_st & 1).any() and (fw_st & 2).any() and (fw_st == 0).any()
