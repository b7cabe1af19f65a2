"""What ships stays apart from the lab: the library never imports the
executable spec (tests/spec) or the lab tooling (bench/lab), so editing
either cannot silently change what a user runs, and no two library modules
import each other, even through an import hidden inside a function.  Checked at run time on the CLI's hot path (`pysig filter`
under `python -X importtime`) and statically over every library source."""
import re
import subprocess
import sys
from pathlib import Path

from conftest import ROOT

IMPORT_OF_REFERENCE = re.compile(r"^\s*(from\s+(spec|lab)\b|import\s+(spec|lab)\b)", re.MULTILINE)


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
    found = ["from spec import chain as _ref", "from spec.chain import X",
             "from spec import pwl", "import spec.chain", "from lab.mcu import runner",
             "    from spec.chain import chain_params", "    import lab.studies.pareto"]
    for line in found:
        assert IMPORT_OF_REFERENCE.search(line), line
    for line in ["# compared with spec in the tests", "from .references import x", "from .spec_io import x",
                 "a rotating reference field,", "from pysig.lab import x"]:
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
    spec = [m for m in modules if m == "spec" or m.startswith("spec.")]
    assert spec == [], f"pysig filter imported the executable spec: {spec}"


def library_sources(area=None):
    """Every library source (.py, .pyx, .pxd), or
    only those of one area (a subpackage such as "refine")."""
    top = ROOT / "pysig"
    return [p for ext in ("*.py", "*.pyx", "*.pxd") for p in top.rglob(ext)
            if area is None or p.relative_to(top).parts[0] == area]


def reference_imports(sources):
    """file:line of each import of spec in `sources`."""
    return [f"{p.relative_to(ROOT)}:{p.read_text().count(chr(10), 0, m.start()) + 1}"
            for p in sources for m in IMPORT_OF_REFERENCE.finditer(p.read_text())]


def test_no_library_source_imports_the_reference():
    library = library_sources()
    assert len(library) > 30
    offenders = reference_imports(library)
    assert offenders == [], "library code imports spec: " + ", ".join(offenders)


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


IMPORT_LINE = re.compile(r"^[ \t]*(?:from\s+(\.*[\w.]*)\s+c?import\s+(\([^)]*\)|[^\n#]*)|import\s+([\w.]+))",
                         re.MULTILINE)


def _module_of(path):
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[0] == "bench":
        parts = parts[1:]                   # bench/ is the lab's import root
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts), parts[-1] == "__init__"


def lab_sources():
    return [p for ext in ("*.py", "*.pyx") for p in (ROOT / "bench" / "lab").rglob(ext)
            if "build" not in p.relative_to(ROOT).parts]


def library_import_graph():
    """module -> the library (and lab) modules it imports, at any depth of
    the file (inside functions too), with relative imports resolved."""
    sources = library_sources() + lab_sources()
    modules = {_module_of(p)[0]: p for p in sources}
    graph = {}
    for p in sources:
        name, is_pkg = _module_of(p)
        package = name.split(".") if is_pkg else name.split(".")[:-1]
        edges = set()
        for m in IMPORT_LINE.finditer(p.read_text()):
            source, names, plain = m.groups()
            if plain:
                targets = [plain]
            else:
                dots = len(source) - len(source.lstrip("."))
                base = source.lstrip(".")
                if dots:
                    anchor = package[:len(package) - (dots - 1)]
                    base = ".".join(anchor + ([base] if base else []))
                targets = [base] + [f"{base}.{n.split(' as ')[0].strip()}"
                                    for n in names.strip("() \n").split(",") if n.strip()]
            for t in targets:
                # an area's front door is the package itself: an import of a
                # name from it depends on the package's __init__
                if t in modules and t != name:
                    edges.add(t)
        graph[name] = edges
    return graph


def test_the_import_graph_parser_resolves_relative_imports():
    graph = library_import_graph()
    assert "pysig.errors" in graph["pysig.io"]
    assert "pysig.weigh._chain" in graph["pysig.weigh"]
    assert "lab.mcu.runner" in graph["lab.mcu.model_cost"]


def test_no_import_circle_between_modules():
    """Two modules that import each other (directly or through others) hide
    their contract; an area's front door may import its own modules, so
    edges into a package's __init__ from inside that package are left out."""
    graph = library_import_graph()

    def inside(child, package):
        return child.startswith(package + ".")

    pruned = {m: {t for t in ts if not inside(m, t)} for m, ts in graph.items()}
    circles = []
    state = {}

    def visit(m, stack):
        # iterative depth-first search would do as well; the graph is small
        state[m] = 1
        for t in sorted(pruned.get(m, ())):
            if state.get(t) == 1:
                circles.append(" -> ".join(stack[stack.index(t):] + [t]))
            elif t not in state:
                visit(t, stack + [t])
        state[m] = 2

    for m in sorted(pruned):
        if m not in state:
            visit(m, [m])
    assert circles == []
