"""The fleet fit on Dask (a small local cluster) equals the local engine:
the same summary, models and images, byte for byte."""
import pytest

pytest.importorskip("dask.dataframe")
pytest.importorskip("distributed")

from fleet_cases import fleet_rows, write_fleet_log  # noqa: E402
from pysig import cli  # noqa: E402
from pysig.errors import InputFileError  # noqa: E402
from pysig.fleet._dask import connect, fit_fleet_dask  # noqa: E402


@pytest.fixture(scope="module")
def client():
    with connect(workers=2, processes=False) as c:
        yield c


def test_dask_equals_local(tmp_path, client, monkeypatch):
    serial, temp, y = fleet_rows(n_dev=24, seed=11, few_temp_devices=(3,), ramp_devices=(5,))
    cold = temp < 30
    # a device's rows spread over two files: the shuffle must bring them together
    write_fleet_log(tmp_path / "cold.parquet", serial[cold], temp[cold], y[cold])
    write_fleet_log(tmp_path / "hot.csv", serial[~cold], temp[~cold], y[~cold])
    logs = [str(tmp_path / "cold.parquet"), str(tmp_path / "hot.csv")]
    base = ["fleet-fit", *logs, "--device", "serial", "--columns", "x,y,z", "--no-plots"]
    assert cli.main([*base, "-o", str(tmp_path / "local")]) == 0
    import pysig.fleet._dask as fd
    monkeypatch.setattr(fd, "connect", lambda *a, **k: _Borrowed(client))
    assert cli.main([*base, "--engine", "dask", "-o", str(tmp_path / "dask")]) == 0
    local = sorted(p.name for p in (tmp_path / "local").iterdir())
    assert local == sorted(p.name for p in (tmp_path / "dask").iterdir()) and len(local) == 2 * 23 + 1
    for name in local:
        assert (tmp_path / "local" / name).read_bytes() == (tmp_path / "dask" / name).read_bytes(), name


class _Borrowed:
    """The module's client, lent to the CLI without closing it."""
    def __init__(self, client):
        self.client = client

    def __enter__(self):
        return self.client

    def __exit__(self, *exc):
        return False


def test_dask_conflicting_serial_is_the_same_error(tmp_path, client):
    serial, temp, y = fleet_rows(n_dev=4, seed=12)
    write_fleet_log(tmp_path / "a.csv", serial, temp, y)
    y[serial == "SN-0001"] += 9
    write_fleet_log(tmp_path / "b.csv", serial, temp, y)
    with pytest.raises(InputFileError, match="'SN-0001' has conflicting data"):
        fit_fleet_dask([tmp_path / "a.csv", tmp_path / "b.csv"], "serial", "temp", ["x", "y", "z"], client=client)
