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
    "pysig.io",
    "pysig.lsq",
    "pysig.weigh._chain",
    "pysig.weigh.scale",
    "pysig.tcomp.fit",
    "pysig.tcomp.model",
    "pysig.tcomp.quant",
    "pysig.tcomp.pareto",
    "pysig.tcomp.tmodel",
    "pysig.tcomp.pwl",
    "pysig.tcomp.fleet",
    "pysig.tcomp.tempcode",
    "pysig.status",
    "pysig.store.image",
    "pysig.refine.loop",
    "pysig.sim.loadcell",
    "pysig.sim.chamber",
    "pysig.mcu.model_cost",
]

# the public API: each must document itself in numpydoc form with an example
PUBLIC_API = [
    ("pysig.weigh.chain", ["Chain", "LimitFilter", "AntiPulse", "Kalman1", "StabilityDetector"]),
    ("pysig.weigh.scale", ["calibrate", "noise_sigma"]),
    ("pysig.io", ["read_csv", "write_csv", "atomic_output", "check_time_column"]),
    ("pysig.tcomp.fit", ["fit_tcomp", "cross_validate", "select_order"]),
    ("pysig.tcomp.model", ["TcompModel"]),
    ("pysig.tcomp.quant", ["to_centi", "choose_scaling", "quantize_axis", "quantize_compact"]),
    ("pysig.tcomp.tmodel", ["fit_model", "load", "image_bytes", "apply", "apply_image"]),
    ("pysig.tcomp.pwl", ["fit_pwl"]),
    ("pysig.tcomp.fleet", ["fit_fleet"]),
    ("pysig.tcomp.tempcode", ["TempCode"]),
    ("pysig.status", ["describe"]),
    ("pysig.store.image", ["build_image", "read_image", "find_section", "offset_poly_payload",
                           "parse_offset_poly", "model_image", "compact_poly_payload",
                           "parse_compact_poly", "compact_image"]),
    ("pysig.refine.loop", ["refine"]),
    ("pysig.sim.loadcell", ["simulate"]),
    ("pysig.sim.chamber", ["simulate"]),
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
