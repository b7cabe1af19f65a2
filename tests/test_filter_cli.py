"""`pysig filter`: the chain over a CSV column, with one-line errors (file,
row, column), exit status 2 and no output file on bad input."""
import csv

import numpy as np
import pytest

from conftest import require_shared_data
from pysig import cli
from pysig.weigh import Chain

HX711 = "hx711_steps_10hz/hx711_steps_10hz.csv"


def filter_csv(tmp_path, content, *extra):
    """Write `content` as in.csv, run `pysig filter` on its counts column:
    (exit status, in.csv, the output path)."""
    src = tmp_path / "in.csv"
    src.write_text(content)
    out = tmp_path / "out.csv"
    return cli.main(["filter", str(src), "--column", "counts", "-o", str(out), *extra]), src, out


def read_out(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], {name: np.array([float(r[i]) for r in rows[1:]]) for i, name in enumerate(rows[0])}


@pytest.mark.parametrize("extra,kw", [
    ([], dict()),
    (["--fixed"], dict(fixed=True)),
    (["--preset", "paper", "--units-per-kg", "2204.6"], dict(preset="paper", units_per_kg=2204.6)),
    (["--preset", "recommended", "--window", "8", "--lockout-n", "5", "--motion-band", "0.05", "--Q", "1e-7",
      "--no-seed-first"],
     dict(preset="recommended", window=8, lockout_n=5, motion_band=0.05, Q=1e-7, seed_first=False)),
    (["--window", "8", "--lockout-n", "5", "--R", "4900"], dict(window=8, lockout_n=5, R=4900.0)),
    (["--preset", "paper", "--units-per-kg", "2204.6", "--motion-band", "auto", "--A0", "AUTO", "--R", "2e-3",
      "--motion-sigmas", "3", "--lockout-n", "3"],
     dict(preset="paper", units_per_kg=2204.6, motion_band="auto", A0="auto", R=2e-3, motion_sigmas=3.0,
          lockout_n=3)),
])
def test_filter_writes_input_columns_plus_filtered_and_stable(tmp_path, extra, kw):
    src = require_shared_data(HX711)
    out = tmp_path / "out.csv"
    assert cli.main([*map(str, ["filter", src, "--column", "lc1_counts", "-o", out]), *extra]) == 0
    header, cols = read_out(out)
    assert header == ["t_s", "lc1_counts", "lc2_counts", "lc3_counts", "lc4_counts", "lc5_counts",
                      "lc6_counts", "filtered", "stable"]
    filtered, stable = Chain(**kw).process(cols["lc1_counts"])
    np.testing.assert_array_equal(cols["filtered"], filtered)
    np.testing.assert_array_equal(cols["stable"], stable.astype(float))
    with open(out) as fh:
        assert fh.readlines()[1].split(",")[1] == "5864"          # integer columns stay integers


def test_filter_status_column_and_nan_as_impulse(tmp_path):
    status, src, out = filter_csv(tmp_path, "counts\n100\n101\nnan\n99\n1e7\n100\n", "--status")
    assert status == 0
    _, cols = read_out(out)
    assert np.all(np.isfinite(cols["filtered"]))
    assert list(cols["status"].astype(int) & 4) == [0, 0, 4, 0, 4, 0]


@pytest.mark.parametrize("content,needle", [
    ("", "empty file"),
    ("counts\n", "header only"),
    ("other\n1\n2\n", "row 1 (header), column 'counts': missing"),
    ("counts\n1\n2\nabc\n", "row 4, column 'counts': not a number"),
    ("t,counts\n0,1\n1,\n", "row 3, column 'counts'"),
])
def test_filter_bad_input_one_line_exit_2_no_output(tmp_path, capsys, content, needle):
    status, src, out = filter_csv(tmp_path, content)
    assert status == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(src) in err and needle in err
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["in.csv"]


def test_filter_fixed_refuses_nan_with_row(tmp_path, capsys):
    status, src, out = filter_csv(tmp_path, "counts\n1\nnan\n", "--fixed")
    assert status == 3
    assert "row 3, column 'counts'" in capsys.readouterr().err
    assert not out.exists()


def test_filter_bad_parameter_is_named(tmp_path, capsys):
    status, src, out = filter_csv(tmp_path, "counts\n1\n2\n", "--window", "33")
    assert status == 7
    assert "window=33" in capsys.readouterr().err
    assert not out.exists()


def test_filter_fixed_refuses_codes_beyond_25_bits(tmp_path, capsys):
    status, src, out = filter_csv(tmp_path, "counts\n1\n2\n40000000\n", "--fixed")
    assert status == 5
    err = capsys.readouterr().err
    assert "row 4, column 'counts'" in err and "40000000" in err
    assert not out.exists()
    # the float form takes it (an impulse for the limit filter)
    assert cli.main(["filter", str(src), "--column", "counts", "-o", str(out)]) == 0


def test_filter_parameter_overflowing_in_signal_units_is_named(tmp_path, capsys):
    status, src, out = filter_csv(tmp_path, "counts\n1\n2\n", "--A0", "1e305")
    assert status == 7
    assert "A0=1e+305" in capsys.readouterr().err
    assert not out.exists()
