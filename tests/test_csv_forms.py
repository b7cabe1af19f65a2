"""CSV as people export them, through every command that reads one: a
UTF-8 byte-order mark (Excel's "CSV UTF-8"), ';' (European spreadsheets)
and tab delimiters give the same result as the plain comma file; a forced
--delimiter reads what detection would not."""
import numpy as np
import pytest

from fleet_cases import fleet_rows
from pysig.cli import main
from pysig.io import read_csv, read_header

FORMS = {"bom": ("\ufeff", ","), "semicolon": ("", ";"), "tab": ("", "\t")}


def write_form(path, cols, form):
    bom, sep = FORMS[form] if form else ("", ",")
    names = list(cols)
    text = sep.join(names) + "\n" + "".join(sep.join(str(v) for v in row) + "\n" for row in zip(*cols.values()))
    path.write_text(bom + text, encoding="utf-8")
    return path


def chamber_cols(n_per=15):
    rng = np.random.default_rng(2)
    t = np.repeat([-10.0, 10.0, 30.0, 50.0, 70.0], n_per)
    x = np.round(150 + 2.5 * t + 0.02 * t ** 2 + rng.normal(0, 2, t.size))
    return {"t": np.arange(t.size, dtype=float), "temp": t, "x": x, "ref": np.full(t.size, 150.0)}


def weigh_cols():
    return {"t": np.arange(80) * 0.1, "counts": 1000 + (np.arange(80) % 3) + 500 * (np.arange(80) > 40)}


def masses_cols():
    m = np.repeat([0.0, 1.0, 2.0, 5.0], 3)
    return {"kg": m, "counts": -8000 + 20000 * m + np.tile([-1, 0, 1], 4)}


def fleet_cols():
    serial, temp, y = fleet_rows(n_dev=6, seed=4)
    return {"serial": serial, "temp": temp, "x": y[:, 0]}


COMMANDS = {
    "fit": (chamber_cols, lambda src, out: ["fit", src, "--columns", "x", "--model", "poly:2", "-o", out], "json"),
    "apply": (chamber_cols, None, "csv"),
    "filter": (weigh_cols, lambda src, out: ["filter", src, "--column", "counts", "-o", out], "csv"),
    "filter-in-memory": (weigh_cols, lambda src, out: ["filter", src, "--column", "counts", "--in-memory",
                                                       "-o", out], "csv"),
    "calibrate-scale": (masses_cols, lambda src, out: ["calibrate-scale", src, "-o", out], "json"),
    "refine": (chamber_cols, lambda src, out: ["refine", src, "--time", "t", "--temp", "temp", "--columns", "x",
                                               "--ref", "ref", "--json", out], "json"),
    "fleet-fit": (fleet_cols, lambda src, out: ["fleet-fit", src, "--device", "serial", "--columns", "x",
                                                "--no-plots", "-o", out], "dir"),
}


def run(tmp_path, name, form, capsys):
    make, argv, kind = COMMANDS[name]
    folder = tmp_path / (form or "plain")
    folder.mkdir(exist_ok=True)
    src = write_form(folder / "in.csv", make(), form)
    out = folder / ("out" if kind == "dir" else f"out.{kind}")
    if name == "apply":
        model = tmp_path / "model.json"
        if not model.exists():
            plain = write_form(tmp_path / "plain_fit.csv", chamber_cols(), None)
            assert main(["fit", str(plain), "--columns", "x", "--model", "poly:2", "-o", str(model)]) == 0
        args = ["apply", str(src), "--model", str(model), "-o", str(out)]
    else:
        args = argv(str(src), str(out))
    assert main(args) == 0, capsys.readouterr().err
    capsys.readouterr()
    if kind == "dir":
        return (out / "fleet_summary.csv").read_text()
    if kind == "json":
        import json
        d = json.loads(out.read_text())
        for key in ("checksum", "report", "inputs"):
            d.pop(key, None)
        return d
    return read_csv(out)


@pytest.mark.parametrize("form", sorted(FORMS))
@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_command_reads_bom_semicolon_and_tab_as_the_plain_file(tmp_path, capsys, name, form):
    plain = run(tmp_path, name, None, capsys)
    other = run(tmp_path, name, form, capsys)
    if isinstance(plain, dict) and plain and isinstance(next(iter(plain.values())), np.ndarray):
        assert set(plain) == set(other)
        for k in plain:
            np.testing.assert_array_equal(plain[k], other[k])
    else:
        assert plain == other


def test_a_bom_is_not_part_of_the_first_name(tmp_path):
    src = write_form(tmp_path / "b.csv", {"temp_c": [1.0, 2.0], "x": [3.0, 4.0]}, "bom")
    assert read_header(src) == ["temp_c", "x"]


def test_a_forced_delimiter_reads_what_detection_would_not(tmp_path, capsys):
    """A one-column file whose values hold commas in a ';' file is read
    by detection as ';'; forcing ',' is then the user's choice, obeyed."""
    src = tmp_path / "s.csv"
    src.write_text("t;counts\n0;1000\n1;1001\n2;1002\n")
    out = tmp_path / "o.csv"
    assert main(["filter", str(src), "--column", "counts", "--delimiter", ";", "-o", str(out)]) == 0
    assert list(read_csv(out)["counts"]) == [1000, 1001, 1002]
    assert main(["filter", str(src), "--column", "counts", "--delimiter", ",", "-o", str(out)]) == 2
    assert "missing (columns are: t;counts)" in capsys.readouterr().err
