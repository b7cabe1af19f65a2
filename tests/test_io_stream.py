"""Streaming: the chain's state carried across chunks gives byte for byte
the output of the in-memory path; errors found in a later chunk still name
the row; nothing is written when a chunk fails."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig import cli
from pysig.errors import NonFiniteError
from pysig.io import read_csv, write_csv
from pysig.io_stream import iter_batches, table_sink
from pysig.sim._loadcell import simulate


def _recording(tmp_path, n=6000, seed=0, suffix=".csv"):
    rng = np.random.default_rng(seed)
    t = np.round(np.arange(n) * 0.1, 1)
    level = np.repeat(rng.integers(0, 40000, n // 500 + 1), 500)[:n]
    counts = level + rng.normal(0, 70, n).round().astype(np.int64)
    counts[rng.integers(0, n, 5)] = -8388000                   # HX711-like read glitches
    src = tmp_path / f"in{suffix}"
    write_csv(src, {"t": t, "counts": counts, "other": rng.normal(size=n)})
    return src


def _filter(src, out, *extra):
    assert cli.main(["filter", str(src), "--column", "counts", "-o", str(out), "--status", *extra]) == 0


@settings(max_examples=12, deadline=None)
@given(chunk_kb=st.integers(1, 64), fixed=st.booleans())
def test_streamed_output_is_byte_identical_to_in_memory(tmp_path_factory, chunk_kb, fixed):
    tmp = tmp_path_factory.mktemp("s")
    src = _recording(tmp)
    extra = ["--fixed"] if fixed else []
    _filter(src, tmp / "mem.csv", "--in-memory", *extra)
    _filter(src, tmp / "stream.csv", "--chunk-mb", str(chunk_kb / 1024), *extra)
    assert (tmp / "mem.csv").read_bytes() == (tmp / "stream.csv").read_bytes()


def test_streaming_really_uses_many_chunks(tmp_path):
    src = _recording(tmp_path)
    offsets = [off for off, _ in iter_batches(src, numeric=["counts"], block_bytes=4096)]
    assert len(offsets) > 20 and offsets[0] == 0 and offsets == sorted(offsets)


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_parquet_streaming_equals_in_memory(tmp_path, suffix):
    src = _recording(tmp_path, suffix=".parquet")
    _filter(src, tmp_path / f"mem{suffix}", "--in-memory")
    _filter(src, tmp_path / f"stream{suffix}", "--chunk-mb", "0.01")
    a, b = read_csv(tmp_path / f"mem{suffix}"), read_csv(tmp_path / f"stream{suffix}")
    assert list(a) == list(b) == ["t", "counts", "other", "filtered", "stable", "status"]
    for name in a:
        np.testing.assert_array_equal(a[name], b[name])


def test_simulated_load_cell_through_csv_and_parquet(tmp_path):
    """A simulated run far from the HX711 recording: both formats, both modes."""
    run = simulate(seed=4)
    write_csv(tmp_path / "sim.parquet", {"t": run["t"], "counts": run["counts"]})
    write_csv(tmp_path / "sim.csv", {"t": run["t"], "counts": run["counts"]})
    _filter(tmp_path / "sim.parquet", tmp_path / "p.csv", "--chunk-mb", "0.002")
    _filter(tmp_path / "sim.csv", tmp_path / "c.csv", "--in-memory")
    assert (tmp_path / "p.csv").read_bytes() == (tmp_path / "c.csv").read_bytes()


def test_bad_cell_in_a_late_chunk_is_named_and_nothing_is_written(tmp_path, capsys):
    src = _recording(tmp_path)
    lines = src.read_text().splitlines(keepends=True)
    row = 5000                                     # file row (header is row 1)
    cells = lines[row - 1].split(",")
    cells[1] = "12x4"
    lines[row - 1] = ",".join(cells)
    src.write_text("".join(lines))
    out = tmp_path / "out.csv"
    assert cli.main(["filter", str(src), "--column", "counts", "-o", str(out), "--chunk-mb", "0.004"]) == 2
    assert f"row {row}, column 'counts': not a number: '12x4'" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.csv"]


def test_fixed_nonfinite_in_a_late_chunk_names_the_row(tmp_path, capsys):
    src = tmp_path / "in.csv"
    src.write_text("counts\n" + "".join(f"{1000 + i % 7}\n" for i in range(3000)) + "nan\n")
    out = tmp_path / "out.csv"
    status = cli.main(["filter", str(src), "--column", "counts", "--fixed", "-o", str(out), "--chunk-mb", "0.001"])
    assert status == NonFiniteError.exit_status
    assert "row 3002, column 'counts'" in capsys.readouterr().err
    assert not out.exists()


def test_type_change_after_the_first_chunk_is_a_clear_error(tmp_path, capsys):
    src = tmp_path / "in.csv"
    src.write_text("label,counts\n" + "".join(f"{i},{1000 + i % 7}\n" for i in range(3000)) + "late,5\n")
    out = tmp_path / "out.csv"
    assert cli.main(["filter", str(src), "--column", "counts", "-o", str(out), "--chunk-mb", "0.001"]) == 2
    err = capsys.readouterr().err
    assert "column 'label'" in err and "--in-memory" in err
    assert not out.exists()
    assert cli.main(["filter", str(src), "--column", "counts", "-o", str(out), "--in-memory"]) == 0


def test_sink_leaves_nothing_when_the_block_fails(tmp_path):
    import pyarrow as pa
    with pytest.raises(RuntimeError):
        with table_sink(tmp_path / "o.parquet") as sink:
            sink.write(pa.record_batch({"a": [1, 2]}))
            raise RuntimeError("cut")
    assert list(tmp_path.iterdir()) == []


def test_no_progress_bar_when_stderr_is_not_a_terminal(tmp_path, capsys):
    src = _recording(tmp_path, n=2000)
    _filter(src, tmp_path / "o.csv", "--chunk-mb", "0.002")
    assert capsys.readouterr().err == ""


def test_progress_bar_on_a_terminal(tmp_path, monkeypatch):
    import io
    import sys

    class Tty(io.StringIO):
        def isatty(self):
            return True
    fake = Tty()
    monkeypatch.setattr(sys, "stderr", fake)
    src = _recording(tmp_path, n=2000, suffix=".parquet")
    _filter(src, tmp_path / "o.csv", "--chunk-mb", "0.002")
    assert "/2.00k" in fake.getvalue() and "rows/s" in fake.getvalue()   # the Parquet row count is the total
