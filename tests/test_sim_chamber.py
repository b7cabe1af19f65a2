"""The QMC5883L-like chamber simulator: seeded and reproducible, int16
readings at 12000 LSB/G, the magnetometer paper's chamber steps, and each switchable
effect off by default and doing what its parameter says when on."""
import numpy as np
import pytest

from pysig.sim import _chamber as sc
from pysig.io import read_csv


def test_seeded_reproducible_and_csv(tmp_path):
    p = sc.ChamberParams(seed=7, dwell_s=300)
    a, b = sc.simulate(p), sc.simulate(p)
    for k in sc.COLUMNS:
        np.testing.assert_array_equal(a[k], b[k])
    assert not np.array_equal(a["x"], sc.simulate(sc.ChamberParams(seed=8, dwell_s=300))["x"])
    d = sc.write(tmp_path / "c.csv", p)
    back = read_csv(tmp_path / "c.csv")
    assert list(back) == list(sc.COLUMNS)
    np.testing.assert_array_equal(back["x"], d["x"])


def test_plateaus_scale_and_int16():
    p = sc.ChamberParams(seed=1, noise_lsb=0.0, temp_noise_c=0.0, gain_drift=((0.0,),) * 3,
                         offset_poly=((0.0,),) * 3)
    d = sc.simulate(p)
    assert d["x"].dtype.kind == "i" and d["x"].min() >= -32768 and d["x"].max() <= 32767
    np.testing.assert_array_equal(d["x"], np.full(d["t"].size, 3600))         # 0.3 G * 12000
    np.testing.assert_array_equal(d["ref_y"], np.full(d["t"].size, -2400.0))
    levels, counts = np.unique(d["temp"], return_counts=True)
    top = set(levels[np.argsort(counts)[-4:]])
    assert top == {0.0, 25.0, 50.0, 70.0}
    big = sc.simulate(sc.ChamberParams(field_g=(2.5, 0.0, 0.0), noise_lsb=0.0, dwell_s=60))
    assert big["x"].max() == 24000                                           # +-2 G range


def test_temperature_sensor_resolution_and_noise():
    d = sc.simulate(sc.ChamberParams(seed=3, temp_resolution_c=0.25, temp_noise_c=0.1, dwell_s=600))
    np.testing.assert_allclose(d["temp"] / 0.25, np.round(d["temp"] / 0.25))
    plateau = d["temp"][:600]
    assert 0.05 < np.std(plateau) < 0.2


def test_hysteresis_separates_heating_from_cooling():
    base = dict(seed=4, profile="ramp", noise_lsb=0.0, temp_noise_c=0.0, temp_resolution_c=0.01,
                dwell_s=60, ramp_c_per_min=2.0)
    off = sc.simulate(sc.ChamberParams(**base))
    on = sc.simulate(sc.ChamberParams(**base, hysteresis_lsb=(20.0, 0.0, -10.0)))
    diff = on["x"] - off["x"]
    rising = np.diff(on["temp"], prepend=on["temp"][0]) > 0
    falling = np.diff(on["temp"], prepend=on["temp"][0]) < 0
    assert np.all(np.abs(diff[rising] - 10) <= 1) and np.all(np.abs(diff[falling] + 10) <= 1)
    np.testing.assert_array_equal(on["y"], off["y"])


def test_thermal_lag_delays_the_drift():
    base = dict(seed=5, noise_lsb=0.0, temp_noise_c=0.0, temp_resolution_c=0.01, dwell_s=2400,
                step_temps_c=(0.0, 40.0), ramp_c_per_min=10.0, gain_drift=((0.0,),) * 3,
                offset_poly=((0.0, 10.0),) * 3)
    fast = sc.simulate(sc.ChamberParams(**base))
    slow = sc.simulate(sc.ChamberParams(**base, thermal_lag_s=300.0))
    end_ramp = 2400 + 240            # 40 °C at 10 °C/min
    assert fast["x"][end_ramp] - slow["x"][end_ramp] > 100                 # die still cold
    i = end_ramp + 300
    lag_part = (fast["x"][i] - slow["x"][i]) / (fast["x"][end_ramp] - slow["x"][end_ramp])
    assert 0.25 < lag_part < 0.5                                           # ~exp(-1) after one tau
    assert abs(int(fast["x"][-1]) - int(slow["x"][-1])) <= 2                # settled at the end


def test_cross_axis_and_cubic_nonlinearity():
    base = dict(seed=6, noise_lsb=0.0, dwell_s=60, gain_drift=((0.0,),) * 3, offset_poly=((0.0,),) * 3)
    m = ((1.0, 0.1, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    d = sc.simulate(sc.ChamberParams(**base, cross_axis=m))
    assert d["x"][0] == round((0.30 + 0.1 * -0.20) * 12000) and d["y"][0] == -2400
    n = sc.simulate(sc.ChamberParams(**base, cubic_lsb_per_g3=(1000.0, 0.0, 0.0)))
    assert n["x"][0] == 3600 + round(1000 * 0.3 ** 3)


def test_bad_profile_is_refused():
    with pytest.raises(ValueError, match="profile"):
        sc.simulate(sc.ChamberParams(profile="sine"))


def test_cli_chamber_then_fit(tmp_path, capsys):
    from pysig.cli import main
    csv_path, model = tmp_path / "ch.csv", tmp_path / "m.json"
    assert main(["chamber", "-o", str(csv_path), "--seed", "9", "--dwell", "600"]) == 0
    np.testing.assert_array_equal(read_csv(csv_path)["x"],
                                  sc.simulate(sc.ChamberParams(seed=9, dwell_s=600))["x"])
    assert main(["fit", str(csv_path), "--columns", "x,y,z", "--order", "auto", "-o", str(model)]) == 0
    assert "order chosen: 2" in capsys.readouterr().out
    assert main(["chamber", "-o", str(tmp_path / "bad.csv"), "--dwell", "0"]) == 7
    assert not (tmp_path / "bad.csv").exists()
