"""The weighing chain (limit -> anti-pulse -> Kalman -> stability), running
the C99 core of csrc/ through Cython.

    from .chain import Chain
    filtered, stable = Chain().process(x)       # auto: any sensor, any unit
    filtered, stable = Chain("paper", units_per_kg=1).process(kg)

Each class takes `fixed=True` for the firmware's fixed-point form.  The
pure-Python spec with the same classes is pysig.reference.chain (tests
only); presets and parameter checks are pysig.weigh.presets."""
from ._chain import AntiPulse, Chain, Kalman1, LimitFilter, NoiseEstimator, StabilityDetector  # noqa: F401
from .presets import (  # noqa: F401
    CHAIN_MOTION, CHAIN_NOISE_FLOOR, CHAIN_RAMP, CHAIN_TARED, LIMIT_RESEEDED, PRESETS, WARN_CLAMPED,
    WARN_REJECTED, chain_fixed_params, chain_params)

__all__ = ["Chain", "LimitFilter", "AntiPulse", "Kalman1", "StabilityDetector", "NoiseEstimator", "PRESETS",
           "chain_params", "chain_fixed_params", "WARN_CLAMPED", "WARN_REJECTED",
           "LIMIT_RESEEDED", "CHAIN_MOTION", "CHAIN_TARED", "CHAIN_NOISE_FLOOR", "CHAIN_RAMP"]
