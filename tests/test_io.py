"""CSV input: every malformed file gives a named error that says where."""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.errors import InputFileError, NonFiniteError
from pysig.io import atomic_output, check_time_column, read_csv, write_csv


def _write(tmp_path, text, name="in.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_reads_requested_columns(tmp_path):
    p = _write(tmp_path, "t,a,b\n0,1.5,2\n1,2.5,3\n")
    cols = read_csv(p, ["b", "t"])
    assert list(cols) == ["b", "t"]
    np.testing.assert_array_equal(cols["b"], [2.0, 3.0])


@pytest.mark.parametrize("text,needle", [
    ("", "empty file"),
    ("\n\n", "empty file"),
    ("t,a\n", "header only"),
    ("t,b\n0,1\n", "missing column 'a'"),
    ("t,a\n0,1\n1,x\n", "row 3, column 'a': not a number: 'x'"),
    ("t,a\n0,1\n1\n", "row 3, column 'a': not a number: ''"),
])
def test_malformed_files_name_the_problem(tmp_path, text, needle):
    p = _write(tmp_path, text)
    with pytest.raises(InputFileError) as err:
        read_csv(p, ["t", "a"])
    assert needle in str(err.value) and str(p) in str(err.value)


@pytest.mark.parametrize("cell", ["nan", "inf", "-inf", "NaN"])
def test_nonfinite_cells_are_named(tmp_path, cell):
    p = _write(tmp_path, f"t,a\n0,1\n1,{cell}\n")
    with pytest.raises(NonFiniteError, match=r"row 3, column 'a'"):
        read_csv(p, ["a"])
    assert math.isnan(read_csv(p, ["a"], allow_nonfinite=True)["a"][1]) or cell.endswith("inf")


def test_missing_file(tmp_path):
    with pytest.raises(InputFileError, match="cannot read"):
        read_csv(tmp_path / "nope.csv")


@pytest.mark.parametrize("t,needle", [([0, 1, 1, 2], "row 4, column 't': duplicate"),
                                      ([0, 2, 1], "row 4, column 't': decreasing")])
def test_time_column_checks(t, needle):
    with pytest.raises(InputFileError, match=needle):
        check_time_column("f.csv", "t", np.array(t, dtype=float))


def test_atomic_output_leaves_nothing_on_failure(tmp_path):
    target = tmp_path / "out.csv"
    with pytest.raises(RuntimeError):
        with atomic_output(target) as fh:
            fh.write("partial")
            raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


@settings(max_examples=100, deadline=None)
@given(st.lists(st.floats(allow_nan=False, allow_infinity=False, width=64), min_size=1, max_size=50))
def test_write_read_round_trip(tmp_path_factory, values):
    p = tmp_path_factory.mktemp("rt") / "x.csv"
    write_csv(p, {"v": np.array(values), "i": np.arange(len(values))})
    back = read_csv(p)
    np.testing.assert_array_equal(back["v"], values)
    np.testing.assert_array_equal(back["i"], np.arange(len(values)))


def test_atomic_output_file_mode_follows_umask(tmp_path):
    """A file written atomically gets the mode open() would give it, not
    mkstemp's private 0600."""
    import os
    old = os.umask(0o022)
    try:
        with atomic_output(tmp_path / "a.txt") as fh:
            fh.write("x")
        os.umask(0o077)
        with atomic_output(tmp_path / "b.txt") as fh:
            fh.write("x")
    finally:
        os.umask(old)
    assert (tmp_path / "a.txt").stat().st_mode & 0o777 == 0o644
    assert (tmp_path / "b.txt").stat().st_mode & 0o777 == 0o600


def test_cli_imports_only_the_requested_command():
    """`pysig filter` must not pay for refine's statsmodels import."""
    import subprocess
    import sys
    code = ("import sys; from pysig import cli; cli.build_parser(cli._requested_command(['filter', 'x.csv']));"
            "print('statsmodels' in sys.modules, 'pysig.cli.commands.filter' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "True"]


def test_unwritable_output_is_a_named_error_and_leaves_nothing(tmp_path):
    from pysig.errors import OutputFileError
    with pytest.raises(OutputFileError, match="nodir.*cannot write"):
        with atomic_output(tmp_path / "nodir" / "a.csv") as fh:
            fh.write("x")
    (tmp_path / "adir").mkdir()
    with pytest.raises(OutputFileError, match="adir: cannot write"):
        with atomic_output(tmp_path / "adir") as fh:
            fh.write("x")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["adir"]
    assert list((tmp_path / "adir").iterdir()) == []


def test_calibrate_scale_with_an_unwritable_header_writes_no_json(tmp_path):
    from pysig import cli
    src = tmp_path / "in.csv"
    src.write_text("kg,counts\n0,120\n10,10130\n20,20118\n30,30127\n")
    out = tmp_path / "cal.json"
    status = cli.main(["calibrate-scale", str(src), "-o", str(out),
                       "--header", str(tmp_path / "nodir" / "cal.h")])
    assert status == 8
    assert not out.exists()
