"""The Examples sections of the public API's docstrings run, and say what
they show: each listed module's doctests pass (run in an empty temporary
directory, so examples that write files leave nothing behind), and each
listed public object carries a numpydoc docstring with an Examples section.

Modules are listed rather than collected with --doctest-modules so that
the MCU tooling and the plotting code are not imported for nothing."""
import doctest
import importlib

import pytest

DOCTEST_MODULES = [
    "pysig.weigh",
    "pysig.io",
    "pysig.lsq",
    "pysig.weigh._chain",
    "pysig.weigh._calibration",
    "pysig.tcomp._poly_fit",
    "pysig.tcomp._poly_model",
    "pysig.tcomp._quant",
    "lab.studies.pareto",
    "pysig.tcomp._calibration",
    "pysig.tcomp._table_fit",
    "pysig.fleet._fit",
    "pysig.tcomp._tempcode",
    "pysig.status",
    "pysig.store._image",
    "pysig.refine._loop",
    "pysig.sim._loadcell",
    "pysig.sim._chamber",
    "lab.mcu.model_cost",
]

# the public API: each must document itself in numpydoc form with an example
PUBLIC_API = [
    ("pysig.weigh", ["Chain", "LimitFilter", "AntiPulse", "Kalman1", "StabilityDetector", "calibrate"]),
    ("pysig.tcomp", ["fit_model", "load", "image_bytes", "apply", "apply_image", "TempCode"]),
    ("pysig.fleet", ["fit_fleet"]),
    ("pysig.store", ["build_image", "read_image", "find_section"]),
    ("pysig.refine", ["refine"]),
    ("pysig.sim", ["simulate_loadcell", "simulate_chamber"]),
    ("pysig.weigh._calibration", ["calibrate", "noise_sigma"]),
    ("pysig.io", ["read_csv", "write_csv", "atomic_output", "check_time_column"]),
    ("pysig.tcomp._poly_fit", ["fit_tcomp", "cross_validate", "select_order"]),
    ("pysig.tcomp._poly_model", ["TcompModel"]),
    ("pysig.tcomp._quant", ["to_centi", "choose_scaling", "quantize_axis", "quantize_compact"]),
    ("pysig.tcomp._calibration", ["fit_model", "load", "image_bytes", "apply", "apply_image"]),
    ("pysig.tcomp._table_fit", ["fit_pwl"]),
    ("pysig.fleet._fit", ["fit_fleet"]),
    ("pysig.tcomp._tempcode", ["TempCode"]),
    ("pysig.status", ["describe"]),
    ("pysig.store._image", ["build_image", "read_image", "find_section", "offset_poly_payload",
                           "parse_offset_poly", "model_image", "compact_poly_payload",
                           "parse_compact_poly", "compact_image"]),
    ("pysig.refine._loop", ["refine"]),
    ("pysig.sim._loadcell", ["simulate"]),
    ("pysig.sim._chamber", ["simulate"]),
]
RETURN_NOTHING = {"write_csv", "check_time_column"}       # they write or check, and return None


@pytest.mark.parametrize("name", DOCTEST_MODULES)
def test_docstring_examples_run(name, tmp_path, monkeypatch):
    module = importlib.import_module(name)
    monkeypatch.chdir(tmp_path)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    tests = [t for t in finder.find(module, name) if t.examples]
    assert tests, f"{name}: no examples found"
    for test in tests:
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{name}: {result.failed} of {result.attempted} examples failed"


def _public_objects():
    for modname, names in PUBLIC_API:
        for attr in names:
            yield pytest.param(modname, attr, id=f"{modname}.{attr}")


@pytest.mark.parametrize("modname, attr", _public_objects())
def test_public_api_has_numpydoc_with_examples(modname, attr):
    obj = getattr(importlib.import_module(modname), attr)
    doc = obj.__doc__ or ""
    wanted = ["Parameters", "Examples"]
    if not isinstance(obj, type) and attr not in RETURN_NOTHING:   # a class documents its constructor
        wanted.append("Yields" if _has_section(doc, "Yields") else "Returns")
    missing = [s for s in wanted if not _has_section(doc, s)]
    assert not missing, f"{modname}.{attr}: docstring lacks {', '.join(missing)}"


def _has_section(doc, title):
    lines = [line.strip() for line in doc.splitlines()]
    return any(a == title and b == "-" * len(title) for a, b in zip(lines, lines[1:]))


AREAS = ["pysig", "pysig.weigh", "pysig.tcomp", "pysig.fleet", "pysig.store", "pysig.refine", "pysig.sim",
         "pysig.io", "pysig.io_stream", "pysig.lsq", "pysig.status", "pysig.errors"]


@pytest.mark.parametrize("name", AREAS)
def test_each_area_has_a_documented_front_door(name):
    """Each area states its public names in __all__, every one of them
    resolves, and the area's docstring names each (the table a reader
    scans first, scipy.signal style)."""
    module = importlib.import_module(name)
    public = getattr(module, "__all__", None)
    assert public, f"{name} has no __all__"
    assert len(set(public)) == len(public)
    doc = module.__doc__ or ""
    missing_doc = [n for n in public if n.rstrip("_") not in doc and not n.startswith("__")
                   and not n.isupper() and not n.endswith("Error")]
    for n in public:
        getattr(module, n)
    if name in AREAS[:7]:
        assert missing_doc == [], f"{name}'s docstring does not name {missing_doc}"
