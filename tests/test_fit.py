"""Training (pysig/tcomp/_poly_fit.py, pysig/tcomp/_poly_model.py) and the CLI round trip
fit -> export -> C evaluation (image parsed in C) -> same numbers as Python."""
import json
import subprocess

import numpy as np
import pytest

from conftest import CSRC_INCLUDE, c_source, require_tool
from pysig.tcomp import _tcomp
from pysig.tcomp import _poly_fit as fit, _poly_model as tmodel, _quant as quant
from pysig import lsq
from pysig.sim import _chamber as sim_chamber
from pysig.cli import main
from pysig.errors import InsufficientDataError, ModelFileError, NonFiniteError, RangeError
from pysig.io import read_csv
from spec import tcomp as ref_tcomp


@pytest.fixture(scope="module")
def chamber_csv(tmp_path_factory):
    path = tmp_path_factory.mktemp("chamber") / "chamber.csv"
    sim_chamber.write(path, sim_chamber.ChamberParams(seed=11, dwell_s=900))
    return path


def test_recovers_the_simulated_drift():
    p = sim_chamber.ChamberParams(seed=5, noise_lsb=0.0, temp_noise_c=0.0, temp_resolution_c=0.01,
                                  gain_drift=((0.0,), (0.0,), (0.0,)))
    d = sim_chamber.simulate(p)
    m = fit.fit_tcomp(d["temp"], {k: d[k] for k in "xyz"}, order=2, t0=25.0)
    t = np.linspace(0, 70, 50)
    for a in range(3):
        true_delta = np.polynomial.polynomial.polyval(t - 25, p.offset_poly[a]) - p.offset_poly[a][0]
        assert np.max(np.abs(m.delta(t, a) - true_delta)) < 0.6     # int16 rounding of the readings
        assert abs(m.delta(25.0, a)) < 1e-9                          # delta(T0) = 0 by construction


def test_cross_validation_picks_order_two_on_the_chamber():
    d = sim_chamber.simulate(sim_chamber.ChamberParams(seed=2))
    cv = fit.cross_validate(d["temp"], {k: d[k] for k in "xyz"})
    by_order = {r["order"]: r for r in cv}
    assert by_order[1]["var"] > 10 * by_order[2]["var"]         # order 1 underfits the curvature
    assert by_order[0]["var"] > by_order[1]["var"]
    assert fit.select_order(cv) == 2
    m = fit.fit_tcomp(d["temp"], {k: d[k] for k in "xyz"}, order="auto")
    assert m.order == 2 and "cv" in m.report


def test_normal_equations_condition_worse_on_chamber_temperatures():
    d = sim_chamber.simulate(sim_chamber.ChamberParams(seed=2, dwell_s=300))
    conds = []
    for order in range(1, 7):
        _, c_normal = lsq.fit_normal_equations(d["temp"], d["x"], order)
        c_scaled = lsq.fit_poly(d["temp"], d["x"], order).cond
        conds.append(c_normal / c_scaled)
    assert conds[-1] > 1e10 and conds[-1] > 1e4 * conds[0]


def test_temperature_groups_count_plateaus_not_float_values():
    rng = np.random.default_rng(0)
    t = np.concatenate([13 + rng.uniform(0, 0.3, 300), 47.3 + rng.uniform(0, 0.5, 600), np.full(10, 49.3)])
    g = fit.temperature_groups(t)
    assert g.count == 2                       # the 10 stray samples do not make a third
    assert fit.temperature_groups(np.arange(6.67, 41.2, 0.188)).count == 184
    ramp = np.linspace(0, 70, 7001)
    assert fit.temperature_groups(ramp).count == 14


@pytest.mark.parametrize("temp, cols, exc, text", [
    (np.repeat([10.0, 20.0], 50), {"x": np.arange(100.0)}, InsufficientDataError,
     "order 2 needs at least 3 distinct temperatures, the data has 2"),
    (np.full(100, 25.0), {"x": np.arange(100.0)}, InsufficientDataError, "constant temperature"),
    (np.r_[np.nan, np.linspace(0, 70, 99)], {"x": np.arange(100.0)}, NonFiniteError, "index 0"),
    (np.linspace(0, 70, 100), {"x": np.r_[np.arange(99.0), np.inf]}, NonFiniteError, "'x'.*index 99"),
    (np.linspace(30, 70, 100), {"x": np.arange(100.0)}, RangeError, "T0 = 25"),
])
def test_bad_training_data_is_named(temp, cols, exc, text):
    with pytest.raises(exc, match=text):
        fit.fit_tcomp(temp, cols, order=2)


def test_model_json_round_trip_and_version_check(tmp_path, chamber_csv):
    d = read_csv(chamber_csv)
    m = fit.fit_tcomp(d["temp"], {k: d[k] for k in "xy"}, order=3)
    m.save(tmp_path / "m.json")
    m2 = tmodel.load(tmp_path / "m.json")
    assert m2.fixed_fields() == m.fixed_fields()
    np.testing.assert_array_equal(m2.delta(d["temp"], 1), m.delta(d["temp"], 1))
    raw = json.loads((tmp_path / "m.json").read_text())
    raw["version"] = 99
    (tmp_path / "v99.json").write_text(json.dumps(raw))
    with pytest.raises(ModelFileError, match="version 99"):
        tmodel.load(tmp_path / "v99.json")
    (tmp_path / "bad.json").write_text("{not json")
    with pytest.raises(ModelFileError, match="not a JSON"):
        tmodel.load(tmp_path / "bad.json")


def test_cli_round_trip_fit_export_image_c_evaluation(tmp_path, chamber_csv, capsys):
    """fit -> export image -> the C loader parses the image -> C fixed point
    equals the Python spec bit for bit and the float64 model within 0.5 LSB."""
    mj, img, out = tmp_path / "m.json", tmp_path / "m.bin", tmp_path / "out.csv"
    assert main(["fit", str(chamber_csv), "--temp", "temp", "--columns", "x,y,z", "--order", "auto",
                 "--t0", "25", "-o", str(mj)]) == 0
    assert main(["export", str(mj), "--format", "image", "--sequence", "9", "-o", str(img)]) == 0
    m = tmodel.load(mj)
    c = _tcomp.TcompQ.from_image(img.read_bytes())
    assert c.fields() == m.fixed_fields()
    assert c.no_overflow                       # pysig.tcomp._quant models take the fast path
    d = read_csv(chamber_csv)
    t = quant.to_centi(d["temp"])
    x = np.column_stack([d[k] for k in "xyz"]).astype(np.int16)
    got, status = c.apply(t, x)
    for i in range(0, len(t), 97):
        want, want_st = ref_tcomp.apply_q(m.fixed_fields(), int(t[i]), [int(v) for v in x[i]])
        assert list(got[i]) == want and status[i] == want_st
    flt = np.column_stack(m.apply_float(t / 100.0, [x[:, a] for a in range(3)]))
    assert np.max(np.abs(got - flt)) <= 0.5 + max(m.error_bound_lsb)
    # pysig apply --fixed writes the same numbers as the C call above
    assert main(["apply", str(chamber_csv), "--model", str(mj), "--fixed", "-o", str(out)]) == 0
    o = read_csv(out)
    np.testing.assert_array_equal(np.column_stack([o[k + "_comp"] for k in "xyz"]), got)
    assert main(["apply", str(chamber_csv), "--model", str(mj), "-o", str(out)]) == 0
    o = read_csv(out)
    flt_raw_t = np.column_stack(m.apply_float(d["temp"], [d[k] for k in "xyz"]))
    np.testing.assert_allclose(np.column_stack([o[k + "_comp"] for k in "xyz"]), flt_raw_t, rtol=0, atol=1e-9)


def test_exported_c_header_compiles_and_matches_python(tmp_path, chamber_csv):
    gcc = require_tool("gcc")
    mj, hdr = tmp_path / "m.json", tmp_path / "cal.h"
    assert main(["fit", str(chamber_csv), "--columns", "x,y,z", "--order", "2", "-o", str(mj)]) == 0
    assert main(["export", str(mj), "--format", "c", "--name", "cal", "-o", str(hdr)]) == 0
    m = tmodel.load(mj)
    temps = [-2000, 0, 1234, 2500, 4999, 7000, 9000]
    prog = tmp_path / "main.c"
    prog.write_text("""#include <stdio.h>
#include "cal.h"
int main(void) {
    sig_tcomp_q m; sig_tcomp_f mf;
    static const int16_t temps[] = {%s};
    int16_t in[3] = {1000, -2000, 3000}, out[3];
    sig_real inf_[3] = {1000, -2000, 3000}, outf[3];
    unsigned i;
    if (sig_tcomp_init_q(&m, CAL_N_AXES, CAL_ORDER, cal_coef_q, cal_q, CAL_T_LO, CAL_T_HI,
                         CAL_T_CENTER, CAL_T0, CAL_U_MUL, CAL_U_SHIFT) != SIG_OK) return 1;
    if (sig_tcomp_init_f(&mf, CAL_N_AXES, CAL_ORDER, cal_coef_f, CAL_F_T_LO, CAL_F_T_HI,
                         CAL_F_CENTER, CAL_F_INV_SCALE) != SIG_OK) return 2;
    for (i = 0; i < sizeof temps / sizeof temps[0]; i++) {
        int st = sig_tcomp_apply_q(&m, temps[i], in, out);
        int stf = sig_tcomp_apply_f(&mf, (sig_real)temps[i] / 100, inf_, outf);
        printf("%%d %%d %%d %%d %%d %%.17g %%.17g %%.17g\\n", st, out[0], out[1], out[2], stf,
               (double)outf[0], (double)outf[1], (double)outf[2]);
    }
    return 0;
}
""" % ", ".join(map(str, temps)))
    exe = tmp_path / "prog"
    srcs = [str(c_source(f)) for f in ("sig_tcomp", "sig_poly", "sig_image", "sig_crc16")]
    res = subprocess.run([gcc, "-std=c99", "-Wall", "-Werror", "-DSIG_REAL_DOUBLE", "-I", str(CSRC_INCLUDE),
                          "-I", str(tmp_path), str(prog), *srcs, "-o", str(exe)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    lines = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split("\n")
    for t, line in zip(temps, lines):
        v = line.split()
        want, want_st = ref_tcomp.apply_q(m.fixed_fields(), int(t), [1000, -2000, 3000])
        assert [int(s) for s in v[:4]] == [want_st] + want
        flt = [x[0] for x in m.apply_float(np.array([t / 100.0]), [[1000.0], [-2000.0], [3000.0]])]
        assert int(v[4]) == want_st
        np.testing.assert_allclose([float(s) for s in v[5:]], flt, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("setup, args, status, text", [
    ("two_temps", ["fit", "IN", "--columns", "x", "--order", "2", "-o", "OUT"], 4, "needs at least 3"),
    ("nan", ["fit", "IN", "--columns", "x", "-o", "OUT"], 3, "non-finite"),
    ("ok", ["fit", "IN", "--columns", "nope", "-o", "OUT"], 2, "missing column"),
    ("ok", ["fit", "IN", "--columns", "x", "--order", "seven", "-o", "OUT"], 2, "--order"),
    ("ok", ["fit", "IN", "--columns", "x", "--order", "9", "-o", "OUT"], 7, "order must be"),
    ("bad_model", ["apply", "IN", "--model", "MODEL", "-o", "OUT"], 6, "version"),
    ("bad_model", ["export", "MODEL", "--format", "image", "-o", "OUT"], 6, "version"),
])
def test_cli_errors_have_their_exit_status_and_write_nothing(tmp_path, capsys, setup, args, status, text):
    inp, out, mdl = tmp_path / "in.csv", tmp_path / "out.file", tmp_path / "m.json"
    temp = {"two_temps": np.repeat([10.0, 40.0], 20)}.get(setup, np.linspace(0, 70, 40))
    x = np.arange(40.0)
    rows = ["temp,x"] + [f"{float(a)!r},{float(b)!r}" for a, b in zip(temp, x)]
    if setup == "nan":
        rows[5] = "nan,3"
    inp.write_text("\n".join(rows) + "\n")
    mdl.write_text(json.dumps({"format": "pysig-tcomp", "version": 3}))
    argv = [str(inp) if a == "IN" else str(out) if a == "OUT" else str(mdl) if a == "MODEL" else a
            for a in args]
    assert main(argv) == status
    assert text in capsys.readouterr().err
    assert not out.exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".pysig-")]


def test_c_float_path_equals_numpy_model_and_clamps(chamber_csv):
    d = read_csv(chamber_csv)
    m = fit.fit_tcomp(d["temp"], {k: d[k] for k in "xyz"}, order=4)
    c = _tcomp.TcompF(**m.float_fields())
    temp = np.r_[d["temp"][::50], -20.0, 95.0]
    x = np.column_stack([np.r_[d[k][::50], 0.0, 0.0] for k in "xyz"])
    out, status = c.apply(temp, x)
    want = np.column_stack(m.apply_float(temp, [x[:, a] for a in range(3)]))
    np.testing.assert_allclose(out, want, rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(status == 1, m.clamped(temp))
    assert status[-1] == 1 and status[-2] == 1
    np.testing.assert_allclose(out[-1], want[-1])                 # flat at the limit
    np.testing.assert_allclose(m.delta(95.0, 0), m.delta(m.t_hi, 0))


def test_export_json_is_the_same_model(tmp_path, chamber_csv):
    mj, mj2 = tmp_path / "m.json", tmp_path / "m2.json"
    assert main(["fit", str(chamber_csv), "--columns", "y", "--order", "3", "--t0", "30", "-o", str(mj)]) == 0
    assert main(["export", str(mj), "--format", "json", "-o", str(mj2)]) == 0
    a, b = tmodel.load(mj), tmodel.load(mj2)
    assert a.to_dict() == b.to_dict() and a.t0 == 30.0 and a.order == 3


def test_cli_apply_with_the_image_runs_the_c_loader(tmp_path, chamber_csv, capsys):
    mj, img, o_img, o_fix = (tmp_path / n for n in ("m.json", "m.bin", "img.csv", "fix.csv"))
    assert main(["fit", str(chamber_csv), "--columns", "x,z", "-o", str(mj)]) == 0
    assert main(["export", str(mj), "--format", "image", "-o", str(img)]) == 0
    assert main(["apply", str(chamber_csv), "--model", str(img), "--temp", "temp", "--columns", "x,z",
                 "-o", str(o_img)]) == 0
    assert main(["apply", str(chamber_csv), "--model", str(mj), "--fixed", "-o", str(o_fix)]) == 0
    a, b = read_csv(o_img), read_csv(o_fix)
    for k in ("x_comp", "z_comp", "tcomp_clamped"):
        np.testing.assert_array_equal(a[k], b[k])
    capsys.readouterr()
    data = bytearray(img.read_bytes())
    data[20] ^= 0x10                                   # one flipped bit: CRC
    (tmp_path / "bad.bin").write_bytes(bytes(data))
    out = tmp_path / "never.csv"
    assert main(["apply", str(chamber_csv), "--model", str(tmp_path / "bad.bin"), "--temp", "temp",
                 "--columns", "x,z", "-o", str(out)]) == ModelFileError.exit_status
    assert "CRC mismatch" in capsys.readouterr().err and not out.exists()
    assert main(["apply", str(chamber_csv), "--model", str(img), "-o", str(out)]) == 2   # no column names
    assert not out.exists()
