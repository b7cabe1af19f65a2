"""`pysig refine` on top of `pysig fit`: --model starts from the fitted
model's family and size; the time column's unit: --time-unit, and a
warning when seconds are unlikely (the name, or the sample interval)."""
import json

import numpy as np
import pytest

from lab.studies.refine_cases import chamber_run
from pysig.cli import main
from pysig.io import read_csv, write_csv


@pytest.fixture(scope="module")
def lag_run(tmp_path_factory):
    """A chamber run with a 90-s-class thermal lag, 2 s between samples,
    its time in s, ms and us."""
    run = chamber_run("thermal_lag", seed=11, constant_field=True)
    path = tmp_path_factory.mktemp("lag") / "run.csv"
    write_csv(path, {"t": run["t"], "t_ms": run["t"] * 1e3, "stamp": run["t"] * 1e3, "tick": run["t"] * 1e6,
                     "temp": run["temp"], "x": run["x"]})
    return path


@pytest.fixture(scope="module")
def short_run(lag_run, tmp_path_factory):
    """The first 400 samples of lag_run: the time-unit warning looks only at
    the time column's name and sample interval, and refine runs in a
    fraction of a second on them."""
    run = {k: v[:400] for k, v in read_csv(str(lag_run)).items()}
    path = tmp_path_factory.mktemp("short") / "run.csv"
    write_csv(path, run)
    return path


def refine_json(path, out, *args):
    assert main(["refine", str(path), "--temp", "temp", "--columns", "x", "--json", str(out), *args]) == 0
    return json.loads(out.read_text())


def test_time_in_ms_with_its_unit_gives_the_seconds_result(lag_run, tmp_path, capsys):
    seconds = refine_json(lag_run, tmp_path / "s.json", "--time", "t")
    capsys.readouterr()
    ms = refine_json(lag_run, tmp_path / "ms.json", "--time", "t_ms", "--time-unit", "ms")
    assert "warning" not in capsys.readouterr().err
    tau = [s["params"]["tau_s"] for s in seconds["steps"] if s["effect"] == "thermal_lag"]
    assert tau and tau == pytest.approx([s["params"]["tau_s"] for s in ms["steps"]
                                         if s["effect"] == "thermal_lag"], rel=1e-9)
    assert 30 < tau[0] < 300                     # seconds, not 1000x that


@pytest.mark.parametrize("column, unit, why", [("t_ms", "ms", "named like ms"),
                                               ("stamp", "ms", "median sample interval is 2000 s"),
                                               ("tick", "us", "median sample interval is 2e+06 s")])
def test_a_time_column_that_looks_like_ms_or_us_is_warned_about(short_run, tmp_path, capsys, column, unit, why):
    refine_json(short_run, tmp_path / "r.json", "--time", column)
    err = capsys.readouterr().err
    assert why in err and f"--time-unit {unit}" in err
    refine_json(short_run, tmp_path / "r.json", "--time", column, "--time-unit", "s")     # said: no warning
    assert "warning" not in capsys.readouterr().err


@pytest.mark.parametrize("spec, family, size", [("table:9", "table", 9), ("poly:3", "poly", 3)])
def test_refine_starts_from_the_fitted_model(lag_run, tmp_path, capsys, spec, family, size):
    model = tmp_path / "model.json"
    assert main(["fit", str(lag_run), "--columns", "x", "--model", spec, "-o", str(model)]) == 0
    capsys.readouterr()
    out = tmp_path / "r.json"
    assert main(["refine", str(lag_run), "--time", "t", "--model", str(model), "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    assert f"base model {family}:{size} from {model}" in printed
    base = json.loads(out.read_text())["base_model"]
    assert (base["offset_family"], base["offset_order"]) == (family, size)
    assert "thermal_lag" in printed                 # the lag the model lacks is still found


@pytest.mark.parametrize("dt, hours, warned", [
    (60.0, 30.0, False),          # a day-long log at one sample a minute, in seconds
    (300.0, 72.0, False),         # three days at one every 5 min
    (1.0, 24.0 * 20, False),      # 20 days at 1 Hz
    (2000.0, 9.3 * 24, True),     # 2-s samples in ms: "9 days" at 2000 "s"
    (100.0, 14 * 24.0, True),     # 10 Hz in ms for 20 min
    (5.0, 31 * 24.0, True),       # anything spanning more than a month
])
def test_the_unit_warning_spares_long_logs_at_a_minute_or_so(dt, hours, warned):
    from pysig.cli.commands.refine import time_unit_warning
    t = np.arange(0.0, hours * 3600.0, dt)
    assert (time_unit_warning("t", t) is not None) == warned
