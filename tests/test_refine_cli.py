"""`pysig refine` end to end: printed table, JSON report with the required
keys, PNGs; bad input gives the error's exit status and no output file."""
import json

import numpy as np

from pysig.cli import main
from pysig.io import write_csv

from lab.studies.refine_cases import chamber_run


def _write(tmp_path, effect, **kw):
    run = chamber_run(effect, seed=11, **kw)
    path = tmp_path / "in.csv"
    write_csv(path, {"t": run["t"], "temp": run["temp"], "x": run["x"], "ref": run["ref"]})
    return path


def test_refine_cli_reports_and_plots(tmp_path, capsys):
    path = _write(tmp_path, "thermal_lag", constant_field=True)
    report = tmp_path / "r.json"
    plots = tmp_path / "plots"
    rc = main(["refine", str(path), "--time", "t", "--temp", "temp", "--columns", "x",
               "--json", str(report), "--plot", str(plots)])
    assert rc == 0
    out = capsys.readouterr().out
    assert "thermal_lag" in out and "unexplained" in out
    doc = json.loads(report.read_text())
    for key in ("base_rms", "final_rms", "steps", "unexplained"):
        assert key in doc
    step = doc["steps"][0]
    assert step["effect"] == "thermal_lag"
    for key in ("effect", "params", "rms_before", "rms_after", "cv_rms_before", "cv_rms_after"):
        assert key in step
    assert doc["base_rms"] / doc["final_rms"] >= 3.0
    assert doc["unexplained"]["unexplained"] is False
    assert "constant field" in doc["base_model"]["reference"]
    names = sorted(p.name for p in plots.iterdir())
    assert names == ["residual_vs_temperature.png", "residual_vs_thermal_lag.png", "residual_vs_time.png"]
    assert all((plots / n).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for n in names)


def test_refine_cli_with_reference_column(tmp_path):
    path = _write(tmp_path, "nonlinearity")
    report = tmp_path / "r.json"
    assert main(["refine", str(path), "--time", "t", "--temp", "temp", "--columns", "x",
                 "--ref", "ref", "--json", str(report)]) == 0
    doc = json.loads(report.read_text())
    assert [s["effect"] for s in doc["steps"]] == ["nonlinearity"]


def test_refine_cli_bad_input_writes_nothing(tmp_path, capsys):
    path = _write(tmp_path, None, constant_field=True)
    report = tmp_path / "r.json"
    rc = main(["refine", str(path), "--time", "t", "--temp", "nosuch", "--columns", "x",
               "--json", str(report)])
    assert rc == 2
    assert "missing column 'nosuch'" in capsys.readouterr().err
    assert not report.exists()


def test_refine_cli_unsorted_time_is_named(tmp_path, capsys):
    run = chamber_run(None, seed=1, constant_field=True)
    t = run["t"].copy()
    t[[5, 6]] = t[[6, 5]]
    path = tmp_path / "in.csv"
    write_csv(path, {"t": t, "temp": run["temp"], "x": run["x"]})
    assert main(["refine", str(path), "--time", "t", "--temp", "temp", "--columns", "x"]) == 2
    assert "row 8" in capsys.readouterr().err


def test_refine_cli_too_short_is_insufficient_data(tmp_path, capsys):
    path = tmp_path / "in.csv"
    write_csv(path, {"t": np.arange(12.0), "temp": np.linspace(0, 10, 12), "x": np.arange(12.0)})
    assert main(["refine", str(path), "--time", "t", "--temp", "temp", "--columns", "x"]) == 4
    assert "usable samples" in capsys.readouterr().err


def test_refine_cli_step_is_unexplained_not_named(tmp_path, capsys):
    path = _write(tmp_path, "step")
    report = tmp_path / "r.json"
    assert main(["refine", str(path), "--time", "t", "--temp", "temp", "--columns", "x",
                 "--ref", "ref", "--json", str(report)]) == 0
    out = capsys.readouterr().out
    # the step is left unexplained and no physical effect is named for it; the
    # nuisance drift takes what a line in time can, on its own line
    assert "unexplained: residual" in out, out
    assert "drift in time (nuisance, not in the device correction)" in out, out
    doc = json.loads(report.read_text())
    assert doc["effects_found"] == [] and doc["unexplained"]["unexplained"] is True


def test_a_p_value_that_underflows_prints_as_a_bound_not_zero():
    from pysig.cli.commands.refine import _p_text
    assert _p_text(0.0) == "< 1e-16"
    assert _p_text(3e-20) == "< 1e-16"
    assert _p_text(0.027) == "0.027"
    assert _p_text(2e-6) == "2e-06"
