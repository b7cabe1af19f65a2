"""`pysig demo`: the chain on the bundled real recording, a table on the
terminal and a picture whose path it prints."""
import importlib.resources
import os
import re
import subprocess
import sys
from pathlib import Path

from pysig.cli import main


def test_bundled_files_are_package_resources():
    data = importlib.resources.files("pysig.data")
    assert (data / "hx711_steps_10hz.csv").is_file()
    licence = (data / "LICENSE.hx711_steps_10hz").read_text()
    assert "MIT License" in licence and "mvsivaselvan" in licence


def test_demo_prints_table_and_writes_picture(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path)]) in (0, None)
    out = capsys.readouterr().out
    for config in ("raw", "paper_chain", "kalman", "recommended"):
        assert re.search(rf"^{config}\s", out, re.M), config
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
