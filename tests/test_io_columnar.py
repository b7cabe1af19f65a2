"""Columnar I/O: Parquet wherever CSV works, a header naming a column twice,
Parquet columns of the wrong type, bad cells located by row and column."""
import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from pysig import cli
from pysig.errors import InputFileError, NonFiniteError
from pysig.io import read_csv, read_header, read_table, write_csv


def test_parquet_round_trip_keeps_values_and_integer_columns(tmp_path):
    cols = {"t": np.arange(5) * 0.1, "n": np.arange(5), "flag": np.array([1, 0, 1, 1, 0], dtype=bool)}
    write_csv(tmp_path / "a.parquet", cols)
    schema = pq.read_schema(tmp_path / "a.parquet")
    assert schema.field("n").type == pa.int64() and schema.field("flag").type == pa.int64()
    back = read_csv(tmp_path / "a.parquet")
    np.testing.assert_array_equal(back["t"], cols["t"])
    np.testing.assert_array_equal(back["flag"], [1, 0, 1, 1, 0])


def test_csv_and_parquet_read_the_same(tmp_path):
    rng = np.random.default_rng(3)
    cols = {"x": rng.normal(size=100), "y": rng.integers(-9, 9, 100)}
    write_csv(tmp_path / "a.csv", cols)
    write_csv(tmp_path / "a.parquet", cols)
    a, b = read_csv(tmp_path / "a.csv"), read_csv(tmp_path / "a.parquet")
    for name in cols:
        np.testing.assert_array_equal(a[name], b[name])


def test_duplicate_header_names_both_columns(tmp_path):
    p = tmp_path / "in.csv"
    p.write_text("t,counts,counts\n0,1,2\n")
    with pytest.raises(InputFileError, match=r"row 1 \(header\), column 3: the name 'counts' is given twice "
                                             r"\(columns 2 and 3\)"):
        read_csv(p, ["counts"])


def test_duplicate_header_in_filter_is_an_error_not_a_guess(tmp_path, capsys):
    src = tmp_path / "in.csv"
    src.write_text("counts,counts\n1,100\n2,200\n")
    out = tmp_path / "out.csv"
    assert cli.main(["filter", str(src), "--column", "counts", "-o", str(out)]) == 2
    assert "given twice" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("column,needle", [
    (pa.array(["1", "2", "x"]), "row 3, column 'v': not a number: 'x'"),
    (pa.array([True, False, True]), "column 'v' holds bool, not numbers"),
    (pa.array([1.0, None, 2.0]), "row 2, column 'v': missing value (empty or nan)"),
])
def test_parquet_wrong_types_and_nulls_are_named(tmp_path, column, needle):
    p = tmp_path / "in.parquet"
    pq.write_table(pa.table({"t": [0.0, 1.0, 2.0], "v": column}), p)
    with pytest.raises((InputFileError, NonFiniteError)) as err:
        read_csv(p, ["v"])
    assert needle in str(err.value) and str(p) in str(err.value)


# (file name, how to write the bad file, the reader, the error, what it must say)
BAD_FILES = {
    "parquet-nonfinite-row": ("in.parquet", lambda p: pq.write_table(pa.table({"v": [0.0, np.inf]}), p),
                              read_csv, NonFiniteError, r"row 2, column 'v'"),
    "not-parquet": ("in.parquet", lambda p: p.write_text("t,v\n0,1\n"),
                    read_header, InputFileError, "not a Parquet file"),
    "csv-extra-cells": ("in.csv", lambda p: p.write_text("t,v\n0,1\n1,2,3\n"),
                        read_table, InputFileError, "row 3: 3 cells, the header has 2"),
}


@pytest.mark.parametrize("case", list(BAD_FILES))
def test_bad_file_is_named(tmp_path, case):
    name, write, read, error, match = BAD_FILES[case]
    p = tmp_path / name
    write(p)
    with pytest.raises(error, match=match):
        read(p)


@pytest.mark.parametrize("n_bad", [0, 1, 4097, 99_999])
def test_bad_cell_found_anywhere_in_a_large_file(tmp_path, n_bad):
    """The vectorised scan after a failed conversion names the exact row."""
    values = np.arange(100_000).astype(str)
    values[n_bad] = "1.2.3"
    p = tmp_path / "big.csv"
    p.write_text("v\n" + "\n".join(values) + "\n")
    with pytest.raises(InputFileError, match=rf"row {n_bad + 2}, column 'v': not a number: '1.2.3'"):
        read_csv(p)


def test_text_columns_stay_text(tmp_path):
    p = tmp_path / "in.csv"
    p.write_text("serial,v\n0012,1\nA7,2\n")
    t = read_table(p, ["serial", "v"], strings=["serial"])
    assert t["serial"].to_pylist() == ["0012", "A7"]


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_every_command_reads_parquet(tmp_path, suffix):
    """fit and apply go through pysig.io, so a Parquet chamber log works as
    the CSV one does."""
    rng = np.random.default_rng(0)
    temp = np.repeat([0.0, 25.0, 50.0, 70.0], 30)
    x = np.round(100 + 2 * temp + 0.01 * temp ** 2 + rng.normal(0, 1, temp.size))
    src = tmp_path / f"run{suffix}"
    write_csv(src, {"temp": temp, "x": x})
    model = tmp_path / "m.json"
    assert cli.main(["fit", str(src), "--temp", "temp", "--columns", "x", "--order", "2", "-o", str(model)]) == 0
    out = tmp_path / f"out{suffix}"
    assert cli.main(["apply", str(src), "--model", str(model), "--temp", "temp", "--columns", "x",
                     "-o", str(out)]) == 0
    assert read_csv(out)["x"].size == temp.size
