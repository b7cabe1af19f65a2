"""The one firmware entry point for any model (sig_tmodel) in the MCU
simulators: an image fitted by `pysig fit --model` (a table on raw uint16
codes, a polynomial on 0.01 °C), stored as a const array, loaded by
sig_tmodel_load_image on the MSP430F5510 (clang) and the 8051 (sdcc), applied
to a batch of codes and readings: the outputs read back equal the host C
(through Cython) and the reference (spec.tmodel) bit for bit."""
import struct

import numpy as np
import pytest

from conftest import ROOT, require_target_tools
from lab.mcu import runner
from spec import tmodel as ref
from pysig.tcomp import _tmodel
from pysig.tcomp import _calibration as tmodel
from pysig.tcomp._tempcode import CELSIUS, raw_code

HARNESS = ROOT / "bench" / "mcu" / "harness"
SOURCES = runner.csrc_sources("sig_tmodel", "sig_tmodel_image")
N = 40


def _case(family):
    rng = np.random.default_rng(5)
    if family == "table":
        codes = np.arange(63000, 65001, 4).astype(float)
        temp_code = raw_code(codes)
        cols = {"x": np.rint(600 * np.sin((codes - 63000) / 400.0)), "y": np.rint(0.1 * (codes - 64000))}
        spec = "table:17"
        test_codes = np.concatenate([[0, 62999, 63000, 65000, 65001, 65535],
                                     rng.integers(62900, 65100, N - 6)])
        temp = codes
    else:
        temp = np.linspace(-20.0, 60.0, 500)
        temp_code = CELSIUS
        cols = {"x": np.rint(300 * ((temp - 20) / 40) ** 2), "y": np.rint(-5 * temp),
                "z": np.rint(40 * np.sin(temp / 9))}
        spec = "poly:3"
        t = np.concatenate([[-32768, -2001, -2000, 6000, 6001, 32767], rng.integers(-2500, 6500, N - 6)])
        test_codes = t & 0xFFFF
    m = tmodel.fit_model(temp, cols, spec=spec, temp_code=temp_code).model
    img = tmodel.image_bytes(m)
    readings = rng.integers(-32768, 32768, (N, len(cols))).astype(np.int16)
    readings[:4] = [[32767] * len(cols), [-32768] * len(cols), [0] * len(cols), [100] * len(cols)]
    return img, test_codes.astype(np.int64), readings


def _header(path, img, codes, readings):
    rows = ",\n".join("{" + ", ".join(str(int(v)) for v in r) + "}" for r in readings)
    path.write_text(f"""#define TM_N {len(codes)}u
#define TM_AXES {readings.shape[1]}u
#define TM_IMAGE_LEN {len(img)}u
#define TM_STORAGE {3 * 64}u
static const uint8_t tm_image[{len(img)}] = {{ {', '.join(str(b) for b in img)} }};
static const uint16_t tm_code[TM_N] = {{ {', '.join(f'{int(c)}u' for c in codes)} }};
static const int16_t tm_in[TM_N][TM_AXES] = {{ {rows} }};
""")


@pytest.mark.parametrize("target", ["msp430", "mcs51"])
@pytest.mark.parametrize("family", ["table", "poly"])
def test_firmware_equals_host_and_reference(target, family, tmp_path):
    require_target_tools(target)
    img, codes, readings = _case(family)
    _header(tmp_path / "tmodel_vectors.h", img, codes, readings)
    if target == "msp430":
        fw = runner.build_msp430(SOURCES, HARNESS / "tmodel_harness.c", [], include_dirs=[tmp_path])
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
