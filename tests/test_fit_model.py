"""`pysig fit --model ...` end to end: the family and size chosen from the
data, raw temperature codes, the fixed-point allowance, coverage warnings,
heating/cooling branches, whole-degree logs; fit -> export image -> apply
through the firmware's C loader on the real curves and on generated ones
far from them."""
import json

import numpy as np
import pytest

from conftest import require_shared_data
from pysig.cli import main
from pysig.errors import InputFileError, InsufficientDataError, RangeError
from pysig.io import read_csv
from pysig.sim import _chamber as sim_chamber
from pysig.tcomp import _calibration as tmodel
from pysig.tcomp._tempcode import CELSIUS, raw_code

MPU = "mpu6000_gyro_offset_vs_temp/mpu6000_sn102_gyro_offset.csv"
GYRO = "gyro_x,gyro_y,gyro_z"


def write_csv(path, cols):
    names = list(cols)
    rows = zip(*[cols[n] for n in names])
    path.write_text(",".join(names) + "\n" + "".join(",".join(repr(float(v)) for v in r) + "\n" for r in rows))
    return path


def round_trip(tmp_path, src, temp, columns, fit_extra=(), apply_extra=()):
    """fit -> export image -> apply through the C loader; also apply --fixed
    on the JSON model.  Returns (model, printed fit output, image output, fixed output)."""
    mj, img, o1, o2 = (tmp_path / n for n in ("m.json", "m.bin", "img.csv", "fix.csv"))
    srcs = [str(s) for s in (src if isinstance(src, list) else [src])]
    assert main(["fit", *srcs, "--temp", temp, "--columns", columns, *fit_extra, "-o", str(mj)]) == 0
    assert main(["export", str(mj), "--format", "image", "-o", str(img)]) == 0
    assert main(["apply", srcs[0], "--model", str(img), "--temp", temp, "--columns", columns,
                 *apply_extra, "-o", str(o1)]) == 0
    assert main(["apply", srcs[0], "--model", str(mj), "--fixed", "-o", str(o2)]) == 0
    return tmodel.load(mj), read_csv(o1), read_csv(o2)


def check_choice(model):
    sel = model.report["selection"]
    assert sel["cv_rms"] <= 1.1 * sel["best_cv_rms"]
    assert sel["cv_rms"] <= 1.05 * sel["best_cv_rms"] + 1e-12     # the rule itself


@pytest.mark.parametrize("temp,extra", [("temp_c", []), ("temp_raw", ["--temp-unit", "raw"])])
def test_mpu6000_every_axis_celsius_and_raw_codes(tmp_path, temp, extra):
    src = require_shared_data(MPU)
    model, img, fixed = round_trip(tmp_path, src, temp, GYRO, extra,
                                   ["--temp-unit", "raw"] if extra else [])
    check_choice(model)
    assert model.family == "table"                     # the curve rises and falls: no low order follows it
    d = read_csv(src)
    flt, _ = tmodel.apply_float(model, d[temp], [d[a] for a in GYRO.split(",")])
    for a, f in zip(GYRO.split(","), flt):
        np.testing.assert_array_equal(img[a + "_comp"], fixed[a + "_comp"])   # image == JSON --fixed
        assert np.max(np.abs(img[a + "_comp"] - f)) <= 1.0                   # 0.5 rounding + 0.5 allowance
    raw_fit = np.std(d["gyro_x"])
    assert np.std(img["gyro_x_comp"]) < 0.1 * raw_fit


def test_bmi270_two_plateaus_fit_without_cv_and_warn_about_the_gap(tmp_path, capsys):
    folder = require_shared_data("bmi270_two_temps")
    files = [folder / "bmi270_cold.csv", folder / "bmi270_hot.csv"]
    joined = tmp_path / "both.csv"
    joined.write_text(files[0].read_text() + "".join(files[1].read_text().splitlines(True)[1:]))
    cols = "gyro_x_dps,gyro_y_dps,gyro_z_dps"
    model, img, fixed = round_trip(tmp_path, [joined], "temp_c", cols, ["--value-scale", "100"],
                                   ["--value-scale", "100"])
    out = capsys.readouterr()
    assert "cross-validation needs 3 separate temperature groups" in out.out
    assert "a gap of" in out.err and "unvalidated" in out.err
    assert model.report["selection"]["chosen"] in ("table:2", "poly:1")
    cold = img["temp_c"] < 30
    for a in cols.split(","):
        before = abs(img[a][cold].mean() - img[a][~cold].mean())
        after = abs(img[a + "_comp"][cold].mean() - img[a + "_comp"][~cold].mean())
        assert after < 0.05 and (before < 0.06 or after < 0.1 * before), (a, before, after)
    # --strict refuses the same data, writes nothing
    mj = tmp_path / "strict.json"
    assert main(["fit", str(joined), "--temp", "temp_c", "--columns", cols, "--strict",
                 "-o", str(mj)]) == InsufficientDataError.exit_status
    assert "coverage check failed" in capsys.readouterr().err and not mj.exists()


def test_chamber_auto_within_ten_percent_of_the_best(tmp_path):
    csv = tmp_path / "run.csv"
    assert main(["chamber", "-o", str(csv)]) == 0
    model, img, fixed = round_trip(tmp_path, csv, "temp", "x,y,z")
    check_choice(model)
    for a in "xyz":
        np.testing.assert_array_equal(img[a + "_comp"], fixed[a + "_comp"])


def drift(t, amplitude):
    return amplitude * np.sin((t - t.min()) / np.ptp(t) * 5.0) + 0.3 * amplitude * ((t - t.mean()) / np.ptp(t)) ** 2


@pytest.mark.parametrize("lo,hi", [(63000, 65000), (-30000, -27000), (-500, 700), (200, 32767)])
def test_generated_raw_code_ranges(tmp_path, lo, hi):
    rng = np.random.default_rng(lo & 0xFFFF)
    codes = np.repeat(np.arange(lo, hi + 1, max(1, (hi - lo) // 300)), 3)
    x = np.rint(drift(codes.astype(float), 900.0) + rng.normal(0, 2.0, codes.size))
    y = np.rint(-40.0 + 0.002 * (codes - lo) + rng.normal(0, 1.0, codes.size))
    src = write_csv(tmp_path / "raw.csv", {"code": codes, "x": x, "y": y})
    model, img, fixed = round_trip(tmp_path, src, "code", "x,y", ["--temp-unit", "raw"],
                                   ["--temp-unit", "raw"])
    check_choice(model)
    assert model.temp_code.code_kind == (1 if hi > 32767 else 0)
    np.testing.assert_array_equal(img["x_comp"], fixed["x_comp"])
    assert np.std(img["x_comp"]) < 5.0                       # the 900-LSB drift is gone, noise 2


def test_raw_codes_must_be_integers_in_a_16_bit_range(tmp_path):
    src = write_csv(tmp_path / "a.csv", {"code": [1.0, 2.5, 3.0, 4.0], "x": [1, 2, 3, 4]})
    assert main(["fit", str(src), "--temp", "code", "--columns", "x", "--temp-unit", "raw",
                 "-o", str(tmp_path / "m.json")]) == InputFileError.exit_status
    with pytest.raises(RangeError, match="fit neither int16"):
        raw_code([-5.0, 70000.0])
    with pytest.raises(RangeError, match="does not fit the int16 temperature"):
        CELSIUS.to_t([20.0, 400.0])
    assert list(CELSIUS.to_t([20.0, 400.0], "saturate")) == [2000, 32767]


def test_whole_degrees_are_averaged_and_said(tmp_path, capsys):
    rng = np.random.default_rng(3)
    t = np.round(rng.uniform(-5, 45, 4000))
    x = np.rint(3.0 * t + 0.05 * t ** 2 + rng.normal(0, 1, t.size))
    src = write_csv(tmp_path / "deg.csv", {"temp": t, "x": x})
    model, _, _ = round_trip(tmp_path, src, "temp", "x")
    out = capsys.readouterr().out
    assert "whole degrees: averaged per distinct temperature (51 of them)" in out
    assert "4000 samples averaged into 51 temperatures" in out
    check_choice(model)


def test_heating_and_cooling_branches_are_reported_and_pooled(tmp_path, capsys):
    up = np.linspace(0, 60, 3000)
    t = np.concatenate([up, up[::-1]])
    band = 12.0
    x = np.rint(5.0 * t + np.where(np.arange(t.size) < up.size, band / 2, -band / 2))
    src = write_csv(tmp_path / "hc.csv", {"temp": t, "x": x, "y": np.rint(2.0 * t)})
    round_trip(tmp_path, src, "temp", "x,y")
    out = capsys.readouterr().out
    line = next(l for l in out.splitlines() if "both present" in l)
    assert "the fit pools both branches" in line
    assert f"x mean {band:.4g}" in line and "y mean 0" in line
    m = tmodel.load(tmp_path / "m.json")
    assert m.report["hysteresis"]["per_axis"]["x"]["mean"] == pytest.approx(band, abs=0.6)


def test_a_single_ramp_is_not_called_hysteresis(tmp_path, capsys):
    t = np.linspace(0, 60, 2000) + np.random.default_rng(1).normal(0, 0.05, 2000)
    src = write_csv(tmp_path / "ramp.csv", {"temp": t, "x": np.rint(5.0 * t)})
    round_trip(tmp_path, src, "temp", "x")
    assert "both present" not in capsys.readouterr().out


def test_thin_block_and_gap_warnings(tmp_path, capsys):
    t = np.concatenate([np.linspace(0, 20, 200), [27.0], np.linspace(45, 80, 300)])
    src = write_csv(tmp_path / "thin.csv", {"temp": t, "x": np.rint(4.0 * t)})
    round_trip(tmp_path, src, "temp", "x")
    err = capsys.readouterr().err
    assert "holds only 2 calibration temperature(s)" in err or "holds only 1 calibration" in err
    assert "a gap of" in err and "wider than a CV block" in err


def test_fixed_point_refusal_names_a_model_that_fits():
    t = np.linspace(-40.0, 125.0, 2000)
    y = 60000.0 * ((t + 40.0) / 165.0) ** 2 - 30000.0          # steep, noise-free: CV RMS ~ 0
    with pytest.raises(RangeError, match=r"would fit") as e:
        tmodel.fit_model(t, {"x": y}, spec="poly:2")
    assert "table:" in str(e.value) or "poly:" in str(e.value)
    r = tmodel.fit_model(t, {"x": y}, spec="auto")              # auto moves on to one that fits
    assert any("the most accurate one that does" in line for line in r.lines)
    assert max(getattr(r.model, "error_lsb", None) or r.model.error_bound_lsb) <= 0.5


@pytest.mark.parametrize("spec,status,text", [
    ("poly:x", InputFileError, "--model must be"), ("cubic", InputFileError, "--model must be"),
    ("poly:9", RangeError, "order must be 1..8"), ("table:300", RangeError, "2..255 knots"),
    ("poly:7", InsufficientDataError, "needs at least 8 distinct temperatures")])
def test_model_spec_refusals(tmp_path, capsys, spec, status, text):
    t = np.repeat([0.0, 10.0, 20.0, 30.0, 40.0], 20)
    src = write_csv(tmp_path / "s.csv", {"temp": t, "x": np.rint(2 * t)})
    out = tmp_path / "m.json"
    assert main(["fit", str(src), "--columns", "x", "--model", spec, "-o", str(out)]) == status.exit_status
    assert text in capsys.readouterr().err and not out.exists()


def test_order_is_a_synonym_of_model_poly(tmp_path):
    t = np.linspace(0, 50, 400)
    src = write_csv(tmp_path / "s.csv", {"temp": t, "x": np.rint(3 * t + 0.1 * t ** 2)})
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    assert main(["fit", str(src), "--columns", "x", "--order", "3", "-o", str(a)]) == 0
    assert main(["fit", str(src), "--columns", "x", "--model", "poly:3", "-o", str(b)]) == 0
    assert json.loads(a.read_text())["float"] == json.loads(b.read_text())["float"]
    assert main(["fit", str(src), "--columns", "x", "--order", "3", "--model", "poly:3",
                 "-o", str(a)]) == InputFileError.exit_status


def test_out_of_range_is_clamped_and_flagged_by_the_firmware(tmp_path):
    t = np.linspace(10, 40, 300)
    src = write_csv(tmp_path / "s.csv", {"temp": t, "x": np.rint(50 * np.sin(t / 5))})
    for spec in ("table:9", "poly:3"):
        mj, img = tmp_path / "m.json", tmp_path / "m.bin"
        assert main(["fit", str(src), "--columns", "x", "--model", spec, "-o", str(mj)]) == 0
        assert main(["export", str(mj), "--format", "image", "-o", str(img)]) == 0
        wide = write_csv(tmp_path / "w.csv", {"temp": [-60.0, 5.0, 25.0, 45.0, 400.0], "x": [0, 0, 0, 0, 0]})
        out = tmp_path / "o.csv"
        assert main(["apply", str(wide), "--model", str(img), "--temp", "temp", "--columns", "x",
                     "-o", str(out)]) == 0
        o = read_csv(out)
        assert list(o["tcomp_clamped"]) == [1, 1, 0, 1, 1]
        assert o["x_comp"][0] == o["x_comp"][1] and o["x_comp"][3] == o["x_comp"][4]   # flat beyond the ends


def test_unit_and_form_refusals(tmp_path, capsys):
    t = np.linspace(0, 50, 200)
    src = write_csv(tmp_path / "d.csv", {"temp": t, "x": 0.37 * t + 0.01})   # readings with decimals
    mj, img = tmp_path / "m.json", tmp_path / "m.bin"
    assert main(["fit", str(src), "--columns", "x", "--temp-scale", "0.1", "-o", str(mj)]) == \
        InputFileError.exit_status and "--temp-unit raw only" in capsys.readouterr().err
    assert main(["fit", str(src), "--columns", "x", "--model", "table:9", "-o", str(mj)]) == 0
    assert main(["export", str(mj), "--format", "image", "--compact", "-o", str(img)]) == \
        RangeError.exit_status and "this one is a table" in capsys.readouterr().err and not img.exists()
    assert main(["export", str(mj), "--format", "image", "-o", str(img)]) == 0
    out = tmp_path / "o.csv"
    assert main(["apply", str(src), "--model", str(img), "--temp", "temp", "--columns", "x",
                 "-o", str(out)]) == RangeError.exit_status
    assert "give --value-scale" in capsys.readouterr().err and not out.exists()
    assert main(["apply", str(src), "--model", str(img), "--temp", "temp", "--columns", "x",
                 "--value-scale", "100", "-o", str(out)]) == RangeError.exit_status    # 0.37 t x 100: not integers
    assert main(["apply", str(src), "--model", str(mj), "--temp-unit", "raw", "-o", str(out)]) == \
        InputFileError.exit_status and "for images" in capsys.readouterr().err


def test_exported_table_header_compiles_and_equals_the_image(tmp_path):
    import subprocess
    from conftest import CSRC_INCLUDE, require_tool
    from pysig.tcomp import _tmodel
    gcc = require_tool("gcc")
    codes = np.arange(63000, 65001, 8).astype(float)
    src = write_csv(tmp_path / "r.csv", {"code": codes, "x": np.rint(300 * np.sin(codes / 300.0)),
                                         "y": np.rint(0.05 * (codes - 64000))})
    mj, hdr = tmp_path / "m.json", tmp_path / "cal.h"
    assert main(["fit", str(src), "--temp", "code", "--temp-unit", "raw", "--columns", "x,y",
                 "--model", "table:33", "-o", str(mj)]) == 0
    assert main(["export", str(mj), "--format", "c", "--name", "cal", "-o", str(hdr)]) == 0
    test_codes = [0, 62999, 63000, 63555, 64001, 65000, 65535]
    (tmp_path / "main.c").write_text("""#include <stdio.h>
#include "cal.h"
int main(void) {
    static const uint16_t codes[] = {%s};
    int16_t in[2] = {1000, -2000}, out[2];
    sig_tmodel m;
    unsigned i;
    if (sig_tmodel_init_table(&m, CAL_N_AXES, cal_table, CAL_N_KNOTS, CAL_T_LO, CAL_T_HI, CAL_RECIP,
                              cal_value_frac, CAL_TCODE) != SIG_OK) return 1;
    for (i = 0; i < sizeof codes / sizeof codes[0]; i++) {
        int st = sig_tmodel_apply(&m, codes[i], in, out);
        printf("%%d %%d %%d\\n", st, out[0], out[1]);
    }
    return 0;
}
""" % ", ".join(f"{c}u" for c in test_codes))
    from lab.mcu.runner import csrc_sources
    srcs = [str(f) for f in csrc_sources("sig_tmodel")]
    exe = tmp_path / "prog"
    res = subprocess.run([gcc, "-std=c99", "-Wall", "-Werror", "-I", str(CSRC_INCLUDE), "-I", str(tmp_path),
                          str(tmp_path / "main.c"), *srcs, "-o", str(exe)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    lines = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split("\n")
    host = _tmodel.TModel.from_image(tmodel.image_bytes(tmodel.load(mj)))
    out, st = host.apply(test_codes, np.array([[1000, -2000]] * len(test_codes)))
    for i, line in enumerate(lines[:len(test_codes)]):
        assert [int(v) for v in line.split()] == [st[i], out[i, 0], out[i, 1]]
