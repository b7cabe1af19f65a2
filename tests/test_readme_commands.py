"""Every `pysig` command the README shows runs, so the README cannot drift
from the program: the command table of "Command line" and every line of
every ```sh block, in README order, in one directory (a command that needs
a file gets it from an earlier command, from ../shared/data, or from the
few inputs written here: standard-mass readings, fleet logs and the refine
example's generated record)."""
import re
import shlex
import shutil

import numpy as np
import pytest

from conftest import ROOT, SHARED_DATA, require_shared_data
from fleet_cases import fleet_rows, write_fleet_log
from lab.studies.overlap_cases import roaming_instrument_case
from pysig.cli import main
from pysig.io import write_csv

README = ROOT / "README.md"
MPU = "mpu6000_gyro_offset_vs_temp/mpu6000_sn102_gyro_offset.csv"


def table_commands(text):
    """The first cell of each row of the "## Command line" table."""
    section = text.split("\n## Command line\n", 1)[1].split("\n## ", 1)[0]
    return [m.group(1) for m in re.finditer(r"^\| `(pysig[^`]*)` \|", section, re.M)]


def block_commands(text):
    """Every `pysig ...` command in ```sh blocks: continuation lines joined,
    comments dropped, `a && pysig b` split."""
    out = []
    for block in re.findall(r"^```sh\n(.*?)^```", text, re.S | re.M):
        for line in block.replace("\\\n", " ").splitlines():
            line = line.split(" #", 1)[0].strip()
            for part in line.split("&&"):
                part = part.strip()
                if part.startswith("pysig "):
                    out.append(part)
    return out


def runnable(command):
    """A table cell as a command: optional [..] parts dropped, the first of
    a|b alternatives taken (the README escapes | as \\| inside tables)."""
    command = re.sub(r"\s*\[[^\]]*\]", "", command.replace("\\|", "|"))
    return [word.split("|")[0] for word in shlex.split(command)]


def readme_commands():
    text = README.read_text()
    return [runnable(c) for c in table_commands(text)] + [shlex.split(c) for c in block_commands(text)]


def test_the_readme_shows_the_commands_this_test_runs():
    commands = readme_commands()
    names = {c[1] for c in commands}
    assert {"--version", "demo", "simulate", "filter", "calibrate-scale", "chamber", "fit", "export", "apply",
            "fleet-fit", "refine"} <= names
    assert len(commands) >= 20


def write_inputs(work):
    """The inputs no README command produces."""
    masses = np.repeat([0.0, 0.5, 1.0, 2.0, 5.0], 5)
    rng = np.random.default_rng(0)
    write_csv(work / "masses.csv", {"kg": masses, "counts": np.round(8400 + 41950.0 * masses + rng.normal(0, 3, 25))})
    serial, temp, y = fleet_rows(n_dev=12, seed=3)
    write_fleet_log(work / "fleet.csv", serial, temp, y)
    (work / "chamber_run").mkdir()
    write_fleet_log(work / "chamber_run" / "fleet.csv", serial, temp, y)
    (work / "dataset").mkdir()
    for part in range(2):
        sel = np.array([int(s[-4:]) % 2 == part for s in serial])
        write_fleet_log(work / "dataset" / f"part-{part}.parquet", serial[sel], temp[sel], y[sel])
    _, _, roaming = roaming_instrument_case(0)       # the refine worked example's record
    write_csv(work / "roaming.csv", {"t_s": roaming.t, "temp_c": roaming.T, "offset_mg": roaming.y})


def test_every_readme_command_runs(tmp_path, monkeypatch, capsys):
    require_shared_data(MPU)
    work = tmp_path / "work"
    work.mkdir()
    (tmp_path / "shared").mkdir()
    (tmp_path / "shared" / "data").symlink_to(SHARED_DATA)          # ../shared/data as in the README
    shutil.copy(SHARED_DATA / MPU, work)
    write_inputs(work)
    monkeypatch.chdir(work)
    ran = set()
    for argv in readme_commands():
        key = tuple(argv)
        if key in ran:
            continue
        ran.add(key)
        if argv[1] == "--version":
            with pytest.raises(SystemExit) as stop:
                main(argv[1:])
            assert stop.value.code == 0
            assert capsys.readouterr().out.startswith("pysig ")
            continue
        status = main(argv[1:])
        printed = capsys.readouterr()
        assert status in (0, None), f"{' '.join(argv)} exited {status}: {printed.err}"
