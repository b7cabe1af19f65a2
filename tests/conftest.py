"""Shared test helpers.

Tests that need an external tool (a cross compiler, a simulator, clang's
fuzzer runtime) skip on a developer machine that lacks it, but FAIL in CI
(CI=true), where .ci/run installs every tool: a green CI run has really run
them."""
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from hypothesis import strategies as st

from lab.mcu.runner import CSRC, CSRC_INCLUDE, c_source, c_sources  # noqa: F401  (for the tests)

ROOT = Path(__file__).resolve().parent.parent
SHARED_DATA = Path(os.environ.get("PYSIG_SHARED_DATA", ROOT.parent / "shared" / "data"))

# hypothesis strategies of the C core's integer types
I16 = st.integers(-32768, 32767)
I32 = st.integers(-(1 << 31), (1 << 31) - 1)


def draw_int16_rows(data, n_rows, n_axes):
    """An (n_rows, n_axes) int16 array of readings drawn with hypothesis' data()."""
    return np.array([[data.draw(I16) for _ in range(n_axes)] for _ in range(n_rows)],
                    dtype=np.int16)


def require_tool(*names):
    """Return the path of the first tool found; skip (or fail in CI) if none."""
    for name in names:
        path = shutil.which(name)
        if path:
            return path
    msg = f"none of {', '.join(names)} is installed"
    if os.environ.get("CI"):
        pytest.fail(msg + " (CI must install it: see .ci/run)")
    pytest.skip(msg)


def require_target_tools(target):
    """Skip (or fail in CI) unless the compiler and simulator of `target`
    ("msp430", "mcs51" or "avr") are installed."""
    if target == "msp430":
        for t in ("clang-14", "mspdebug"):
            require_tool(t)
        require_tool("ld.lld-14", "ld.lld")
    elif target == "avr":
        for t in ("avr-gcc", "avr-nm", "avr-objdump", "avr-size", "simavr"):
            require_tool(t)
        if not os.path.exists("/usr/lib/avr/include/avr/io.h"):
            msg = "avr-libc is not installed"
            if os.environ.get("CI"):
                pytest.fail(msg + " (CI must install it: see .ci/run)")
            pytest.skip(msg)
    else:
        for t in ("sdcc", "s51"):
            require_tool(t)


def require_shared_data(relpath):
    """A recording from ../shared/data; skip outside the workplace layout, fail in CI."""
    path = SHARED_DATA / relpath
    if not path.exists():
        if os.environ.get("CI"):
            pytest.fail(f"{path} missing in CI")
        pytest.skip(f"{path} not present")
    return path
