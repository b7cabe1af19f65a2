"""Named exceptions: each says what is wrong and where.

Every error pysig raises for bad input derives from PysigError, and the CLI
maps each class to its own exit status (see pysig/cli/__init__.py)."""

__all__ = ["PysigError", "InputFileError", "NonFiniteError", "InsufficientDataError", "SaturationError",
           "ModelFileError", "RangeError", "OutputFileError"]


class PysigError(Exception):
    """Base class of every error pysig raises on purpose."""
    exit_status = 2


class InputFileError(PysigError, ValueError):
    """A CSV input is unreadable: empty, header only, missing column,
    non-numeric cell, duplicate or unsorted time."""
    exit_status = 2


class NonFiniteError(PysigError, ValueError):
    """NaN or inf where a finite number is needed."""
    exit_status = 3


class InsufficientDataError(PysigError, ValueError):
    """Too few samples or distinct temperatures for what was asked
    (for example a polynomial order above distinct temperatures - 1)."""
    exit_status = 4


class SaturationError(PysigError, ValueError):
    """ADC codes at the converter's rails: the true value is unknown."""
    exit_status = 5


class ModelFileError(PysigError, ValueError):
    """A model file or coefficient image is corrupt, truncated, of the wrong
    version, or fails its CRC."""
    exit_status = 6


class RangeError(PysigError, ValueError):
    """A parameter or temperature outside the range it is valid for."""
    exit_status = 7


class OutputFileError(PysigError, OSError):
    """An output file cannot be written (missing directory, no permission,
    a directory in the way); nothing is left behind."""
    exit_status = 8
