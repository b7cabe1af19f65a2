"""Test vectors of the one firmware entry point for any model
(sig_tmodel): a calibration image fitted by pysig (a table on raw uint16
codes, a polynomial on 0.01 degC), N temperature codes with the range edges
and beyond, N readings with the int16 rails, written as tmodel_vectors.h for
bench/mcu/harness/tmodel_harness.c.  Deterministic (seeded)."""
from __future__ import annotations

import numpy as np

from pysig.tcomp import _calibration as tmodel
from pysig.tcomp._tempcode import CELSIUS, raw_code

N = 40


def tmodel_case(family):
    """(image bytes, codes, readings) of one family: "table" or "poly"."""
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


def write_tmodel_header(path, img, codes, readings):
    """tmodel_vectors.h: the image as a const array (standing for flash), codes, readings."""
    rows = ",\n".join("{" + ", ".join(str(int(v)) for v in r) + "}" for r in readings)
    path.write_text(f"""#define TM_N {len(codes)}u
#define TM_AXES {readings.shape[1]}u
#define TM_IMAGE_LEN {len(img)}u
#define TM_STORAGE {3 * 64}u
static const uint8_t tm_image[{len(img)}] = {{ {', '.join(str(b) for b in img)} }};
static const uint16_t tm_code[TM_N] = {{ {', '.join(f'{int(c)}u' for c in codes)} }};
static const int16_t tm_in[TM_N][TM_AXES] = {{ {rows} }};
""")
