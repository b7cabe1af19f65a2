"""pyarrow's worker threads must never hold a Python object after a read or
write returns.  A reader released on a worker thread while the interpreter
exits takes the GIL there, and the process aborts after its work is done
("terminate called without an active exception"; a core dump of such an
abort showed the CSV reader's invalid-row callback released on a pool
thread, apache/arrow#34314; another showed the same from the single-threaded
streaming reader).  So reads and writes hand pyarrow no Python callback and
no Python file object; a malformed row is found from pyarrow's own message
on a single-threaded re-read."""
import numpy as np
import pyarrow.csv as pcsv
import pytest

from pysig.errors import InputFileError
from pysig.io import read_csv, to_table, write_csv
from pysig.io_stream import iter_batches, table_sink


@pytest.fixture
def parse_options_seen(monkeypatch):
    """Every invalid_row_handler given to pyarrow's ParseOptions."""
    seen = []
    real = pcsv.ParseOptions

    def recording(*args, **kwargs):
        seen.append(kwargs.get("invalid_row_handler"))
        return real(*args, **kwargs)
    monkeypatch.setattr(pcsv, "ParseOptions", recording)
    return seen


def _log(path, n=5000):
    rng = np.random.default_rng(0)
    write_csv(path, {"t": np.arange(n) * 0.1, "x": rng.normal(size=n)})
    return path


def test_a_read_hands_pyarrow_no_callback(tmp_path, parse_options_seen):
    src = _log(tmp_path / "in.csv")
    read_csv(str(src))
    for _ in iter_batches(str(src), numeric=["t", "x"], block_bytes=4096):
        pass
    assert parse_options_seen and all(h is None for h in parse_options_seen)


def test_a_malformed_row_is_still_named_by_its_row(tmp_path, parse_options_seen):
    src = _log(tmp_path / "in.csv")
    lines = src.read_text().splitlines()
    lines[3001] = "7"                                  # row 3002 has one cell, the header two
    src.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputFileError, match="row 3002"):
        read_csv(str(src))
    with pytest.raises(InputFileError, match="row 3002"):
        for _ in iter_batches(str(src), numeric=["t", "x"], block_bytes=4096):
            pass
    assert parse_options_seen and all(h is None for h in parse_options_seen)


def test_csv_output_goes_through_pyarrows_own_file(tmp_path, monkeypatch):
    seen = []
    real = pcsv.write_csv

    def recording(table, sink, **kwargs):
        seen.append(type(sink).__name__)
        return real(table, sink, **kwargs)
    monkeypatch.setattr(pcsv, "write_csv", recording)
    _log(tmp_path / "out.csv", n=10)
    assert seen == ["OSFile"]
    real_writer = pcsv.CSVWriter
    kinds = []

    def recording_writer(sink, schema, **kwargs):
        kinds.append(type(sink).__name__)
        return real_writer(sink, schema, **kwargs)
    monkeypatch.setattr(pcsv, "CSVWriter", recording_writer)
    with table_sink(str(tmp_path / "stream.csv")) as sink:
        sink.write(to_table(read_csv(str(tmp_path / "out.csv"))))
    assert kinds == ["OSFile"]

