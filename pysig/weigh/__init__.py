"""Weighing: the chain of the weighing paper made to settle fast and follow
real loads, its stages, presets and the scale calibration.

The chain runs the C99 core of ``csrc/weigh`` through Cython; every class
takes ``fixed=True`` for the firmware's fixed-point form (the one spelling
of the numeric form in the public API).

============================  =======================================================
Chain                         limit -> anti-pulse -> Kalman -> stability (+ tare,
                              zero tracking, motion), ``process(x) -> (y, stable)``
LimitFilter, AntiPulse,       each stage alone, the same C as inside the chain
Kalman1, StabilityDetector,
NoiseEstimator
PRESETS                       the named parameter sets (``auto`` is the default)
chain_params,                 the checked float / fixed-point parameters of a preset
chain_fixed_params
calibrate, Calibration,       counts -> mass from standard masses (JSON, C header)
load_calibration
find_plateaus                 the held levels of a recording (for calibration)
plateaus_at_masses            a raw log's still loads matched to the masses put on
first_saturated,              a 24-bit converter's rail codes (never filtered)
saturated_count
analyse_recording,            the chain on a recording of held loads (the demo):
load_recording,               calibration on its plateaus, settle time and plateau
plot_recording,               error per configuration, and its plot; the bundled
bundled_recording,            HX711 recording and its loaded channels
RECORDING_CHANNELS
CODE_MAX                      the largest count magnitude the fixed-point form takes (24 bit)
WARN_*, LIMIT_RESEEDED,       the per-sample flags the chain reports
CHAIN_*
EventCounter                  impulses told from samples of load motion, from the flags
============================  =======================================================

Examples
--------
>>> import numpy as np
>>> from pysig.weigh import Chain
>>> x = np.r_[np.zeros(50), np.full(100, 1000.0)] + np.random.default_rng(0).normal(0, 2, 150)
>>> y, stable = Chain().process(x)
>>> bool(abs(y[-1] - 1000) < 5 and stable[-1])
True
"""
from ._chain import AntiPulse, Chain, Kalman1, LimitFilter, NoiseEstimator, StabilityDetector
from ._presets import (
    CHAIN_MOTION, CHAIN_NOISE_FLOOR, CHAIN_RAMP, CODE_MAX, CHAIN_TARED, LIMIT_RESEEDED, PRESETS, WARN_CLAMPED,
    WARN_REJECTED, chain_fixed_params, chain_params)
from ._calibration import (Calibration, calibrate, find_plateaus, first_saturated, load_calibration,
                           plateaus_at_masses, saturated_count)
from ._events import EventCounter
from ._recording import LOADED as RECORDING_CHANNELS
from ._recording import analyse_loaded as analyse_recording
from ._recording import bundled_csv as bundled_recording
from ._recording import load as load_recording
from ._recording import plot_channel as plot_recording

__all__ = ["Chain", "LimitFilter", "AntiPulse", "Kalman1", "StabilityDetector", "NoiseEstimator", "PRESETS",
           "chain_params", "chain_fixed_params", "calibrate", "Calibration", "load_calibration",
           "find_plateaus", "plateaus_at_masses", "first_saturated", "saturated_count", "analyse_recording", "load_recording",
           "plot_recording", "bundled_recording", "RECORDING_CHANNELS", "CODE_MAX",
           "WARN_CLAMPED", "WARN_REJECTED", "LIMIT_RESEEDED", "CHAIN_MOTION", "CHAIN_TARED", "CHAIN_NOISE_FLOOR", "CHAIN_RAMP",
           "EventCounter"]
