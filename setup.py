"""Build the Cython extensions.  The C99 core (csrc/<area>/*.c, the same
sources the firmware uses) is compiled once into a static library, sigcore,
which every extension (pysig/<area>/_*.pyx) links."""
import glob
import os

import numpy
from Cython.Build import cythonize
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
CSRC_INCLUDE = os.path.join("csrc", "include")
CORE_SOURCES = sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, "csrc", "*", "*.c")))
# The host build carries the float path as double so numpy float64 flows
# through unconverted; firmware builds use float (sig_types.h).
CORE_MACROS = [("SIG_REAL_DOUBLE", "1")]
CFLAGS = ["-O2", "-std=c99", "-fPIC"]

# Every header is an input of every core object: a header edit rebuilds the core.
CORE_HEADERS = sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, "csrc", "**", "*.h"),
                                                                 recursive=True))
sigcore = ("sigcore", {"sources": CORE_SOURCES, "include_dirs": [CSRC_INCLUDE],
                       "macros": CORE_MACROS, "cflags": CFLAGS, "obj_deps": {"": CORE_HEADERS}})


class build_ext_with_core(build_ext):
    """build_ext that builds the sigcore library first (plain build_ext,
    as run by `build_ext --inplace` and editable installs, does not)."""

    def run(self):
        self.run_command("build_clib")
        # An extension must relink when the core changes, not only when its
        # own .pyx does: the static library is one of its inputs.
        clib = self.get_finalized_command("build_clib")
        core = clib.compiler.library_filename("sigcore", output_dir=clib.build_clib)
        for ext in self.extensions:
            ext.depends = [*ext.depends, core]
        super().run()


def module_name(pyx):
    return os.path.splitext(os.path.relpath(pyx, HERE))[0].replace(os.sep, ".")


extensions = [
    Extension(
        module_name(pyx),
        sources=[os.path.relpath(pyx, HERE)],
        include_dirs=[CSRC_INCLUDE, numpy.get_include()],
        libraries=["sigcore"],
        define_macros=CORE_MACROS + [("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")],
        extra_compile_args=CFLAGS,
    )
    for pyx in sorted(glob.glob(os.path.join(HERE, "pysig", "**", "_*.pyx"), recursive=True))
]

setup(libraries=[sigcore], cmdclass={"build_ext": build_ext_with_core},
      ext_modules=cythonize(extensions, language_level=3,
                            compiler_directives={"boundscheck": False, "wraparound": False}))
