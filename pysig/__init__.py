"""pysig: signal conditioning for low-power sensor nodes.

A portable C99 core (csrc/) reached through Cython, a pure-Python reference
of every algorithm (pysig.reference), calibration fitting and diagnosis."""
from .errors import (PysigError, InputFileError, NonFiniteError, InsufficientDataError,
                     SaturationError, ModelFileError, RangeError)

__version__ = "0.1.0"
