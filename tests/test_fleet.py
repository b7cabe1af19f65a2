"""Fleet calibration: the batched fit equals pysig.tcomp._poly_fit device by
device; the CLI writes a model, an image carrying the serial and a summary
row per device; bad devices are flagged and the fleet goes on; bad logs are
named errors and nothing is half-written."""
import csv
import json

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from hypothesis import given, settings, strategies as st

from fleet_cases import fleet_rows, write_fleet_log
from pysig import cli
from pysig.errors import InsufficientDataError, RangeError
from pysig.store._device import SIG_ERR_DEVICE, image_device_status
from pysig.store._image import SECTION_OFFSET_POLY, find_section, parse_offset_poly
from pysig.tcomp import _poly_model as tmodel
from pysig.tcomp._poly_fit import fit_tcomp
from pysig.fleet._fit import device_groups, fit_fleet
from pysig.tcomp._poly_fit import temperature_groups


def _check_equal(serial, temp, y, model, t0=25.0):
    devices, dev = np.unique(serial, return_inverse=True)
    ff = fit_fleet(dev, temp, y, devices, ["x", "y", "z"], model=model, t0=t0)
    for d in range(len(devices)):
        sel = dev == d
        try:
            m = fit_tcomp(temp[sel], {"x": y[sel, 0], "y": y[sel, 1], "z": y[sel, 2]}, order=model, t0=t0)
        except (InsufficientDataError, RangeError) as exc:
            assert not ff.ok[d], f"{devices[d]}: per-device fit refused ({exc}), batched did not"
            continue
        assert ff.ok[d], f"{devices[d]}: batched refused: {ff.reason[d]}"
        fm = ff.model(d)
        assert fm.order == m.order and fm.scaling == m.scaling and fm.q == m.q
        for a in range(3):
            np.testing.assert_allclose(fm.coef[a], m.coef[a], rtol=1e-9, atol=1e-9 * max(1, np.abs(m.coef[a]).max()))
        np.testing.assert_allclose(fm.f_t0, m.f_t0, rtol=1e-12, atol=1e-9)
        assert fm.coef_q == [tuple(c) for c in m.coef_q]
        np.testing.assert_allclose([m.report["per_axis"][a]["rms"] for a in "xyz"], ff.rms[d], rtol=1e-8, atol=1e-9)
        if model == "auto":
            cv = next(r for r in m.report["cv"] if r["order"] == m.order)
            np.testing.assert_allclose([cv["per_axis"][a]["rms"] for a in "xyz"], ff.cv_rms[d], rtol=1e-7, atol=1e-9)
    return ff


@pytest.mark.parametrize("model", ["auto", 1, 2, 3])
def test_batched_equals_per_device_fit(model):
    serial, temp, y = fleet_rows(n_dev=25, temps=(-10.0, 5.0, 25.0, 45.0, 70.0), seed=2,
                                 ramp_devices=(3, 7), few_temp_devices=(5,), stray_devices=(9,))
    ff = _check_equal(serial, temp, y, model)
    assert ff.ok.sum() >= 20


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 10_000), n_temps=st.integers(2, 7), lo=st.floats(-40, 20), span=st.floats(6, 120),
       per_temp=st.integers(1, 20), noise=st.sampled_from([0.3, 2.0, 30.0]), model=st.sampled_from(["auto", 1, 2, 4]))
def test_batched_equals_per_device_fit_far_from_the_chamber(seed, n_temps, lo, span, per_temp, noise, model):
    """Other ranges, plateau counts, sample counts and noise levels; T0 at
    the middle of the range."""
    temps = tuple(np.linspace(lo, lo + span, n_temps).round(2))
    serial, temp, y = fleet_rows(n_dev=6, temps=temps, per_temp=per_temp, seed=seed, noise=noise,
                                 ramp_devices=(1,) if per_temp > 3 else ())
    _check_equal(serial, temp, y, model, t0=round(lo + span / 2, 2))


def test_device_groups_equal_the_per_device_rule():
    serial, temp, _ = fleet_rows(n_dev=12, seed=4, ramp_devices=(2,), stray_devices=(4, 5))
    devices, dev = np.unique(serial, return_inverse=True)
    labels, counts = device_groups(dev, temp, len(devices))
    for d in range(len(devices)):
        g = temperature_groups(temp[dev == d])
        assert counts[d] == g.count
        np.testing.assert_array_equal(labels[dev == d], g.labels)


def _run(tmp_path, logs, *extra, out="out"):
    argv = ["fleet-fit", *map(str, logs), "--device", "serial", "--columns", "x,y,z",
            "-o", str(tmp_path / out), *extra]
    return cli.main(argv)


def _summary(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_cli_writes_models_images_summary_and_plots(tmp_path, capsys):
    serial, temp, y = fleet_rows(n_dev=30, seed=1, few_temp_devices=(4,))
    y[serial == "SN-0007"] += np.outer(temp[serial == "SN-0007"], [4.0, 0, 0])   # a unit drifting far more
    log = write_fleet_log(tmp_path / "fleet.csv", serial, temp, y)
    assert _run(tmp_path, [log], "--k", "6") == 0
    printed = capsys.readouterr().out
    assert "k = 6" in printed
    out = tmp_path / "out"
    rows = {r["device"]: r for r in _summary(out / "fleet_summary.csv")}
    assert len(rows) == 30
    assert set(rows["SN-0000"]) >= {"device", "model", "n_temps", "cv_rms_x", "cv_rms_y", "cv_rms_z",
                                    "flagged", "reason"}
    assert rows["SN-0004"]["flagged"] == "1" and "2 temperatures" in rows["SN-0004"]["reason"]
    assert rows["SN-0007"]["flagged"] == "1" and "drift x" in rows["SN-0007"]["reason"]
    assert not (out / "SN-0004.json").exists()
    assert (out / "fleet_coefficients.png").stat().st_size > 0 and (out / "fleet_worst.png").stat().st_size > 0
    # the model and the image agree, and the image belongs to its device only
    model = tmodel.load(out / "SN-0001.json")
    image = (out / "SN-0001.bin").read_bytes()
    fields = parse_offset_poly(find_section(image, SECTION_OFFSET_POLY))
    assert fields["coef"] == [list(c) for c in model.fixed_fields()["coef"]]
    assert image_device_status(image, "SN-0001") == 0
    assert image_device_status(image, "SN-0002") == SIG_ERR_DEVICE
    assert json.loads((out / "SN-0001.json").read_text())["report"]["device"] == "SN-0001"
    model.save(tmp_path / "again.json")                  # the fleet writes what TcompModel.save writes
    assert (tmp_path / "again.json").read_bytes() == (out / "SN-0001.json").read_bytes()


def test_logs_split_over_files_equal_one_log_and_parquet_equals_csv(tmp_path):
    serial, temp, y = fleet_rows(n_dev=10, seed=3)
    cold = temp < 30
    write_fleet_log(tmp_path / "all.csv", serial, temp, y)
    write_fleet_log(tmp_path / "cold.parquet", serial[cold], temp[cold], y[cold])
    write_fleet_log(tmp_path / "hot.csv", serial[~cold], temp[~cold], y[~cold])
    assert _run(tmp_path, [tmp_path / "all.csv"], "--no-plots", out="one") == 0
    assert _run(tmp_path, [tmp_path / "cold.parquet", tmp_path / "hot.csv"], "--no-plots", out="two") == 0
    for name in ["fleet_summary.csv", "SN-0003.json", "SN-0003.bin"]:
        assert (tmp_path / "one" / name).read_bytes() == (tmp_path / "two" / name).read_bytes()


def test_parquet_dataset_partitioned_by_device(tmp_path):
    serial, temp, y = fleet_rows(n_dev=6, seed=5)
    pq.write_to_dataset(pa.table({"serial": serial.astype(str), "temp": temp, "x": y[:, 0], "y": y[:, 1],
                                  "z": y[:, 2]}), tmp_path / "ds", partition_cols=["serial"])
    write_fleet_log(tmp_path / "all.csv", serial, temp, y)
    assert _run(tmp_path, [tmp_path / "ds"], "--no-plots", out="a") == 0
    assert _run(tmp_path, [tmp_path / "all.csv"], "--no-plots", out="b") == 0
    assert (tmp_path / "a" / "fleet_summary.csv").read_bytes() == (tmp_path / "b" / "fleet_summary.csv").read_bytes()


def _leftovers(tmp_path):
    return sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".pysig"))


def test_same_serial_with_conflicting_data_in_two_files(tmp_path, capsys):
    serial, temp, y = fleet_rows(n_dev=4, seed=6)
    a = write_fleet_log(tmp_path / "a.csv", serial, temp, y)
    y2 = y.copy()
    y2[serial == "SN-0002"] += 50
    b = write_fleet_log(tmp_path / "b.csv", serial, temp, y2)
    assert _run(tmp_path, [a, b]) == 2
    err = capsys.readouterr().err
    assert "a.csv and" in err and "b.csv" in err and "'SN-0002'" in err and "conflicting" in err
    assert not (tmp_path / "out").exists() and _leftovers(tmp_path) == []


@pytest.mark.parametrize("make,words", [
    (lambda p: p.write_text("sn,temp,x,y,z\nA,0,1,2,3\n"), ["missing column 'serial'"]),
    (lambda p: p.write_text("serial,temp,x,x,y,z\nA,0,1,1,2,3\n"), ["'x' is given twice"]),
    (lambda p: p.write_text("serial,temp,x,y,z\nA,0,1,2,3\n,25,1,2,3\n"), ["row 3, column 'serial': empty serial"]),
    (lambda p: p.write_text("serial,temp,x,y,z\nA,0,1,2,3\nA,hot,1,2,3\n"), ["row 3, column 'temp': not a number"]),
])
def test_bad_logs_are_named_and_nothing_is_written(tmp_path, capsys, make, words):
    log = tmp_path / "log.csv"
    make(log)
    assert _run(tmp_path, [log]) == 2
    err = capsys.readouterr().err
    assert all(w in err for w in words), err
    assert not (tmp_path / "out").exists() and _leftovers(tmp_path) == []


def test_parquet_with_wrong_column_types(tmp_path, capsys):
    log = tmp_path / "log.parquet"
    pq.write_table(pa.table({"serial": ["A", "A"], "temp": [True, False], "x": [1.0, 2.0], "y": [1.0, 2.0],
                             "z": [1.0, 2.0]}), log)
    assert _run(tmp_path, [log]) == 2
    assert "column 'temp' holds bool, not numbers" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_integer_serials_in_parquet_are_serials(tmp_path):
    serial, temp, y = fleet_rows(n_dev=3, seed=7)
    num = np.array([int(s[3:]) + 1000 for s in serial])
    pq.write_table(pa.table({"serial": num, "temp": temp, "x": y[:, 0], "y": y[:, 1], "z": y[:, 2]}),
                   tmp_path / "log.parquet")
    assert _run(tmp_path, [tmp_path / "log.parquet"], "--no-plots") == 0
    assert (tmp_path / "out" / "1001.bin").exists()


def test_output_directory_is_replaced_whole_or_refused(tmp_path, capsys):
    serial, temp, y = fleet_rows(n_dev=5, seed=8)
    log = write_fleet_log(tmp_path / "log.csv", serial, temp, y)
    assert _run(tmp_path, [log], "--no-plots") == 0
    assert _run(tmp_path, [log], "--no-plots", "--model", "poly:1") == 0     # a previous fleet output: replaced
    assert _summary(tmp_path / "out" / "fleet_summary.csv")[0]["model"] == "poly:1"
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "keep.txt").write_text("mine")
    assert _run(tmp_path, [log], out="other") == 8
    assert "refusing" in capsys.readouterr().err
    assert sorted(p.name for p in (tmp_path / "other").iterdir()) == ["keep.txt"]


def test_serials_that_are_not_file_names(tmp_path):
    serial, temp, y = fleet_rows(n_dev=3, seed=9)
    serial = np.array([s.replace("SN-", "../lot 7/") for s in serial], dtype=object)
    log = write_fleet_log(tmp_path / "log.csv", serial, temp, y)
    assert _run(tmp_path, [log], "--no-plots") == 0
    rows = _summary(tmp_path / "out" / "fleet_summary.csv")
    for r in rows:
        assert "/" not in r["file"]
        image = (tmp_path / "out" / f"{r['file']}.bin").read_bytes()
        assert image_device_status(image, r["device"]) == 0
    assert len({r["file"] for r in rows}) == 3


def test_bad_model_option(tmp_path, capsys):
    serial, temp, y = fleet_rows(n_dev=2, seed=1)
    log = write_fleet_log(tmp_path / "log.csv", serial, temp, y)
    assert _run(tmp_path, [log], "--model", "poly:9") == 7
    assert "poly:N" in capsys.readouterr().err
