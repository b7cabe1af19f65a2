"""A real recording the defaults were not tuned on, the two-temperature IMU recording (../shared/data/bmi270_two_temps):
an order-1 temperature model of the gyro bias works and moves both plateaus'
bias to the same value; order 2 or more is refused, naming how many distinct
temperatures the data has (2) and how many the order needs."""
import numpy as np
import pytest

from conftest import require_shared_data
from pysig.tcomp import _poly_fit as fit
from pysig.cli import main
from pysig.errors import InsufficientDataError
from pysig.io import read_csv

GYRO = ["gyro_x_dps", "gyro_y_dps", "gyro_z_dps"]


@pytest.fixture(scope="module")
def recording():
    folder = require_shared_data("bmi270_two_temps")
    files = [folder / "bmi270_cold.csv", folder / "bmi270_hot.csv"]
    parts = [read_csv(f, ["temp_c"] + GYRO) for f in files]
    return files, {k: np.concatenate([p[k] for p in parts]) for k in ["temp_c"] + GYRO}


def test_two_plateaus_are_two_temperatures(recording):
    _, d = recording
    g = fit.temperature_groups(d["temp_c"])
    assert g.count == 2
    (lo0, hi0, n0), (lo1, hi1, n1) = g.ranges
    assert 12.9 < lo0 and hi0 < 13.4 and n0 == 3255
    assert 47.0 < lo1 and hi1 < 48.0 and n1 > 6400          # 10 start-up samples at 49.3 °C do not count


def test_order_one_moves_both_plateaus_to_the_same_bias(recording):
    _, d = recording
    model = fit.fit_tcomp(d["temp_c"], {k: d[k] for k in GYRO}, order=1, t0=25.0)
    rows = fit.group_bias_report(model, d["temp_c"], {k: d[k] for k in GYRO})
    cold, hot = rows
    # before: the published plateau biases (PROVENANCE.md), about 0.65 dps apart on x
    assert cold["before"]["gyro_x_dps"] == pytest.approx(-0.15, abs=0.05)
    assert hot["before"]["gyro_x_dps"] == pytest.approx(0.50, abs=0.05)
    for k in GYRO:
        before = abs(hot["before"][k] - cold["before"][k])
        after = abs(hot["after"][k] - cold["after"][k])
        assert after < 0.02 and (before < 0.05 or after < 0.1 * before), (k, before, after)


def test_order_two_is_refused_with_counts(recording):
    _, d = recording
    for order in (2, 3, 6):
        with pytest.raises(InsufficientDataError,
                           match=f"order {order} needs at least {order + 1} distinct temperatures, "
                                 f"the data has 2"):
            fit.fit_tcomp(d["temp_c"], {k: d[k] for k in GYRO}, order=order)


def test_cli_refuses_order_two_and_writes_nothing(recording, tmp_path, capsys):
    files, _ = recording
    out = tmp_path / "m.json"
    argv = ["fit", *map(str, files), "--temp", "temp_c", "--columns", ",".join(GYRO), "-o", str(out)]
    assert main(argv + ["--order", "2"]) == InsufficientDataError.exit_status
    err = capsys.readouterr().err
    assert "needs at least 3 distinct temperatures, the data has 2" in err and not out.exists()
    assert main(argv + ["--order", "1"]) == 0 and out.exists()
