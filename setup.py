"""Build the Cython extensions: one extension per pysig/*.pyx, each compiled
with the whole C99 core from csrc/ (the same sources the firmware uses)."""
import glob
import os

import numpy
from Cython.Build import cythonize
from setuptools import Extension, setup

HERE = os.path.dirname(os.path.abspath(__file__))
CSRC = sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, "csrc", "*.c")))

extensions = [
    Extension(
        "pysig." + os.path.splitext(os.path.basename(pyx))[0],
        sources=[os.path.relpath(pyx, HERE)] + CSRC,
        include_dirs=["csrc", numpy.get_include()],
        # The host build carries the float path as double so numpy float64
        # flows through unconverted; firmware builds use float (sig_types.h).
        define_macros=[("SIG_REAL_DOUBLE", "1"), ("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")],
        extra_compile_args=["-O2", "-std=c99"],
    )
    for pyx in sorted(glob.glob(os.path.join(HERE, "pysig", "*.pyx")))
]

setup(ext_modules=cythonize(extensions, language_level=3,
                            compiler_directives={"boundscheck": False, "wraparound": False}))
