"""`pysig demo`: the chain on the bundled real recording, a table on the
terminal and a picture whose path it prints."""
import importlib.resources
import os
import re
import subprocess
import sys
from pathlib import Path

from pysig.cli import main
from pysig.weigh import analyse_recording, bundled_recording, load_recording


def test_bundled_files_are_package_resources():
    data = importlib.resources.files("pysig.data")
    assert (data / "hx711_steps_10hz.csv").is_file()
    licence = (data / "LICENSE.hx711_steps_10hz").read_text()
    assert "MIT License" in licence and "mvsivaselvan" in licence


def test_demo_prints_table_and_writes_picture(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    # every row of the printed table is the library's result on the bundled recording
    with bundled_recording() as path:
        d = load_recording(path)
    res = analyse_recording(d["t_s"], d["lc1_counts"])
    for config, r in res["rows"].items():
        m = re.search(rf"^{config}\s+(\d+)/(\d+)\s+(\d+)/(\d+)\s+(\S+)\s+([\d.]+)\s+([\d.]+)$", out, re.M)
        assert m, config
        settle = "never" if r["settle_s_max"] is None else f"{r['settle_s_max']:.1f}"
        assert m.groups() == (str(r["glitches_passed"]), str(r["glitches"]), str(r["plateaus_missed"]),
                              str(r["plateaus"]), settle, f"{r['plateau_err_lb_max']:.3f}",
                              f"{r['plateau_noise_lb']:.3f}"), config
    # what the demo shows: the chains settle on every step (the README: 5.3 s and 5.8 s)
    # where the paper's chain and a plain Kalman filter never do
    for config in ("recommended", "auto"):
        assert res["rows"][config]["settle_s_max"] is not None and res["rows"][config]["settle_s_max"] <= 6.0
        assert res["rows"][config]["plateau_noise_lb"] < res["rows"]["raw"]["plateau_noise_lb"]
    for config in ("paper_chain", "kalman"):
        assert res["rows"][config]["settle_s_max"] is None
    cal = re.search(r"on 9 plateaus found automatically .*: ([\d.]+) counts/lb", out)
    assert cal and float(cal.group(1)) == round(res["calibration"].counts_per_unit, 1)
    assert 990 < res["calibration"].counts_per_unit < 1005       # HX711, 128x gain, this load cell
    assert "CIE324-Swing-Project" in out
    m = re.search(r"picture: (.+\.png)$", out, re.M)
    png = Path(m.group(1))
    assert png.parent == tmp_path.resolve()
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the recommended row: no glitch passed, no plateau missed
    rec = re.search(r"^recommended\s+(\d+)/\d+\s+(\d+)/\d+", out, re.M)
    assert rec.groups() == ("0", "0")


def test_demo_default_is_current_directory(tmp_path):
    res = subprocess.run([sys.executable, "-m", "pysig", "demo", "--channel", "lc2"], cwd=tmp_path,
                         capture_output=True, text=True,
                         env={**os.environ, "MPLBACKEND": "Agg",
                              "PYTHONPATH": str(Path(__file__).resolve().parent.parent)})
    assert res.returncode == 0, res.stderr
    assert (tmp_path / "pysig_demo_lc2.png").exists()
    assert str(tmp_path / "pysig_demo_lc2.png") in res.stdout


def test_demo_bad_out_dir(tmp_path, capsys):
    missing = tmp_path / "nope"
    assert main(["demo", "--out", str(missing)]) == 2
    assert "not a directory" in capsys.readouterr().err
    assert not missing.exists()
