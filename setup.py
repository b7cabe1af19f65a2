"""Build the Cython extensions.  The C99 core (csrc/<area>/*.c, the same
sources the firmware uses) is built once, by the project's CMakeLists.txt,
as the static library sigcore that every extension (pysig/<area>/_*.pyx)
links: which sources make the core, its C standard and its warnings are
stated there and nowhere else."""
import glob
import os
import shutil
import subprocess

import numpy
from Cython.Build import cythonize
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
CSRC_INCLUDE = os.path.join("csrc", "include")
PUBLIC_HEADERS = sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, CSRC_INCLUDE, "*.h")))
# The host build carries the float path as double so numpy float64 flows
# through unconverted; firmware builds use float (sig_types.h).  The
# extensions must see the same sig_real as the library they link, so both
# take it from here.
REAL_DOUBLE = True
REAL_MACROS = [("SIG_REAL_DOUBLE", "1")] if REAL_DOUBLE else []
CFLAGS = ["-O2", "-std=c99", "-fPIC"]
CORE_CMAKE_OPTIONS = [
    "-DCMAKE_BUILD_TYPE=Release",
    "-DCMAKE_C_FLAGS_RELEASE=-O2",             # the optimisation the extensions use
    "-DCMAKE_POSITION_INDEPENDENT_CODE=ON",    # linked into shared extension modules
    f"-DSIG_REAL_DOUBLE={'ON' if REAL_DOUBLE else 'OFF'}",
    "-DSIG_BUILD_TESTS=OFF",
    "-DSIG_BUILD_FUZZ=OFF",
    # A new compiler's new warning must not stop a user's install; the
    # warning-free build with -Werror is checked by tests/test_cmake.py.
    "-DSIG_WERROR=OFF",
]


def find_tool(name):
    """A build tool on PATH, else the binary inside its PyPI wheel (the
    `cmake` and `ninja` packages the isolated build environment installs)."""
    path = shutil.which(name)
    if path:
        return path
    try:
        module = __import__(name)
    except ImportError:
        return None
    bin_dir = getattr(module, "CMAKE_BIN_DIR", None) or getattr(module, "BIN_DIR", None)
    path = bin_dir and os.path.join(bin_dir, name)
    return path if path and os.path.exists(path) else None


def stale_cmake_cache(build_dir, cmake):
    """True when build_dir's CMake cache was made by another cmake, or names
    a build tool that no longer exists."""
    cache = os.path.join(build_dir, "CMakeCache.txt")
    if not os.path.exists(cache):
        return False
    entries = {}
    with open(cache, encoding="utf-8", errors="replace") as fh:
        for line in fh:
            key, sep, value = line.rstrip("\n").partition("=")
            if sep and ":" in key:
                entries[key.split(":", 1)[0]] = value
    command = entries.get("CMAKE_COMMAND", "")
    make = entries.get("CMAKE_MAKE_PROGRAM", "")
    return (os.path.realpath(command) != os.path.realpath(cmake)
            or (os.path.isabs(make) and not os.path.exists(make)))


class build_ext_with_core(build_ext):
    """build_ext that first builds sigcore with CMake (the same build a
    firmware project uses) and links every extension against it."""

    def run(self):
        library = self.build_core()
        for ext in self.extensions:
            ext.library_dirs = [*ext.library_dirs, os.path.dirname(library)]
            # An extension must rebuild when the core or a header it
            # compiles against changes (struct layouts), not only when its
            # own .pyx does.
            ext.depends = [*ext.depends, library, *PUBLIC_HEADERS]
        super().run()

    def build_core(self):
        cmake = find_tool("cmake")
        if cmake is None:
            raise RuntimeError("building pysig needs CMake >= 3.16 for its C core: "
                               "`python3 -m pip install cmake`, or your system's cmake package")
        build_dir = os.path.abspath(os.path.join(self.build_temp, "sigcore"))
        lib_dir = os.path.join(build_dir, "lib")
        configure = [cmake, "-S", HERE, "-B", build_dir, f"-DCMAKE_ARCHIVE_OUTPUT_DIRECTORY={lib_dir}",
                     *CORE_CMAKE_OPTIONS]
        ninja = find_tool("ninja")
        if stale_cmake_cache(build_dir, cmake):
            # A rebuild after `git pull` or a second `pip wheel` reuses
            # build/temp*: its cache may name the cmake and ninja of an
            # isolated build environment pip has since deleted.
            shutil.rmtree(build_dir)
        # The generator is chosen once per build directory (CMake refuses a change).
        if ninja and not os.path.exists(os.path.join(build_dir, "CMakeCache.txt")):
            configure += ["-G", "Ninja", f"-DCMAKE_MAKE_PROGRAM={ninja}"]
        subprocess.run(configure, check=True)
        subprocess.run([cmake, "--build", build_dir, "--parallel"], check=True)
        library = os.path.join(lib_dir, "libsigcore.a")
        if not os.path.exists(library):
            raise RuntimeError(f"CMake built no {library}")
        return library


def module_name(pyx):
    return os.path.splitext(os.path.relpath(pyx, HERE))[0].replace(os.sep, ".")


extensions = [
    Extension(
        module_name(pyx),
        sources=[os.path.relpath(pyx, HERE)],
        include_dirs=[CSRC_INCLUDE, numpy.get_include()],
        libraries=["sigcore"],
        define_macros=REAL_MACROS + [("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")],
        extra_compile_args=CFLAGS,
    )
    for pyx in sorted(glob.glob(os.path.join(HERE, "pysig", "**", "_*.pyx"), recursive=True))
]

setup(cmdclass={"build_ext": build_ext_with_core},
      ext_modules=cythonize(extensions, language_level=3,
                            compiler_directives={"boundscheck": False, "wraparound": False}))
