"""The executable spec stays out of what ships: the library never imports
pysig.reference (only tests do), so editing the spec cannot silently change
what a user runs.  Checked at run time on the CLI's hot path (`pysig filter`
under `python -X importtime`) and statically over every library source."""
import re
import subprocess
import sys
from pathlib import Path

from conftest import ROOT

IMPORT_OF_REFERENCE = re.compile(r"^\s*(from\s+(pysig|\.+)\.?reference\b|import\s+pysig\.reference\b)",
                                 re.MULTILINE)


def imported_modules(importtime_stderr):
    """Module names from `python -X importtime` output (one per import)."""
    names = []
    for line in importtime_stderr.splitlines():
        if line.startswith("import time:") and "|" in line:
            name = line.rsplit("|", 1)[1].strip()
            if name != "imported package":
                names.append(name)
    return names


def test_imported_modules_parses_importtime_lines():
    err = ("import time: self [us] | cumulative | imported package\n"
           "import time:       120 |        120 |   pysig.errors\n"
           "import time:        80 |        200 | pysig\n")
    assert imported_modules(err) == ["pysig.errors", "pysig"]


def test_the_import_pattern_finds_every_spelling():
    found = ["from ..reference import chain as _ref", "from ...reference.chain import X",
             "from pysig.reference import pwl", "import pysig.reference.chain",
             "    from ..reference.chain import chain_params"]
    for line in found:
        assert IMPORT_OF_REFERENCE.search(line), line
    for line in ["# compared with pysig.reference in the tests", "from .references import x",
                 "a rotating reference field,"]:
        assert not IMPORT_OF_REFERENCE.search(line), line


def test_filter_command_imports_no_reference_module(tmp_path):
    src = tmp_path / "in.csv"
    src.write_text("time,counts\n" + "".join(f"{i / 10:.1f},{1000 + (i % 3)}\n" for i in range(40)))
    out = tmp_path / "out.csv"
    run = subprocess.run([sys.executable, "-X", "importtime", "-m", "pysig", "filter", str(src),
                          "--column", "counts", "-o", str(out)],
                         cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    modules = imported_modules(run.stderr)
    assert "pysig.weigh._chain" in modules          # the filter really ran through the C chain
    assert out.exists()
    spec = [m for m in modules if m == "pysig.reference" or m.startswith("pysig.reference.")]
    assert spec == [], f"pysig filter imported the executable spec: {spec}"


def library_sources(area=None):
    """Every library source (.py, .pyx, .pxd) outside pysig/reference, or
    only those of one area (a subpackage such as "refine")."""
    top = ROOT / "pysig"
    return [p for ext in ("*.py", "*.pyx", "*.pxd") for p in top.rglob(ext)
            if "reference" not in p.relative_to(top).parts
            and (area is None or p.relative_to(top).parts[0] == area)]


def reference_imports(sources):
    """file:line of each import of pysig.reference in `sources`."""
    return [f"{p.relative_to(ROOT)}:{p.read_text().count(chr(10), 0, m.start()) + 1}"
            for p in sources for m in IMPORT_OF_REFERENCE.finditer(p.read_text())]


def test_no_library_source_imports_the_reference():
    library = library_sources()
    assert len(library) > 30
    offenders = reference_imports(library)
    assert offenders == [], "library code imports pysig.reference: " + ", ".join(offenders)


def _sources(folder, *patterns):
    return [p for pattern in patterns for p in (ROOT / folder).rglob(pattern)
            if "build" not in p.relative_to(ROOT).parts]


def test_tests_and_benches_import_the_package_only():
    """Tests never load bench scripts, benches never load test helpers, and
    neither edits the module search path: both run against the installed package."""
    this = Path(__file__).resolve()
    tests = [p for p in _sources("tests", "*.py") if p.resolve() != this]
    benches = _sources("bench", "*.py")
    assert tests and benches
    loads_bench = re.compile(r"^\s*(from\s+bench\b|import\s+bench\b)|spec_from_file_location",
                             re.MULTILINE)
    loads_tests = re.compile(r"^\s*(from\s+(conftest|tests)\b|import\s+(conftest|tests)\b)",
                             re.MULTILINE)
    edits_path = re.compile(r"\bsys\.path\b")
    found = [f"{p.relative_to(ROOT)}: loads a bench script" for p in tests
             if loads_bench.search(p.read_text())]
    found += [f"{p.relative_to(ROOT)}: loads a test helper" for p in benches
              if loads_tests.search(p.read_text())]
    found += [f"{p.relative_to(ROOT)}: edits the module search path" for p in tests + benches
              if edits_path.search(p.read_text())]
    assert found == []
