"""pysig: signal conditioning for low-power sensor nodes.

A portable C99 core (``csrc/``) that runs on the smallest MCUs, the very same
code from Python through Cython, with calibration fitting, diagnosis and the
coefficient image around it.  Each area is a subpackage with its own front
door (``__all__`` and a table of what it offers); they load on first use.

===========  ==================================================================
weigh        the weighing chain, its stages and presets, scale calibration
tcomp        temperature-compensation models: fit, load, apply, image, C header
fleet        many devices at once: batched fits, screening, per-device images
store        the coefficient image (sections, CRC, A/B sequence, device id)
refine       the residual loop: find the effect a model lacks, before / after
sim          simulators: load cell, thermal chamber
io           CSV and Parquet in and out (pyarrow), JSON model files
io_stream    chunked reading and atomic chunked writing of large files
lsq          the one least-squares solver every calibration uses
status       the C core's status codes and warning bits
errors       the named exceptions (also here at the top level)
===========  ==================================================================
"""
import importlib

from .errors import (InputFileError, InsufficientDataError, ModelFileError, NonFiniteError, OutputFileError,
                     PysigError, RangeError, SaturationError)

__version__ = "0.1.0"

_AREAS = ("weigh", "tcomp", "fleet", "store", "refine", "sim", "io", "io_stream", "lsq", "status", "errors")

__all__ = ["__version__", *_AREAS, "PysigError", "InputFileError", "NonFiniteError", "InsufficientDataError",
           "SaturationError", "ModelFileError", "RangeError", "OutputFileError"]


def __getattr__(name):
    # Areas load on first use, so `import pysig` stays cheap and the CLI's
    # filter command never pulls in statsmodels or matplotlib.
    if name in _AREAS:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'pysig' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_AREAS))
