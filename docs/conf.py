"""Sphinx configuration of pysig's API reference: built from the docstrings
of each area's front door (`__all__`), numpydoc style, warning-free:

    python3 -m sphinx -W -b html docs docs/_build/html
"""
import pysig

project = "pysig"
version = release = pysig.__version__
extensions = ["sphinx.ext.autodoc", "sphinx.ext.autosummary", "numpydoc"]
autosummary_generate = True
autosummary_ignore_module_all = False       # an area's public names are its __all__
autosummary_imported_members = True         # front doors re-export their private modules' names
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
autodoc_default_options = {"members": False}
templates_path = ["_templates"]
exclude_patterns = ["_build", "*.md", "img"]
master_doc = "index"
html_theme = "alabaster"
