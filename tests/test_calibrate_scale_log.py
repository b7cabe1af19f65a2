"""Grams end to end: `pysig calibrate-scale LOG --column C --masses ...`
finds the still loads in a raw log itself (the plateau finder of the demo),
fits counts -> mass, states a linearity error only with three or more
masses; `pysig filter --cal` writes the filtered mass; `--fixed` on readings
that are not integer codes is refused with the remedy (--scale-factor).
On the real HX711 recording (10-lb steps, in kg and in lb) and on generated
logs in other units, rates, noise and with an inverted cell."""
import json

import numpy as np
import pytest

from conftest import require_shared_data
from pysig.cli import main
from pysig.errors import InsufficientDataError, RangeError
from pysig.io import read_csv
from pysig.weigh import load_calibration, plateaus_at_masses

HX711 = "hx711_steps_10hz/hx711_steps_10hz.csv"
KG_PER_10LB = 4.5359237


def run(argv, capsys):
    status = main(argv)
    out = capsys.readouterr()
    return status, out.out, out.err


def plateau_errors(path, column, masses, rate, out_col, cal_path=None):
    """|median of the filtered mass over the second half of each plateau - its mass|."""
    d = read_csv(str(path), [column, out_col])
    errs = []
    for p in plateaus_at_masses(d[column], masses, rate):
        half = slice(p.start + (p.stop - p.start) // 2, p.stop)
        errs.append(abs(float(np.median(d[out_col][half])) - p.nominal))
    return np.array(errs)


@pytest.mark.parametrize("channel", ["lc1", "lc2"])
@pytest.mark.parametrize("unit,step", [("kg", KG_PER_10LB), ("lb", 10.0)])
def test_hx711_recording_calibrates_and_filters_to_mass(tmp_path, capsys, channel, unit, step):
    log = require_shared_data(HX711)
    masses = ",".join(f"{k * step:g}" for k in range(5))
    cal = tmp_path / "cal.json"
    status, out, err = run(["calibrate-scale", str(log), "--column", f"{channel}_counts", "--masses", masses,
                            "--time", "t_s", "--unit", unit, "-o", str(cal)], capsys)
    assert status == 0, err
    assert "9 plateaus" in out and "linearity error" in out
    c = load_calibration(cal)
    per_lb = c.counts_per_unit * (KG_PER_10LB / 10.0 if unit == "kg" else 1.0)
    assert 950 < per_lb < 1050                       # ~1000 counts per lb (the recording's notes)
    assert c.linearity_err_pct_fs is not None and c.linearity_err_pct_fs < 0.5
    for fixed in ([], ["--fixed"]):
        filtered = tmp_path / f"f{len(fixed)}.csv"
        status, out, err = run(["filter", str(log), "--column", f"{channel}_counts", "--cal", str(cal),
                                "-o", str(filtered)] + fixed, capsys)
        assert status == 0, err
        errs = plateau_errors(filtered, f"{channel}_counts", [k * step for k in range(5)], 10.0,
                              f"filtered_{unit}")
        assert errs.size == 9 and errs.max() < 0.01 * 4 * step       # within 1 % of full scale


def test_two_masses_state_no_linearity(tmp_path, capsys):
    log = require_shared_data(HX711)
    cal = tmp_path / "cal.json"
    # lc1 with only its first two loads named is refused (5 loads found) ...
    status, _, err = run(["calibrate-scale", str(log), "--column", "lc1_counts", "--masses", "0,4.536",
                          "--time", "t_s", "-o", str(cal)], capsys)
    assert status == RangeError.exit_status and "5 still loads" in err and not cal.exists()
    # ... a generated two-load log is not: a line through two masses, no linearity figure
    src = tmp_path / "two.csv"
    write_log(src, [0.0, 250.0], rate=10.0, counts_per_unit=400.0, noise=30.0, seed=1)
    status, out, err = run(["calibrate-scale", str(src), "--column", "counts", "--masses", "0,250",
                            "--rate", "10", "--unit", "g", "-o", str(cal)], capsys)
    assert status == 0, err
    assert "linearity not measured" in out and "linearity error" not in out
    assert json.loads(cal.read_text())["linearity_err_pct_fs"] is None
    assert load_calibration(cal).linearity_err_pct_fs is None


def write_log(path, masses, rate, counts_per_unit, noise, seed, zero=-120000.0, hold_s=6.0, ramp_s=1.5,
              glitches=3):
    """A raw log: each mass placed by a ramp (a hand), held hold_s, the next
    one; noise in counts, a few read glitches; integer codes."""
    rng = np.random.default_rng(seed)
    hold, ramp = int(hold_s * rate), int(ramp_s * rate)
    level, parts = 0.0, []
    for m in masses:
        parts.append(np.linspace(level, m, ramp, endpoint=False))
        parts.append(np.full(hold, m))
        level = m
    mass = np.concatenate(parts)
    counts = np.round(zero + counts_per_unit * mass + rng.normal(0, noise, mass.size))
    counts[rng.choice(np.arange(ramp, mass.size), glitches, replace=False)] = -8000000
    np.savetxt(path, np.c_[np.arange(mass.size) / rate, counts], delimiter=",", header="t,counts",
               comments="", fmt=["%.4f", "%d"])
    return mass


@pytest.mark.parametrize("case", [
    # (masses, unit, rate Hz, counts per unit, noise counts)
    ([0.0, 52.7, 152.7, 400.0, 652.7], "g", 10.0, 430.0, 40.0),       # a coffee scale, HX711
    ([0.0, 1.0, 2.5, 5.0], "lb", 80.0, -90000.0, 400.0),                # inverted cell, 80 Hz
    ([0.0, 0.2, 0.5, 1.0, 2.0, 3.0], "kg", 50.0, 1.2e5, 15.0),          # quiet, many loads
])
def test_generated_logs_in_other_units(tmp_path, capsys, case):
    masses, unit, rate, cpu, noise = case
    src = tmp_path / "log.csv"
    write_log(src, masses, rate, cpu, noise, seed=3)
    cal = tmp_path / "cal.json"
    status, out, err = run(["calibrate-scale", str(src), "--column", "counts", "--time", "t",
                            "--masses", ",".join(map(str, masses)), "--unit", unit, "-o", str(cal)], capsys)
    assert status == 0, err
    c = load_calibration(cal)
    assert c.counts_per_unit == pytest.approx(cpu, rel=0.005)
    assert c.linearity_err_pct_fs is not None and c.linearity_err_pct_fs < 0.5
    out_csv = tmp_path / "out.csv"
    status, out, err = run(["filter", str(src), "--column", "counts", "--cal", str(cal), "-o", str(out_csv)],
                           capsys)
    assert status == 0, err
    errs = plateau_errors(out_csv, "counts", masses, rate, f"filtered_{unit}")
    assert errs.size == len(masses) and errs.max() < 0.005 * max(masses) + 3 * noise / abs(cpu)


def test_fewer_loads_than_masses_is_named(tmp_path):
    src = tmp_path / "log.csv"
    write_log(src, [0.0, 100.0], 10.0, 400.0, 20.0, seed=2)
    x = read_csv(str(src), ["counts"])["counts"]
    with pytest.raises(InsufficientDataError, match="3 masses given, 2 still loads"):
        plateaus_at_masses(x, [0.0, 100.0, 200.0], 10.0)
    with pytest.raises(RangeError, match="each load's mass once"):
        plateaus_at_masses(x, [0.0, 0.0], 10.0)


def test_fixed_refuses_readings_in_grams_and_takes_a_scale_factor(tmp_path, capsys):
    """A column in grams with decimals is not integer codes: --fixed refuses
    it, naming the row and the remedy; with --scale-factor 10 the fixed chain
    runs on tenths of a gram and the output is back in grams, close to the
    float chain's."""
    rng = np.random.default_rng(5)
    grams = np.round(np.r_[np.zeros(80), np.full(120, 52.7)] + rng.normal(0, 0.3, 200), 1)
    src = tmp_path / "g.csv"
    np.savetxt(src, np.c_[np.arange(200) / 10, grams], delimiter=",", header="t,grams", comments="",
               fmt=["%.1f", "%.1f"])
    out = tmp_path / "out.csv"
    status, _, err = run(["filter", str(src), "--column", "grams", "--fixed", "-o", str(out)], capsys)
    first = int(np.flatnonzero(grams != np.rint(grams))[0])
    assert status == RangeError.exit_status and not out.exists()
    assert f"row {first + 2}" in err and "not an integer code" in err and "--scale-factor" in err
    status, _, err = run(["filter", str(src), "--column", "grams", "--fixed", "--scale-factor", "10",
                          "-o", str(out)], capsys)
    assert status == 0, err
    fixed = read_csv(str(out), ["filtered"])["filtered"]
    status, _, err = run(["filter", str(src), "--column", "grams", "-o", str(out)], capsys)
    flt = read_csv(str(out), ["filtered"])["filtered"]
    assert np.abs(fixed - flt)[100:].max() < 0.05          # tenths of a gram: the fixed form's codes
    assert abs(np.median(fixed[150:]) - 52.7) < 0.1
