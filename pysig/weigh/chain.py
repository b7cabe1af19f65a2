"""The weighing chain (limit -> anti-pulse -> Kalman -> stability), running
the C99 core of csrc/ through Cython.

    from .chain import Chain
    filtered, stable = Chain().process(counts)                 # recommended
    filtered, stable = Chain("paper", units_per_kg=1).process(kg)

Each class takes `fixed=True` for the firmware's fixed-point form.  The
pure-Python twin with the same classes is pysig.reference.chain."""
from ._chain import AntiPulse, Chain, Kalman1, LimitFilter, StabilityDetector  # noqa: F401
from ..reference.chain import (  # noqa: F401
    CHAIN_MOTION, CHAIN_TARED, LIMIT_RESEEDED, PRESETS, WARN_CLAMPED, WARN_REJECTED,
    chain_fixed_params, chain_params)

__all__ = ["Chain", "LimitFilter", "AntiPulse", "Kalman1", "StabilityDetector", "PRESETS",
           "chain_params", "chain_fixed_params", "WARN_CLAMPED", "WARN_REJECTED",
           "LIMIT_RESEEDED", "CHAIN_MOTION", "CHAIN_TARED"]
