"""The weighing chain's presets and parameter checks: what the library runs
(pysig.weigh builds the C chain from these).

Presets are in kg (variances in kg^2) with a `units_per_kg` scale, except
the default, "auto", which has no unit: the chain measures the noise sigma
on the fly and every threshold follows it (csrc/include/sig_chain.h).
The pure-Python spec in spec.chain states the same rules; the
tests prove the two agree.
"""
import math

import numpy as np

from ..errors import RangeError
from ..status import Status, Warn

# ---- status codes (csrc/include/sig_status.h through pysig.status) ---------
OK = int(Status.OK)
WARN_CLAMPED = int(Warn.WARN_CLAMPED)
WARN_REJECTED = int(Warn.WARN_REJECTED)
LIMIT_RESEEDED = int(Warn.LIMIT_RESEEDED)
CHAIN_MOTION = int(Warn.CHAIN_MOTION)
CHAIN_TARED = int(Warn.CHAIN_TARED)
CHAIN_NOISE_FLOOR = int(Warn.CHAIN_NOISE_FLOOR)
CHAIN_RAMP = int(Warn.CHAIN_RAMP)
ERR_NONFINITE = int(Status.ERR_NONFINITE)

INT32_MIN, INT32_MAX = -(1 << 31), (1 << 31) - 1
CODE_MAX = (1 << 24) - 1          # fixed-form input range, sig_antipulse.h
WINDOW_MAX = 32
Q30 = 1 << 30
Q_MAX_Q30 = 1 << 30               # Q/R <= 1
P0_MAX_Q16 = 1 << 30              # P0/R <= 16384

LB_PER_KG = 1 / 0.45359237
AUTO = "auto"

# Presets.  Every value is in kg (variances in kg^2); `units_per_kg` is the
# default scale of the signal the preset expects.
#
# Thresholds from the noise.  A0 and motion_band may be "auto": they are then
# derived from R, the variance of one reading (in signal units, after the
# scale), so that they follow the sensor they are used on:
#     A0          = A0_sigmas * sqrt(R)                    (sigmas of one reading)
#     motion_band = motion_sigmas * sqrt(R / (window - 2))  (sigmas of the window mean)
# A number given for A0 or motion_band (preset or override) is used as is, in
# kg.  The firmware's C chain takes the resulting numbers (sig_chain_params_*).
# R is the sensor's measured noise: a scale with another cell or ADC passes
# its own R (for example from pysig.weigh._calibration.noise_sigma on a still record)
# and the thresholds follow.
PRESETS = {
    # The weighing paper exactly: Q, R, x0, P0, N as published.  A0 is not given in
    # the weighing paper: 2 kg, just above its largest raw reading error (1.86 kg at
    # 30 kg), so every reading the weighing paper reports passes and larger pulses are
    # cut.  The stability step (not given either) is 0.01 kg, one scale
    # division of a 50 kg / 5000 e scale; count 1 as in the weighing paper.
    "paper": dict(A0=2.0, window=12, Q=1e-7, R=0.05, x0=1.0, P0=10.0, seed_first=False,
                  stable_step=0.01, stable_count=1, lockout_n=0,
                  motion_band=0.0, motion_count=1, zero_band=0.0, zero_rate=0.0,
                  A0_sigmas=6.0, motion_sigmas=4.0, noise_auto=False, units_per_kg=1.0),
    # The weighing paper's chain and parameters (A0 2 kg included) plus the fixes
    # beyond the weighing paper: the lock-out fix after 5 rejections on one side (3
    # happen by chance when A0 is under 2 sigma of a reading: spurious
    # re-seeds) and motion-aware settling with the band at 4 sigma of the
    # window mean from R, twice in a row.
    "adaptive": dict(A0=2.0, window=12, Q=1e-7, R=0.05, x0=1.0, P0=10.0, seed_first=False,
                     stable_step=0.01, stable_count=1, lockout_n=5,
                     motion_band="auto", motion_count=2, zero_band=0.0, zero_rate=0.0,
                     A0_sigmas=6.0, motion_sigmas=4.0, noise_auto=False, units_per_kg=1.0),
    # The default everywhere.  Tuned on the real HX711 step recording
    # (../shared/data/hx711_steps_10hz: ~1000 counts/lb, ~70 counts noise),
    # so its default scale is HX711 counts at 1000 counts per lb and its R is
    # that recording's (0.032 kg ~ 70 counts per reading).  Q/R = 1e-3 lets
    # the estimate forget the last swing of a load change within ~3 s (the
    # weighing paper's 2e-6 remembers it for ~70 s); the Kalman filter starts from the
    # first sample; A0 at 6 sigma of a reading and the lock-out fix after 3
    # rejections on one side; motion mode restarts window and P when the
    # window mean leaves the estimate by more than 4 sigma of the mean twice
    # in a row; stable after 5 steps within 4 g; zero tracking within 0.05 kg
    # of zero at 0.5 g per sample.
    "recommended": dict(A0="auto", window=12, Q=1e-6, R=1e-3, x0=0.0, P0=10.0, seed_first=True,
                        stable_step=0.004, stable_count=5, lockout_n=3,
                        motion_band="auto", motion_count=2, zero_band=0.05, zero_rate=0.0005,
                        A0_sigmas=6.0, motion_sigmas=4.0, noise_auto=False,
                        units_per_kg=1000.0 * LB_PER_KG),
    # The default everywhere: no sensor constant, no unit.  The chain
    # measures the noise sigma on the fly (NoiseEstimator) and A0, the
    # motion band, the stability step and the zero-tracking band and rate
    # follow it (noise_thresholds); R "auto".  The Kalman filter is set by
    # ratios only: Q and P0 here are Q/R and P0/R.  An explicit R (signal
    # units squared) fixes sigma = sqrt(R) instead of measuring it.  The
    # firmware builds the same chain with sig_chain_params_auto_f/_q
    # (csrc/weigh/sig_chain_auto.c); tests/test_chain_auto_params.py keeps
    # these numbers equal to the C constructors'.
    "auto": dict(A0=AUTO, window=12, Q=1e-3, R=AUTO, x0=0.0, P0=10.0, seed_first=True,
                 stable_step=AUTO, stable_count=5, lockout_n=3,
                 motion_band=AUTO, motion_count=2, zero_band=AUTO, zero_rate=AUTO,
                 A0_sigmas=6.0, motion_sigmas=4.0, noise_auto=True, units_per_kg=1.0),
}
PARAM_NAMES = tuple(k for k in PRESETS["paper"] if k != "units_per_kg")
_COUNTS = ("window", "stable_count", "lockout_n", "motion_count")
_DERIVED = ("A0", "motion_band")         # may be AUTO: from R (see above)
_NOISE_DERIVED = ("A0", "motion_band", "stable_step", "zero_band", "zero_rate")   # auto preset


def _check(cond, name, value, what):
    if not cond:
        raise RangeError(f"parameter {name}={value!r}: {what}")


def _finite(name, value):
    _check(isinstance(value, (int, float, np.integer, np.floating)) and math.isfinite(value),
           name, value, "must be a finite number")


def chain_params(preset="recommended", units_per_kg=None, **overrides):
    """Parameters of a Chain in signal units (floats), from a preset in kg,
    the scale and overrides (also in kg).  A0 and motion_band "auto" are
    derived from R in signal units (see PRESETS).  Raises RangeError naming
    the bad parameter."""
    if preset not in PRESETS:
        raise RangeError(f"unknown preset {preset!r} (choose from {', '.join(PRESETS)})")
    p = dict(PRESETS[preset])
    for k, v in overrides.items():
        if k not in p:
            raise RangeError(f"unknown chain parameter {k!r} (known: {', '.join(p)})")
        if v is not None:
            p[k] = v
    if units_per_kg is not None:
        p["units_per_kg"] = units_per_kg
    s = p.pop("units_per_kg")
    _finite("units_per_kg", s)
    _check(s > 0, "units_per_kg", s, "must be > 0")
    for k in _COUNTS:
        v = p[k]
        _check(float(v) == int(v), k, v, "must be an integer")
        p[k] = int(v)
    p["seed_first"] = bool(p["seed_first"])
    if PRESETS[preset]["noise_auto"]:
        return _noise_params(p, s)
    auto = {k for k in _DERIVED if isinstance(p[k], str)}
    for k in auto:
        _check(p[k] == AUTO, k, p[k], f"must be a number (kg) or {AUTO!r}")
    for k in ("A0", "Q", "R", "P0", "x0", "stable_step", "motion_band", "zero_band", "zero_rate",
              "A0_sigmas", "motion_sigmas"):
        if k not in auto:
            _finite(k, p[k])
    if "A0" not in auto:
        _check(p["A0"] > 0, "A0", p["A0"], "must be > 0")
    _check(p["A0_sigmas"] > 0, "A0_sigmas", p["A0_sigmas"], "must be > 0")
    _check(3 <= p["window"] <= WINDOW_MAX, "window", p["window"], f"must be in 3..{WINDOW_MAX}")
    _check(p["R"] > 0, "R", p["R"], "must be > 0")
    for k in ("Q", "P0", "stable_step", "motion_band", "zero_band", "zero_rate", "motion_sigmas"):
        if k not in auto:
            _check(p[k] >= 0, k, p[k], "must be >= 0")
    for k, lo in (("stable_count", 1), ("motion_count", 1), ("lockout_n", 0)):
        _check(lo <= p[k] <= 255, k, p[k], f"must be in {lo}..255")
    for k in ("A0", "x0", "stable_step", "motion_band", "zero_band", "zero_rate", "Q", "R", "P0"):
        if k in auto:
            continue
        given = p[k]
        p[k] = float(given) * s * (s if k in ("Q", "R", "P0") else 1.0)
        _check(math.isfinite(p[k]), k, given, f"overflows in signal units (units_per_kg={s!r})")
    p["A0_sigmas"], p["motion_sigmas"] = float(p["A0_sigmas"]), float(p["motion_sigmas"])
    _check_kalman_start(p)
    if "A0" in auto:
        p["A0"] = p["A0_sigmas"] * math.sqrt(p["R"])
        _check(p["A0"] > 0 and math.isfinite(p["A0"]), "A0", AUTO,
               f"A0_sigmas * sqrt(R) = {p['A0']!r} in signal units must be finite and > 0")
    if "motion_band" in auto:
        p["motion_band"] = p["motion_sigmas"] * math.sqrt(p["R"] / (p["window"] - 2))
        _check(math.isfinite(p["motion_band"]), "motion_band", AUTO,
               "motion_sigmas * sqrt(R / (window - 2)) overflows in signal units")
    return p


def _noise_params(p, s):
    """chain_params() of the auto preset: thresholds from the noise sigma,
    measured on the fly (R auto) or sqrt(R) for an R given in kg^2."""
    for k in _NOISE_DERIVED:
        if p[k] != AUTO:
            _finite(k, p[k])
        _check(p[k] == AUTO, k, p[k], "follows the noise in the auto preset: leave it 'auto' "
               "(or choose another preset)")
    for k in ("Q", "P0", "x0"):
        _finite(k, p[k])
        _check(k == "x0" or p[k] >= 0, k, p[k], "must be >= 0")
    _check(3 <= p["window"] <= WINDOW_MAX, "window", p["window"], f"must be in 3..{WINDOW_MAX}")
    for k, lo in (("stable_count", 1), ("motion_count", 1), ("lockout_n", 0)):
        _check(lo <= p[k] <= 255, k, p[k], f"must be in {lo}..255")
    p["x0"] = float(p["x0"]) * s
    if isinstance(p["R"], str):
        _check(p["R"] == AUTO, "R", p["R"], f"must be a number (kg^2) or {AUTO!r}")
        r, p["noise_auto"] = 1.0, True
    else:
        _finite("R", p["R"])
        _check(p["R"] > 0, "R", p["R"], "must be > 0")
        r, p["noise_auto"] = float(p["R"]) * s * s, False
        _check(math.isfinite(r) and r > 0, "R", p["R"], f"out of range in signal units (units_per_kg={s!r})")
    p["Q"], p["P0"], p["R"] = float(p["Q"]) * r, float(p["P0"]) * r, r
    _check(p["seed_first"] or not p["noise_auto"], "seed_first", False,
           "the noise measured on the fly (R 'auto') re-seeds the Kalman filter on the window "
           "mean while settling: it needs seed_first=True")
    _check_kalman_start(p)
    sigma = math.sqrt(r) if not p["noise_auto"] else NOISE_FLOOR_ABS
    (p["A0"], p["motion_band"], p["stable_step"], p["zero_band"],
     p["zero_rate"]) = noise_thresholds(sigma)
    p["A0_sigmas"], p["motion_sigmas"] = float(p["A0_sigmas"]), float(p["motion_sigmas"])
    return p


def _check_kalman_start(p):
    """Without seed_first the estimate starts from x0: the first samples must
    count (P0 >= R, the first gain at least 1/2), else a steady load is
    approached over about R/P0 samples and read wrong meanwhile
    (csrc/include/sig_chain.h states the same rule)."""
    _check(p["seed_first"] or p["P0"] >= p["R"], "P0", p["P0"],
           f"with seed_first=False the Kalman filter starts from x0 and needs P0 >= R "
           f"(R={p['R']!r} in signal units)")


def _round_int32(name, value):
    _check(math.isfinite(value), name, value, "out of the int32 range in fixed point")
    v = round(value)
    _check(INT32_MIN <= v <= INT32_MAX, name, value, "out of the int32 range in fixed point")
    return int(v)


def kalman_fixed_params(Q, R, P0, x0):
    """(q_q30, p0_q16, x0_q7) of the fixed Kalman from signal-unit floats."""
    _check(R > 0, "R", R, "must be > 0")
    # a tiny R makes the ratios overflow to inf, which round() cannot take
    _check(math.isfinite(Q / R * Q30), "Q", Q, "fixed point needs 0 <= Q/R <= 1")
    _check(math.isfinite(P0 / R * 65536), "P0", P0, "fixed point needs 0 <= P0/R <= 16384")
    q = round(Q / R * Q30)
    p0 = round(P0 / R * 65536)
    _check(0 <= q <= Q_MAX_Q30, "Q", Q, "fixed point needs 0 <= Q/R <= 1")
    _check(0 <= p0 <= P0_MAX_Q16, "P0", P0, "fixed point needs 0 <= P0/R <= 16384")
    return int(q), int(p0), _round_int32("x0", x0 * 128)


def chain_fixed_params(p):
    """The sig_chain_params_q fields from chain_params() output."""
    q, p0, x0 = kalman_fixed_params(p["Q"], p["R"], p["P0"], p["x0"])
    common = dict(window=p["window"], q_q30=q, p0_q16=p0, x0_q7=x0, seed_first=p["seed_first"],
                  stable_count=p["stable_count"], lockout_n=p["lockout_n"],
                  motion_count=p["motion_count"], noise_auto=bool(p["noise_auto"]))
    if p["noise_auto"]:       # the thresholds follow the measured noise, from its floor
        a0, band, step, zband, zrate = noise_thresholds(NOISE_FLOOR_Q7, fixed=True)
        return dict(common, a0=a0, stable_step_q7=step, motion_band_q7=band,
                    zero_band_q7=zband, zero_rate_q7=zrate)
    a0 = _round_int32("A0", p["A0"])
    _check(a0 > 0, "A0", p["A0"], "rounds to 0 codes in fixed point")
    return dict(common, a0=a0,
                stable_step_q7=_round_int32("stable_step", p["stable_step"] * 128),
                motion_band_q7=_round_int32("motion_band", p["motion_band"] * 128),
                zero_band_q7=_round_int32("zero_band", p["zero_band"] * 128),
                zero_rate_q7=_round_int32("zero_rate", p["zero_rate"] * 128))



# ---- thresholds from the measured noise (csrc/include/sig_noise.h, sig_chain.h) -----
NOISE_FLOOR_Q7 = 32               # a quarter of one code, Q24.7
NOISE_FLOOR_ABS = 1e-30           # float floor (never below this)


def noise_thresholds(sigma, fixed=False):
    """(a0, motion_band, stable_step, zero_band, zero_rate) from a noise sigma,
    as sig_chain.c derives them in auto mode (fixed: sigma Q24.7 int, a0 in
    codes; float otherwise)."""
    if fixed:
        a0 = max(((sigma << 2) + (sigma << 1) + 64) >> 7, 1)
        return a0, sigma + (sigma >> 1), sigma >> 2, sigma, sigma >> 4
    return 6.0 * sigma, 1.5 * sigma, 0.25 * sigma, sigma, 0.0625 * sigma


# ---- parameter checks of the single stages ------------------------------------
def limit_params(a0, lockout_n, fixed):
    """(a0, lockout_n) for sig_limit_init_*: a0 in codes when fixed."""
    _finite("a0", a0)
    _check(a0 > 0, "a0", a0, "must be > 0")
    _check(0 <= lockout_n <= 255 and int(lockout_n) == lockout_n, "lockout_n", lockout_n,
           "must be an integer in 0..255")
    a = _round_int32("a0", a0) if fixed else float(a0)
    _check(a > 0, "a0", a0, "rounds to 0 codes in fixed point")
    return a, int(lockout_n)


def window_param(window):
    _check(int(window) == window and 3 <= window <= WINDOW_MAX, "window", window,
           f"must be an integer in 3..{WINDOW_MAX}")
    return int(window)


def kalman_params(Q, R, x0, P0):
    """Q, R, x0, P0 as floats, checked (sig_kalman1_init_f's domain)."""
    for name, v in (("Q", Q), ("R", R), ("x0", x0), ("P0", P0)):
        _finite(name, v)
    _check(Q >= 0, "Q", Q, "must be >= 0")
    _check(R > 0, "R", R, "must be > 0")
    _check(P0 >= 0, "P0", P0, "must be >= 0")
    return float(Q), float(R), float(x0), float(P0)


def stable_params(step, count, fixed):
    """(step, count) for sig_stable_init_*: step in Q24.7 when fixed."""
    _finite("step", step)
    _check(step >= 0, "step", step, "must be >= 0")
    _check(int(count) == count and 1 <= count <= 255, "count", count, "must be an integer in 1..255")
    return (_round_int32("step", step * 128) if fixed else float(step)), int(count)


def offset_q7(offset):
    """A tare offset in Q24.7 for sig_chain_set_offset_q."""
    _finite("offset", offset)
    return _round_int32("offset", offset * 128)
