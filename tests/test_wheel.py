"""The wheel holds what users run and nothing of the lab: the library, the
CLI and the compiled extensions; not the executable spec (tests/spec), the
MCU tooling or the studies (bench/lab).  And a second build in the same
clone works (a reinstall after `git pull` reuses build/, whose CMake cache
named the first build's deleted isolated environment)."""
import shutil
import subprocess
import sys
import zipfile

import pytest

from conftest import ROOT

LAB_OR_SPEC = ("spec/", "lab/", "pysig/reference/", "pysig/mcu/", "tests/", "bench/")
STUDIES = ("pareto.py", "orders_study.py", "refine_study.py", "study.py", "weighing_accuracy.py",
           "refine_cases.py")


def clean_clone(dest):
    """The tracked tree as a fresh clone has it (no build outputs)."""
    files = subprocess.run(["git", "ls-files", "-co", "--exclude-standard"], cwd=ROOT, check=True,
                           capture_output=True, text=True).stdout.split("\n")
    for name in filter(None, files):
        src = ROOT / name
        if src.is_file():
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / name)
    return dest


def build_wheel(src, out, *options):
    run = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", *options, "-w", str(out), "."],
                         cwd=src, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    wheels = sorted(out.glob("pysig-*.whl"))
    assert len(wheels) == 1
    return wheels[0]


@pytest.fixture(scope="module")
def wheel_names(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("wheel")
    src = clean_clone(tmp / "clone")
    first = build_wheel(src, tmp / "first")
    # The same clone, its build/ kept: the first build's isolated environment
    # (its cmake and ninja) is gone, as after a `git pull` and reinstall.
    second = build_wheel(src, tmp / "second", "--no-build-isolation")
    with zipfile.ZipFile(first) as a, zipfile.ZipFile(second) as b:
        assert sorted(a.namelist()) == sorted(b.namelist())
        return a.namelist()


def test_wheel_holds_the_library_cli_and_extensions(wheel_names):
    for needed in ("pysig/__init__.py", "pysig/cli/__init__.py", "pysig/weigh/__init__.py",
                   "pysig/tcomp/__init__.py", "pysig/fleet/__init__.py", "pysig/data/hx711_steps_10hz.csv"):
        assert needed in wheel_names
    extensions = [n for n in wheel_names if n.endswith(".so") or n.endswith(".pyd")]
    assert any("weigh/_chain" in n for n in extensions)
    assert len(extensions) >= 8


def test_wheel_holds_no_spec_lab_or_study(wheel_names):
    lab = [n for n in wheel_names if n.startswith(LAB_OR_SPEC) or n.rsplit("/", 1)[-1] in STUDIES]
    assert lab == []
