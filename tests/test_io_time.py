"""Time columns as loggers write them: numbers in a stated unit, or ISO 8601
date-times (with or without a zone, CSV text or a Parquet timestamp), all
read as seconds; the refine command gives the same result for either form
of the same times."""
import datetime as dt
import json

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from pysig.cli import main
from pysig.errors import InputFileError, NonFiniteError
from pysig.io import read_time_column

START = dt.datetime(2026, 3, 1, 12, 0, 0)


def write(path, header, rows):
    path.write_text(header + "\n" + "\n".join(rows) + "\n")
    return path


def test_numbers_are_read_in_the_unit_given(tmp_path):
    f = write(tmp_path / "a.csv", "t,x", ["0,1", "250,2", "500,3"])
    t, kind = read_time_column(f, "t", "ms")
    assert kind == "number"
    np.testing.assert_allclose(t, [0.0, 0.25, 0.5])


@pytest.mark.parametrize("fmt", ["%Y-%m-%dT%H:%M:%S.%f", "%Y-%m-%d %H:%M:%S.%f"])
def test_date_times_without_a_zone_are_seconds_on_their_own_clock(tmp_path, fmt):
    times = [START + dt.timedelta(seconds=s) for s in (0.0, 1.5, 3600.25)]
    f = write(tmp_path / "a.csv", "when,x", [f"{w.strftime(fmt)},1" for w in times])
    t, kind = read_time_column(f, "when")
    assert kind == "date-time"
    np.testing.assert_allclose(t - t[0], [0.0, 1.5, 3600.25], atol=1e-6)
    assert t[0] == pytest.approx(START.replace(tzinfo=dt.timezone.utc).timestamp())


def test_date_times_with_zones_are_converted_to_one_clock(tmp_path):
    # the same instant written in two zones, then one second later
    f = write(tmp_path / "a.csv", "when,x", ["2026-03-01T12:00:00Z,1", "2026-03-01T14:00:01+02:00,2"])
    t, _ = read_time_column(f, "when")
    np.testing.assert_allclose(np.diff(t), [1.0])


def test_a_parquet_timestamp_column_is_read_as_seconds(tmp_path):
    f = tmp_path / "a.parquet"
    when = [START + dt.timedelta(seconds=s) for s in (0, 2, 4)]
    pq.write_table(pa.table({"when": pa.array(when, pa.timestamp("ms")), "x": [1.0, 2.0, 3.0]}), f)
    t, kind = read_time_column(f, "when")
    assert kind == "date-time"
    np.testing.assert_allclose(t - t[0], [0.0, 2.0, 4.0])


def test_a_mixed_column_is_refused_with_its_reason(tmp_path):
    f = write(tmp_path / "a.csv", "when,x", ["2026-03-01T12:00:00,1", "2026-03-01T12:00:01Z,2"])
    with pytest.raises(InputFileError, match="with a zone .* and without one"):
        read_time_column(f, "when")


def refine_log(tmp_path, iso):
    """A chamber log with a lagging sensor, its time as seconds or as date-times."""
    rng = np.random.default_rng(5)
    t = np.arange(0.0, 4 * 3600.0, 4.0)
    temp = 25.0 + 15.0 * np.sign(np.sin(2 * np.pi * t / 3600.0))
    alpha = 1.0 - np.exp(-4.0 / 300.0)
    die = np.empty_like(temp)
    die[0] = temp[0]
    for k in range(1, t.size):
        die[k] = die[k - 1] + alpha * (temp[k] - die[k - 1])
    x = 2.0 * die + 0.2 * rng.standard_normal(t.size)
    stamps = [(START + dt.timedelta(seconds=float(s))).isoformat() if iso else f"{s:g}" for s in t]
    return write(tmp_path / ("iso.csv" if iso else "num.csv"), "t,temp,x",
                 [f"{a},{b:.3f},{c:.4f}" for a, b, c in zip(stamps, temp, x)])


def test_refine_reads_date_times_as_it_reads_the_same_seconds(tmp_path):
    reports = []
    for iso in (False, True):
        out = tmp_path / f"r{int(iso)}.json"
        assert main(["refine", str(refine_log(tmp_path, iso)), "--time", "t", "--temp", "temp",
                     "--columns", "x", "--json", str(out)]) == 0
        reports.append(json.loads(out.read_text()))
    a, b = reports         # one measured column: the report itself
    assert a["effects_found"] == b["effects_found"] == ["thermal_lag"]
    assert [s["params"] for s in a["steps"]] == [s["params"] for s in b["steps"]]


@pytest.mark.parametrize("cells, error, where", [
    (["0", "1.5", "x"], InputFileError, "row 4, column 'when': not a number: 'x'"),
    (["2026-03-01T12:00:00", "nan", "2026-03-01T12:00:02"], NonFiniteError, "row 3, column 'when': missing"),
    (["2026-03-01T12:00:00Z", "2026-03-01T12:00:01Z", "01/03/2026 12:00"], InputFileError,
     "row 4, column 'when': not a number nor an ISO 8601 date-time"),
])
def test_a_bad_time_cell_is_named_by_its_row(tmp_path, cells, error, where):
    f = write(tmp_path / "a.csv", "when,x", [f"{c},1" for c in cells])
    with pytest.raises(error, match=where):
        read_time_column(f, "when")
