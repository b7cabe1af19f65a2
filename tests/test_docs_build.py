"""The API reference builds from the docstrings without a warning (Sphinx
with numpydoc and autosummary over each area's front door), so a docstring
that breaks its own format fails here, not on a reader's screen."""
import subprocess
import sys

import pytest

from conftest import ROOT


def test_api_reference_builds_warning_free(tmp_path):
    pytest.importorskip("sphinx")
    pytest.importorskip("numpydoc")
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                          "-d", str(tmp_path / "doctrees"), str(ROOT / "docs"), str(tmp_path / "html")],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-4000:]
    page = (tmp_path / "html" / "api" / "generated" / "pysig.tcomp.html").read_text()
    assert "Parameters" in page and "InsufficientDataError" in page      # numpydoc sections rendered
