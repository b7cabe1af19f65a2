"""Units, value scales and temperature sources carried from the log to the
firmware: a log in a physical unit calibrates with a value scale that keeps
its drift (or is refused with the remedy), the image and the C header carry
the units, `apply` uses the file's own, and nothing that lost the signal is
exported.  Generated logs in tesla, µV, g, raw int16 codes and 24-bit
counts, far from one another."""
import re
import subprocess

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from conftest import CSRC_INCLUDE, require_tool
from pysig.cli import main
from pysig.errors import InputFileError, RangeError
from pysig.io import read_csv
from pysig.store import SECTION_OFFSET_POLY, SECTION_TEMP_CODE, SECTION_UNITS, build_image
from pysig.tcomp._sections import units_payload
from pysig.store._image import read_image
from pysig.tcomp import _calibration as tmodel
from pysig.tcomp import _poly_fit
from pysig.tcomp._tmodel import load_units
from spec import image as ref_image


def write_columns(path, cols, fmt="{:.9g}"):
    names = list(cols)
    lines = [",".join(names)] + [",".join(fmt.format(float(v)) for v in row) for row in zip(*cols.values())]
    path.write_text("\n".join(lines) + "\n")
    return path


def magnetometer_log(path, seed=1, n=3000, drift=1e-7, curvature=2e-9):
    """Readings in tesla (~2e-5), drift ~1e-7 T/°C and a little curvature,
    the board's uint16 temperature code (about 63000..65000), time in ms."""
    rng = np.random.default_rng(seed)
    temp_c = np.linspace(-20.0, 60.0, n) + rng.normal(0, 0.05, n)
    code = np.round(62766.7 + temp_c / 0.03)              # °C = code x 0.03 - 1883
    bx = 2.0e-5 + drift * (temp_c - 25) + curvature * (temp_c - 25) ** 2 + rng.normal(0, 2e-9, n)
    by = -1.5e-5 - 0.8 * drift * (temp_c - 25) + rng.normal(0, 2e-9, n)
    return write_columns(path, {"time_ms": np.arange(n) * 100.0, "temp_code": code, "bx": bx, "by": by})


def drift_slope(x, temp):
    return abs(np.polyfit(temp, x, 1)[0])


def test_tesla_log_calibrates_with_a_chosen_value_scale_and_the_image_needs_no_unit_flags(tmp_path, capsys):
    src = magnetometer_log(tmp_path / "mag.csv")
    mj, img, hdr, out = (tmp_path / n for n in ("m.json", "m.bin", "mag.h", "out.csv"))
    assert main(["fit", str(src), "--temp", "temp_code", "--temp-unit", "raw", "--temp-scale", "0.03",
                 "--temp-offset", "-1883", "--columns", "bx,by", "-o", str(mj)]) == 0
    printed = capsys.readouterr().out
    assert "value scale 2e+08 chosen" in printed and "1 LSB = 5e-09 in the column's unit" in printed
    model = tmodel.load(mj)
    assert model.value_scale == 2e8
    assert main(["export", str(mj), "--format", "c", "--name", "mag", "-o", str(hdr)]) == 0
    text = hdr.read_text()
    coef = re.search(r"mag_coef_q\[\d+\] = \{(.*?)\};", text, re.S).group(1)
    values = [int(v) for v in re.findall(r"-?\d+(?=[,\s])", re.sub(r"/\*.*?\*/", "", coef))]
    assert len(values) == 2 * (model.order + 1) and sum(v != 0 for v in values) >= 2
    for words in ("Source log: mag.csv", "code x 0.03 - 1883", "T0 (the correction is 0 there): code",
                  "round(column value x 2e+08)", "CV error:", f"pysig {__import__('pysig').__version__}",
                  "Calibrated range: code"):
        assert words in text, words
    lo, hi = model.t_lo + 32768, model.t_hi + 32768
    assert f"code {lo:.0f} (" in text and f"code {hi:.0f} (" in text       # the codes fit printed
    assert main(["export", str(mj), "--format", "image", "-o", str(img)]) == 0
    assert main(["apply", str(src), "--model", str(img), "--temp", "temp_code", "--columns", "bx,by",
                 "-o", str(out)]) == 0
    assert "value scale 2e+08" in capsys.readouterr().out
    d = read_csv(out)
    for a in ("bx", "by"):
        assert drift_slope(d[a + "_comp"], d["temp_code"]) < 0.01 * drift_slope(d[a], d["temp_code"])
        assert np.std(d[a + "_comp"]) < 0.01 * np.std(d[a])
    assert not d["tcomp_clamped"].any()


def test_the_header_of_a_raw_code_model_compiles_and_has_one_line_per_row(tmp_path):
    gcc = require_tool("gcc")
    src = magnetometer_log(tmp_path / "mag.csv")
    for spec in ("poly:2", "table:9"):
        mj, hdr = tmp_path / "m.json", tmp_path / "cal.h"
        assert main(["fit", str(src), "--temp", "temp_code", "--temp-unit", "raw", "--columns", "bx,by",
                     "--model", spec, "-o", str(mj)]) == 0
        assert main(["export", str(mj), "--format", "c", "--name", "cal", "-o", str(hdr)]) == 0
        text = hdr.read_text()
        if spec.startswith("table"):
            assert len(re.findall(r"/\* b[xy] knot \d+: code \d+", text)) == 2 * 9
        else:
            assert len(re.findall(r"/\* b[xy]: ascending powers of u, Q\d+", text)) == 2
        (tmp_path / "main.c").write_text('#include "cal.h"\nint main(void) { return 0; }\n')
        res = subprocess.run([gcc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-fsyntax-only",
                              "-I", str(CSRC_INCLUDE), "-I", str(tmp_path), str(tmp_path / "main.c")],
                             capture_output=True, text=True)
        assert res.returncode == 0, res.stderr


def test_a_value_scale_that_erases_the_drift_is_refused_with_the_remedy(tmp_path, capsys):
    src = magnetometer_log(tmp_path / "mag.csv")
    mj = tmp_path / "m.json"
    assert main(["fit", str(src), "--temp", "temp_code", "--temp-unit", "raw", "--columns", "bx,by",
                 "--model", "poly:2", "--value-scale", "1", "-o", str(mj)]) == RangeError.exit_status
    err = capsys.readouterr().err
    assert "lost its float form" in err and "--value-scale 2e+08" in err and not mj.exists()
    assert main(["fit", str(src), "--temp", "temp_code", "--temp-unit", "raw", "--columns", "bx,by",
                 "--model", "poly:2", "--value-scale", "1e10", "-o", str(mj)]) == RangeError.exit_status
    assert "leaves int16" in capsys.readouterr().err and not mj.exists()


def test_a_drift_no_int16_scale_resolves_is_refused(tmp_path, capsys):
    src = magnetometer_log(tmp_path / "mag.csv", drift=1e-14, curvature=0.0)
    mj = tmp_path / "m.json"
    assert main(["fit", str(src), "--temp", "temp_code", "--temp-unit", "raw", "--columns", "bx",
                 "--model", "poly:1", "-o", str(mj)]) == RangeError.exit_status
    assert "subtract the readings' constant offset" in capsys.readouterr().err and not mj.exists()


def test_export_refuses_a_model_whose_fixed_point_form_lost_the_float_one(tmp_path, capsys):
    """A model an older pysig wrote (value scale 1 on a column in tesla)."""
    d = read_csv(magnetometer_log(tmp_path / "mag.csv"))
    model = _poly_fit.fit_tcomp(d["temp_code"] * 0.03 - 1883, {"bx": d["bx"]}, order=2)
    assert model.value_scale == 1.0
    mj = tmp_path / "old.json"
    model.save(mj)
    for fmt in ("c", "image"):
        out = tmp_path / f"out.{fmt}"
        assert main(["export", str(mj), "--format", fmt, "-o", str(out)]) == RangeError.exit_status
        err = capsys.readouterr().err
        assert "lost its float form" in err and "--value-scale" in err and not out.exists()


# name, readings (value at T, rng) -> column, temperature kind
UNIT_CASES = {
    "tesla": (lambda T, r: 4.8e-5 + 1.2e-7 * (T - 25) + r.normal(0, 3e-9, T.size), "c"),
    "microvolt": (lambda T, r: 350.0 + 0.42 * (T - 25) - 0.004 * (T - 25) ** 2 + r.normal(0, 0.05, T.size), "c"),
    "g": (lambda T, r: 1.0 + 0.0021 * (T - 25) + r.normal(0, 2e-4, T.size), "raw"),
    "int16_codes": (lambda T, r: np.round(-1200 + 3.1 * (T - 25) + r.normal(0, 2, T.size)), "raw"),
    "counts_24bit": (lambda T, r: np.round(3.1e6 + 55.0 * (T - 25) + r.normal(0, 40, T.size)), "c"),
}


@pytest.mark.parametrize("case", sorted(UNIT_CASES))
def test_every_unit_round_trips_through_the_image_with_no_unit_flags(tmp_path, case):
    make, temp_kind = UNIT_CASES[case]
    rng = np.random.default_rng(7)
    T = np.repeat([-10.0, 5.0, 20.0, 35.0, 50.0, 65.0], 150) + rng.normal(0, 0.05, 900)
    temp = np.round(20000 + T / 0.0625) if temp_kind == "raw" else T     # an int16 code: 1/16 °C
    src = write_columns(tmp_path / "log.csv", {"temp": temp, "v": make(T, rng)}, fmt="{!r}")
    mj, img, out = tmp_path / "m.json", tmp_path / "m.bin", tmp_path / "o.csv"
    extra = ["--temp-unit", "raw"] if temp_kind == "raw" else []
    assert main(["fit", str(src), "--columns", "v", *extra, "-o", str(mj)]) == 0
    assert main(["export", str(mj), "--format", "image", "-o", str(img)]) == 0
    assert main(["apply", str(src), "--model", str(img), "--temp", "temp", "--columns", "v",
                 "-o", str(out)]) == 0
    d = read_csv(out)
    model = tmodel.load(mj)
    lsb = 1.0 / model.value_scale
    assert drift_slope(d["v_comp"], T) < max(0.02 * drift_slope(d["v"], T), 0.2 * lsb)
    if case == "int16_codes":
        assert model.value_scale == 1.0


def test_apply_takes_the_units_from_the_file_and_refuses_a_contradicting_flag(tmp_path, capsys):
    src = magnetometer_log(tmp_path / "mag.csv")
    mj, img, out = tmp_path / "m.json", tmp_path / "m.bin", tmp_path / "o.csv"
    assert main(["fit", str(src), "--temp", "temp_code", "--temp-unit", "raw", "--columns", "bx,by",
                 "--model", "poly:2", "-o", str(mj)]) == 0
    assert main(["export", str(mj), "--format", "image", "-o", str(img)]) == 0
    base = ["apply", str(src), "--temp", "temp_code", "--columns", "bx,by", "-o", str(out)]
    for model in (img, mj):
        assert main([*base, "--model", str(model), "--temp-unit", "raw", "--value-scale", "2e8"]) == 0
        assert main([*base, "--model", str(model), "--temp-unit", "c"]) == InputFileError.exit_status
        assert "contradicts" in capsys.readouterr().err
        assert main([*base, "--model", str(model), "--value-scale", "1"]) == InputFileError.exit_status
        assert "contradicts" in capsys.readouterr().err


def test_a_run_where_most_rows_are_clamped_names_the_likely_cause(tmp_path, capsys):
    src = magnetometer_log(tmp_path / "mag.csv")
    d = read_csv(src)
    other = write_columns(tmp_path / "c.csv", {"temp_c": np.round(d["temp_code"] * 0.03 - 1883), "bx": d["bx"]})
    mj, img, out = tmp_path / "m.json", tmp_path / "m.bin", tmp_path / "o.csv"
    assert main(["fit", str(src), "--temp", "temp_code", "--temp-unit", "raw", "--columns", "bx",
                 "--model", "poly:2", "-o", str(mj)]) == 0
    assert main(["export", str(mj), "--format", "image", "-o", str(img)]) == 0
    for model in (img, mj):
        assert main(["apply", str(other), "--model", str(model), "--temp", "temp_c", "--columns", "bx",
                     "-o", str(out)]) == RangeError.exit_status
        err = capsys.readouterr().err
        assert "outside the calibrated range" in err and "Likely cause" in err and "raw sensor codes" in err
        assert not out.exists()


def test_an_image_without_a_units_section_still_applies_with_flags(tmp_path):
    """An older image: no units section; --temp-unit and --value-scale fill in."""
    src = magnetometer_log(tmp_path / "mag.csv")
    mj, img, out = tmp_path / "m.json", tmp_path / "m.bin", tmp_path / "o.csv"
    assert main(["fit", str(src), "--temp", "temp_code", "--temp-unit", "raw", "--columns", "bx",
                 "--model", "poly:2", "-o", str(mj)]) == 0
    seq, sections = read_image(tmodel.image_bytes(tmodel.load(mj)))
    assert [t for t, _ in sections] == [SECTION_OFFSET_POLY, SECTION_TEMP_CODE, SECTION_UNITS]
    img.write_bytes(build_image([s for s in sections if s[0] != SECTION_UNITS], seq))
    assert main(["apply", str(src), "--model", str(img), "--temp", "temp_code", "--columns", "bx",
                 "--value-scale", "2e8", "-o", str(out)]) == 0
    d = read_csv(out)
    assert drift_slope(d["bx_comp"], d["temp_code"]) < 0.01 * drift_slope(d["bx"], d["temp_code"])


DECIMAL = st.tuples(st.integers(-(1 << 31), (1 << 31) - 1), st.integers(-128, 127))


@settings(max_examples=300, deadline=None)
@given(vs=DECIMAL, ts=DECIMAL, to=DECIMAL, flags=st.integers(0, 255), length=st.sampled_from([16, 16, 16, 15, 17]))
def test_the_c_units_loader_equals_the_spec(vs, ts, to, flags, length):
    payload = (np.array([vs[0]], "<i4").tobytes() + np.array([vs[1]], "i1").tobytes() + bytes([flags])
               + np.array([ts[0]], "<i4").tobytes() + np.array([ts[1]], "i1").tobytes()
               + np.array([to[0]], "<i4").tobytes() + np.array([to[1]], "i1").tobytes())
    payload = (payload + b"\0")[:length]
    image = ref_image.build([(SECTION_UNITS, payload)], 1)
    st_c, fields_c = load_units(image)
    assert (st_c, fields_c) == ref_image.load_units(image)


@pytest.mark.parametrize("scale, raw, tscale, toffset", [
    (2e8, True, 0.03, -1883.0), (1.0, False, None, None), (1 / 1.5e-7, True, None, None),
    (0.002, True, 0.0029412, 36.53), (12345.678, False, None, None)])
def test_the_units_section_round_trips(scale, raw, tscale, toffset):
    from pysig.tcomp._sections import from_decimal
    image = build_image([(SECTION_UNITS, units_payload(scale, raw, tscale, toffset))])
    st_c, f = load_units(image)
    assert st_c == 0 and ref_image.load_units(image) == (st_c, f)
    assert from_decimal(*f["value_scale"]) == pytest.approx(scale, rel=1e-9)
    assert bool(f["flags"] & 1) == raw and bool(f["flags"] & 2) == (tscale is not None)
    if tscale is not None:
        assert from_decimal(*f["temp_scale"]) == pytest.approx(tscale, rel=1e-9)
        assert from_decimal(*f["temp_offset"]) == pytest.approx(toffset, rel=1e-9)
