"""The 8051 chain port compiled for the host, so its bit-exactness with the
portable chain can be tested without the simulator.  It is lab tooling, not
part of the wheel: pyximport builds it on first import (into
bench/lab/build/, beside the other lab build outputs) and the import hook is
removed again, so no other .pyx is ever built this way."""
from pathlib import Path

import pyximport

BUILD_DIR = Path(__file__).resolve().parents[1] / "build" / "pyximport"

_hooks = pyximport.install(build_dir=str(BUILD_DIR), language_level=3, inplace=False)
try:
    from ._chain_mcs51 import GAINS_MAX, ChainMcs51, gain_table  # noqa: E402
finally:
    pyximport.uninstall(*_hooks)

__all__ = ["ChainMcs51", "gain_table", "GAINS_MAX"]
