"""The refine library never imports the executable spec (spec):
only tests do, so editing the spec cannot change what ships."""
import ast
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
LIBRARY = sorted((ROOT / "pysig" / "refine").glob("*.py")) + [
    ROOT / "pysig" / "refine" / "_effects.pyx", ROOT / "pysig" / "cli" / "commands" / "refine.py"]


def _imported_modules(path):
    text = path.read_text()
    if path.suffix == ".pyx":      # Cython: read its Python-level import lines only
        text = "\n".join(line for line in text.splitlines()
                         if line.startswith(("import ", "from ")) and " cimport " not in line)
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ImportFrom):
            yield ("." * node.level) + (node.module or "")
            for alias in node.names:
                yield ("." * node.level) + (node.module or "") + "." + alias.name
        elif isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name


def test_no_refine_module_imports_the_reference():
    for path in LIBRARY:
        bad = [m for m in _imported_modules(path) if "reference" in m.split(".")]
        assert not bad, (path.name, bad)


def test_running_the_loop_loads_no_reference_of_the_effects():
    """At run time: the effects' spec (spec.effects) stays out of
    a refine session (other areas' modules answer for their own imports)."""
    code = ("import sys, numpy as np\n"
            "from pysig.refine import loop, effects as fx\n"
            "t = np.arange(400.0); T = 20 + 10 * np.sin(t / 60)\n"
            "loop.refine(fx.FitData(y=2 * T + np.random.default_rng(0).standard_normal(400), t=t, T=T))\n"
            "print('spec.effects' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False", out.stdout
