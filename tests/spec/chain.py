"""The weighing chain in plain Python: the executable spec of csrc/weigh/
sig_limit.c, sig_antipulse.c, sig_kalman1.c, sig_stable.c, sig_noise.c and
sig_chain.c.  Imported by tests only; the presets and parameter checks it runs
from are the library's (pysig.weigh._presets).

Read next to the weighing paper: limit filter -> anti-pulse filter -> scalar Kalman
filter -> stability detector.  Every class takes `fixed=False` (floating
point, Python float == C double) or `fixed=True` (the C fixed-point form:
integer ADC codes, Kalman state in Q24.7, gain in Q2.30; computed here with
Python ints so the result is the C result bit for bit).

Units.  The stage classes take parameters and samples in signal units
(ADC codes, or kg).  `Chain` takes the preset's parameters in kg and a
`units_per_kg` scale (signal units per kg), so the same preset serves a kg
signal (units_per_kg=1) and ADC counts.  Q, R and P0 are variances: they
scale with units_per_kg squared.
"""
import math

import numpy as np

from pysig.errors import NonFiniteError, RangeError

# The presets and the parameter rules (kg -> signal units -> the C's fixed-point
# parameters) are configuration, not filter algorithm: the spec runs from the
# library's one parameter set (pysig.weigh._presets) and specifies the stages.
from pysig.weigh._presets import (  # noqa: F401  (re-exported for the tests)
    AUTO, CHAIN_MOTION, CHAIN_NOISE_FLOOR, CHAIN_RAMP, CHAIN_TARED, CODE_MAX, ERR_NONFINITE, INT32_MAX,
    INT32_MIN, LB_PER_KG, LIMIT_RESEEDED, OK, P0_MAX_Q16, PARAM_NAMES, PRESETS, Q30, Q_MAX_Q30,
    WARN_CLAMPED, WARN_REJECTED, WINDOW_MAX, _check, _finite, _round_int32, chain_fixed_params,
    chain_params, kalman_fixed_params)


# ---- fixed-point arithmetic (csrc/include/sig_types.h, sig_antipulse.c, sig_kalman1.c) ----------
def sat32(v):
    return INT32_MIN if v < INT32_MIN else INT32_MAX if v > INT32_MAX else v


def mul_q30_u(a, b):
    """floor((a*b + 2^29) / 2^30) truncated to 32 bits (sig_mul_q30_u32)."""
    return ((a * b + (1 << 29)) >> 30) & 0xFFFFFFFF


def mul_q30_gain(a, k):
    """sign(a) * round-half-up(|a| * k / 2^30) (sig_mul_q30_gain)."""
    r = mul_q30_u(abs(a), k)
    return r if a >= 0 else (INT32_MIN if r >= 1 << 31 else -r)


def code_of(x):
    """A float sample as the fixed form's int32 code (nearest, ties to even)."""
    if not math.isfinite(x):
        raise NonFiniteError(f"non-finite sample {x!r}: the fixed form takes ADC codes")
    return sat32(int(round(x)))


def clamp_code(x):
    return max(-CODE_MAX, min(CODE_MAX, x))


# ---- stage 1: limit filter -------------------------------------------------
class LimitFilter:
    """|x - Dc| > A0 -> replaced by Dc.  lockout_n > 0: the lockout_n-th
    successive rejection on one side is accepted and re-seeds Dc."""

    def __init__(self, a0, lockout_n=0, fixed=False):
        _finite("a0", a0)
        _check(a0 > 0, "a0", a0, "must be > 0")
        _check(0 <= lockout_n <= 255 and int(lockout_n) == lockout_n, "lockout_n", lockout_n,
               "must be an integer in 0..255")
        self.fixed = bool(fixed)
        self.a0 = _round_int32("a0", a0) if self.fixed else float(a0)
        _check(self.a0 > 0, "a0", a0, "rounds to 0 codes in fixed point")
        self.lockout_n = int(lockout_n)
        self.reset()

    def reset(self):
        self.Dc, self.run, self.side, self.seeded, self.status = 0, 0, 0, False, OK

    def set_ref(self, dc):
        self.Dc, self.seeded = dc, True

    def accept(self, x):
        """Take x as the reference and end the rejection run (the chain saw a
        load change in the run: a ramp)."""
        self.Dc, self.seeded, self.run, self.side = x, True, 0, 0

    def _step(self, x):
        """One sample in the stage's own numbers; returns (out, status)."""
        if not self.fixed and not math.isfinite(x):
            if not self.seeded:
                return None, ERR_NONFINITE
            return self.Dc, WARN_REJECTED
        if not self.seeded:
            self.Dc, self.seeded, self.run, self.side = x, True, 0, 0
            return x, OK
        d = sat32(x - self.Dc) if self.fixed else x - self.Dc
        if d > self.a0 or d < -self.a0:
            side = 1 if d > 0 else -1
            if side == self.side:
                self.run = min(self.run + 1, 255)
            else:
                self.side, self.run = side, 1
            if self.lockout_n and self.run >= self.lockout_n:
                self.Dc, self.run, self.side = x, 0, 0
                return x, LIMIT_RESEEDED
            return self.Dc, WARN_REJECTED
        self.run, self.side, self.Dc = 0, 0, x
        return x, OK

    def step(self, x):
        out, self.status = self._step(code_of(x) if self.fixed else float(x))
        return float("nan") if out is None else float(out)

    def process(self, x):
        return np.array([self.step(v) for v in np.asarray(x, dtype=float)])


# ---- stage 2: anti-pulse filter --------------------------------------------
class AntiPulse:
    """Mean of the last N samples without one max and one min.  Filling:
    1 sample -> itself, 2 -> their mean, k >= 3 -> trimmed mean of the k.
    Fixed: codes clamped to +-CODE_MAX, round-half-up((sum-max-min)/(k-2)).
    Float: the C keeps a running sum (re-summed in storage order each time
    the write position wraps) and multiplies by 1/(N-2) for a full window;
    this twin does the same operations so the float results agree to the bit."""

    def __init__(self, window=12, fixed=False):
        _check(int(window) == window and 3 <= window <= WINDOW_MAX, "window", window,
               f"must be an integer in 3..{WINDOW_MAX}")
        self.n = int(window)
        self.fixed = bool(fixed)
        self.inv = 1.0 / (self.n - 2)
        self.reset()

    def reset(self):
        self.buf, self.count, self.head, self.status = [0] * self.n, 0, 0, OK
        self.sum = 0.0

    def _step(self, x):
        st = OK
        if self.fixed and abs(x) > CODE_MAX:
            x, st = clamp_code(x), WARN_CLAMPED
        full = self.count == self.n
        old = self.buf[self.head]
        self.buf[self.head] = x
        self.head = (self.head + 1) % self.n
        self.count = min(self.count + 1, self.n)
        held = self.buf[:self.count]
        mx, mn = max(held), min(held)
        if self.fixed:                         # the definition, exactly
            if self.count >= 3:
                total, d = sum(held) - mx - mn, self.count - 2
            else:
                total, d = sum(held), self.count
            return (total + d // 2) // d, st
        self.sum = (self.sum - old) + x if full else self.sum + x
        if self.head == 0 or not math.isfinite(self.sum):
            self.sum = held[0]
            for v in held[1:]:
                self.sum += v
        if self.count == 1:
            return x, st
        if self.count == 2:
            t = self.sum * 0.5
            return (t if math.isfinite(t) else self._safe_mean(held, mx, mn)), st
        t = self.sum - mx - mn
        if not math.isfinite(t):
            return self._safe_mean(held, mx, mn), st
        return (t * self.inv if self.count == self.n else t / (self.count - 2)), st

    def _safe_mean(self, held, mx, mn):
        """Overflow-free trimmed mean: sum of v / d, one max and one min left out."""
        trim = len(held) >= 3
        d = float(len(held) - 2 if trim else len(held))
        skip_mx = skip_mn = trim
        acc = 0.0
        for v in held:
            if skip_mx and v == mx:
                skip_mx = False
                continue
            if skip_mn and v == mn:
                skip_mn = False
                continue
            acc += v / d
        # rounded terms can sum past the largest float; the mean is within [mn, mx]
        return min(max(acc, mn), mx)

    def step(self, x):
        if self.fixed:
            x = code_of(x)
        elif not math.isfinite(x):
            raise NonFiniteError(f"non-finite sample {x!r} (the anti-pulse stage alone takes finite samples)")
        out, self.status = self._step(x if self.fixed else float(x))
        return float(out)

    def process(self, x):
        return np.array([self.step(v) for v in np.asarray(x, dtype=float)])


# ---- stage 3: scalar Kalman filter -----------------------------------------
class Kalman1:
    """A = 1, H = 1: P- = P + Q; K = P-/(P- + R); x += K (z - x); P = R K.
    Fixed: runs on P/R with y = 1/(1 + K + q) by two Newton steps (see
    csrc/include/sig_kalman1.h); samples are codes, x is Q24.7."""

    def __init__(self, Q=1e-7, R=0.05, x0=1.0, P0=10.0, seed_first=False, fixed=False):
        for name, v in (("Q", Q), ("R", R), ("x0", x0), ("P0", P0)):
            _finite(name, v)
        _check(Q >= 0, "Q", Q, "must be >= 0")
        _check(R > 0, "R", R, "must be > 0")
        _check(P0 >= 0, "P0", P0, "must be >= 0")
        self.fixed, self.seed_first = bool(fixed), bool(seed_first)
        self.Q, self.R, self.P0, self.x0 = float(Q), float(R), float(P0), float(x0)
        if self.fixed:
            self.q, self.p0, self.x0_q7 = kalman_fixed_params(Q, R, P0, x0)
            self.y1 = (1 << 46) // (65536 + self.p0 + ((self.q + 8192) >> 14))
        self.reset()

    def reset(self):
        self.seeded, self.status = False, OK
        if self.fixed:
            self.xq, self.innov_q, self.y, self.phase = self.x0_q7, 0, Q30, 0
        else:
            self._x, self._P, self._K, self._innov = self.x0, self.P0, 0.0, 0.0

    def restart(self):
        """P back to P0, x kept (motion-aware settling)."""
        if self.fixed:
            self.phase = 0
        else:
            self._P = self.P0

    @staticmethod
    def _newton(y, d):
        t = mul_q30_u(d, y)
        if t >= 1 << 31:
            return y >> 1
        return mul_q30_u(y, (1 << 31) - t)

    def _step(self, z):
        if not self.seeded:
            self.seeded = True
            if self.seed_first:
                if self.fixed:
                    self.xq = z
                else:
                    self._x = z
        if not self.fixed:
            pm = self._P + self.Q
            den = pm + self.R
            self._K = pm / den if math.isfinite(den) else 1.0 / (1.0 + self.R / pm)
            self._P = self.R * self._K                 # = (1 - K) P-, without the cancellation
            self._innov = z - self._x
            if math.isfinite(self._innov):
                self._x = self._x + self._K * self._innov
            else:                                      # z - x overflowed: same update, other form
                self._x = (1.0 - self._K) * self._x + self._K * z
            return self._x
        if self.phase == 0:
            self.y, self.phase = self.y1, 1
        elif self.phase != 3:
            d = Q30 + (Q30 - self.y) + self.q
            if self.phase == 1:
                half = d >> 1
                yn = 0x60000000 - half if half < 0x50000000 else 0x10000000
            else:
                yn = self.y
            yn = self._newton(self._newton(yn, d), d)
            yn = min(max(yn, 1), Q30)
            self.phase = 3 if (self.phase == 2 and yn == self.y) else 2
            self.y = yn
        self.innov_q = sat32(z - self.xq)
        self.xq = sat32(self.xq + mul_q30_gain(self.innov_q, Q30 - self.y))
        return self.xq

    def step(self, z):
        if self.fixed:
            out = self._step(clamp_code(code_of(z)) * 128) / 128
        else:
            if not math.isfinite(z):
                raise NonFiniteError(f"non-finite sample {z!r} (the Kalman stage alone takes finite samples)")
            out = self._step(float(z))
        return float(out)

    def process(self, z):
        return np.array([self.step(v) for v in np.asarray(z, dtype=float)])

    @property
    def x(self):
        return self.xq / 128 if self.fixed else self._x

    @property
    def K(self):
        return (Q30 - self.y) / Q30 if self.fixed else self._K

    @property
    def P(self):
        if not self.fixed:
            return self._P
        return self.p0 / 65536 * self.R if self.phase == 0 else self.K * self.R

    @property
    def innovation(self):
        return self.innov_q / 128 if self.fixed else self._innov


# ---- stage 4: stability detector -------------------------------------------
class StabilityDetector:
    """Stable when successive outputs differ by <= step for `count` samples."""

    def __init__(self, step=0.01, count=1, fixed=False):
        _finite("step", step)
        _check(step >= 0, "step", step, "must be >= 0")
        _check(int(count) == count and 1 <= count <= 255, "count", count, "must be an integer in 1..255")
        self.fixed = bool(fixed)
        self.step_value = _round_int32("step", step * 128) if self.fixed else float(step)
        self.count = int(count)
        self.reset()

    def reset(self):
        self.prev, self.run, self.has_prev, self.stable = 0, 0, False, False

    def _step(self, x):
        d = sat32(x - self.prev) if self.fixed else x - self.prev
        if self.fixed:
            within = min(abs(d), INT32_MAX) <= self.step_value
        else:
            within = d <= self.step_value and -d <= self.step_value
        if self.has_prev and within:
            self.run = min(self.run + 1, 255)
        else:
            self.run = 0
        self.prev, self.has_prev = x, True
        self.stable = self.run >= self.count
        return self.stable

    def step(self, x):
        if self.fixed:
            if not math.isfinite(x):
                raise NonFiniteError(f"non-finite value {x!r}")
            return self._step(sat32(int(round(x * 128))))
        if not math.isfinite(x):
            raise NonFiniteError(f"non-finite value {x!r} (the stability stage alone takes finite values)")
        return self._step(float(x))

    def process(self, x):
        return np.array([self.step(v) for v in np.asarray(x, dtype=float)], dtype=bool)



# ---- the noise estimator (csrc/weigh/sig_noise.c) ---------------------------------
NOISE_FLOOR_Q7 = 32               # a quarter of one code, Q24.7
NOISE_MAX_Q7 = 1 << 27            # 2^20 codes: 6 x this still fits int32
NOISE_FLOOR_REL = 2.0 ** -24      # float floor: this fraction of |sample| ...
NOISE_FLOOR_ABS = 1e-30           # ... and never below this
NOISE_MAX_F = 1e300               # host double (the MCU float build caps at 1e36)
NOISE_WARMUP = 24                 # updates before the estimator may be frozen


class NoiseEstimator:
    """Per-sample noise sigma from |x_k - x_{k-1}|: a quantile tracker that
    moves up by sigma/2^s when |d| > sigma and down by (1 - 1/8) sigma/2^s
    when |d| < sigma (s = 2, 3, 4, then 5 after 8, 24 and 56 updates).  For
    Gaussian noise it settles where P(|d| > sigma) = 0.48, i.e. sigma ~ the
    noise's standard deviation; a glitch or a step moves it by one step at
    most.  Floor: a quarter code (fixed, Q24.7); float: a quarter of the
    smallest non-zero |d| seen (one code of a quantised signal), 2^-24 |x|
    and 1e-30, the largest of the three."""

    def __init__(self, fixed=False):
        self.fixed = bool(fixed)
        self.reset()

    def reset(self):
        self.prev, self.has_prev, self.count = 0, False, 0
        self.res = 0.0                  # float: smallest non-zero |d| seen (a code), 0 = none
        self.sigma = NOISE_FLOOR_Q7 if self.fixed else NOISE_FLOOR_ABS

    def floor(self, x):
        if self.fixed:
            return NOISE_FLOOR_Q7
        return max(abs(x) * NOISE_FLOOR_REL, self.res * 0.25, NOISE_FLOOR_ABS)

    def _step(self, x, update=True):
        """x: a clamped code (fixed) or a float; non-finite: nothing changes."""
        if not self.fixed and not math.isfinite(x):
            return
        if not self.fixed:
            dd = abs(x - self.prev)
            if self.has_prev and 0 < dd < NOISE_MAX_F and (dd < self.res or self.res == 0):
                self.res = dd
        if self.has_prev and update:
            if self.fixed:
                d = abs(x - self.prev)
                d = INT32_MAX if d > (INT32_MAX >> 7) else d << 7
            else:
                d = abs(x - self.prev)
            if self.count == 0:
                self.sigma = min(d, NOISE_MAX_Q7 if self.fixed else NOISE_MAX_F)
            else:
                sh = 2 if self.count < 8 else 3 if self.count < NOISE_WARMUP else 4 if self.count < 56 else 5
                if self.fixed:
                    up = self.sigma >> sh
                    down = up - (up >> 3)
                    if d > self.sigma:
                        self.sigma = min(self.sigma + up, NOISE_MAX_Q7)
                    elif d < self.sigma:
                        self.sigma -= down
                else:
                    up = self.sigma * 2.0 ** -sh
                    down = up - up * 0.125
                    if d > self.sigma:
                        self.sigma = min(self.sigma + up, NOISE_MAX_F)
                    elif d < self.sigma:
                        self.sigma = self.sigma - down
            self.count = min(self.count + 1, 255)
        self.sigma = max(self.sigma, self.floor(x))
        self.prev, self.has_prev = x, True

    def process(self, x, update=None):
        """Samples (optionally per-sample update flags) -> sigma after each."""
        x = np.asarray(x, dtype=float)
        up = np.ones(x.size, dtype=bool) if update is None else np.asarray(update, dtype=bool)
        out = np.empty(x.size)
        for i, v in enumerate(x):
            self._step(clamp_code(code_of(v)) if self.fixed else float(v), bool(up[i]))
            out[i] = self.value
        return out

    @property
    def at_floor(self):
        return self.sigma <= self.floor(self.prev)

    @property
    def value(self):
        return self.sigma / 128 if self.fixed else self.sigma


# Thresholds from the measured noise sigma (the "auto" preset): the C core
# computes them from sigma with these factors (fixed: shifts and adds).
NOISE_FROZEN_MAX = 64             # skip count from which motion is taken for noise


def noise_thresholds(sigma, fixed=False):
    """(a0, motion_band, stable_step, zero_band, zero_rate) from sigma (Q24.7
    int for the fixed form, a0 then in codes; float otherwise)."""
    if fixed:
        a0 = max(((sigma << 2) + (sigma << 1) + 64) >> 7, 1)
        return a0, sigma + (sigma >> 1), sigma >> 2, sigma, sigma >> 4
    return 6.0 * sigma, 1.5 * sigma, 0.25 * sigma, sigma, 0.0625 * sigma

# ---- the chain ---------------------------------------------------------------
class Chain:
    """limit -> anti-pulse -> Kalman -> stability, with the lock-out fix,
    motion-aware settling, tare and zero tracking, and in the auto preset
    (the default) the thresholds following the noise measured on the fly
    (csrc/weigh/sig_chain.c)."""

    def __init__(self, preset="auto", fixed=False, units_per_kg=None, **overrides):
        self.params = chain_params(preset, units_per_kg, **overrides)
        self.fixed = bool(fixed)
        p = self.params
        if self.fixed:
            self.fixed_params = f = chain_fixed_params(p)
            self.limit = LimitFilter(f["a0"], f["lockout_n"], fixed=True)
            self.motion_band, self.zero_band, self.zero_rate = (
                f["motion_band_q7"], f["zero_band_q7"], f["zero_rate_q7"])
        else:
            self.limit = LimitFilter(p["A0"], p["lockout_n"])
            self.motion_band, self.zero_band, self.zero_rate = (
                p["motion_band"], p["zero_band"], p["zero_rate"])
        self.ap = AntiPulse(p["window"], fixed=self.fixed)
        self.kf = Kalman1(p["Q"], p["R"], p["x0"], p["P0"], p["seed_first"], fixed=self.fixed)
        self.st = StabilityDetector(p["stable_step"], p["stable_count"], fixed=self.fixed)
        self.motion_count = p["motion_count"]
        self.noise_auto = bool(p["noise_auto"])
        self.noise = NoiseEstimator(self.fixed)
        self.reset()

    def reset(self):
        for stage in (self.limit, self.ap, self.kf, self.st, self.noise):
            stage.reset()
        self.offset_raw, self.out_raw, self.motion_run = 0, 0, 0
        self.zero_raw = 0           # the set zero: the offset at the last tare, set_offset or reset
        self.holdoff, self.frozen, self.rejected_prev = 0, 0, False
        self.tare_pending, self.stable, self.settled, self.has_out, self.status = False, False, False, False, OK
        self.ramp, self.missed, self.paused, self.followed = False, False, False, False
        self.slope, self.last, self.prev_x, self.origin, self.pred = 0, 0, 0, 0, 0
        self.anchor, self.drift_age, self.drifting = 0, 0, True
        self.level, self.has_level, self.hold_block = 0, False, False
        self.trend_mean, self.trending = 0, False
        self._set_thresholds()

    def _set_thresholds(self):
        """The thresholds that follow the measured noise (auto mode only)."""
        if self.noise_auto:
            (self.limit.a0, self.motion_band, self.st.step_value, self.zero_band,
             self.zero_rate) = noise_thresholds(self.noise.sigma, self.fixed)
            s = self.noise.sigma
            self.near_band = s << 1 if self.fixed else 2.0 * s
            if self.noise.count == 0:           # no difference seen yet: take every sample
                self.limit.a0 = 2 * CODE_MAX if self.fixed else 6.0 * NOISE_MAX_F

    def _restart_kf(self):
        """The load moved: P back to P0; in auto mode the estimate also starts
        again from the new samples (seed_first), keeping nothing of the old load."""
        if self.noise_auto:
            self.kf.reset()
        else:
            self.kf.restart()

    def _noise_step(self, x, ret):
        """After the stages: the estimator sees the sample unless it or the one
        before was rejected as an impulse or the load is moving (a motion
        restart or re-seed, then `window` samples of hold-off, or a motion run
        under way).  A count goes up on each skipped sample and down on each
        other one; from NOISE_FROZEN_MAX on, so much motion is noise and the
        estimator sees every sample, with its warm-up steps again.  A ramp
        sample is never noise: skipped, the count left as it is."""
        event = (ret & (CHAIN_MOTION | LIMIT_RESEEDED | CHAIN_RAMP)) != 0
        rejected = (ret & WARN_REJECTED) != 0
        if event:
            self.holdoff = self.ap.n
        elif self.holdoff:
            self.holdoff -= 1
        quiet = not (event or rejected or self.rejected_prev) and self.holdoff == 0 and self.motion_run == 0
        self.rejected_prev = rejected
        if ret & CHAIN_RAMP:
            update = False
        elif quiet:
            self.frozen, update = max(self.frozen - 1, 0), True
        else:
            self.frozen = min(self.frozen + 1, 2 * NOISE_FROZEN_MAX)
            if self.frozen == NOISE_FROZEN_MAX:
                self.noise.count = min(self.noise.count, 8)     # the noise changed: large steps again
            update = self.frozen >= NOISE_FROZEN_MAX or self.noise.count < NOISE_WARMUP
        self.noise._step(x, update)
        self._set_thresholds()
        return ret | CHAIN_NOISE_FLOOR if self.noise.at_floor else ret

    def _kx(self):
        return self.kf.xq if self.fixed else self.kf._x

    # ---- ramps (auto mode): a pour is a load change, not a glitch ----------------
    def _within(self, a, b, band):
        """|a - b| <= band (saturating in the fixed form)."""
        d = self._diff(a, b)
        return (min(abs(d), INT32_MAX) if self.fixed else abs(d)) <= band

    def _diff(self, a, b):
        return sat32(a - b) if self.fixed else a - b

    def _ramp_before(self, x):
        """While a ramp is followed the limit judges the sample against the
        ramp's prediction (last + slope); a sample nearer the last followed
        one than the prediction, within A0/2 of it, says the load may have
        stopped: the first such sample is followed (judged against the last
        one, the slope kept), the second in a row ends the ramp (returns
        True) and is taken."""
        if not self.ramp:
            return False
        step = self.slope + self.slope if self.missed else self.slope     # one sample held: two ahead
        if self.fixed:
            p, half = clamp_code(self.last + step), self.limit.a0 >> 1
        else:
            p, half = self.last + step, self.limit.a0 * 0.5
            p = p if math.isfinite(p) else self.last
        d_last, d_pred = self._diff(x, self.last), self._diff(x, p)
        if d_last <= half and -d_last <= half and abs(d_last) <= abs(d_pred):
            self.limit.set_ref(self.last)
            if self.paused:
                self.ramp = self.missed = self.paused = False
                return True
            self.paused = True
            return False
        self.paused = False
        self.pred = p
        self.limit.set_ref(p)
        return False

    def _ramp_after(self, x, y, ret):
        """After the limit: a second rejection on one side that lies further out
        than the first by more than A0/2 starts a ramp (both samples moved on:
        a pour, not a glitch pair at one level; and the two steps out, from Dc
        to the first and from the first to the second, within a factor 4 of
        each other: not a glitch on a load step); so does a first rejection
        when the sample before, accepted, lay more than A0/2 out on the same
        side and the two steps agree within a factor 2 (a ramp of 3-6 sigma
        per sample, whose first sample is within A0; a swing turning back
        shrinks its step); a followed ramp takes each
        sample within A0 of its prediction, last + slope, the slope moving half
        way to each new difference (kept across one held sample).  A rejection back within A0 of where the ramp began ends it
        and the sample is taken (a glitch pair or a bump that came back);
        otherwise, if no sample has been followed since the start and the
        sample is nearer where the ramp began than its prediction, and no
        farther from it than the ramp's last value (not a glitch itself), the
        start was a glitch pair: the level before it is held and the window starts
        again from it (a re-seed); else the prediction is held when the sample
        lies beyond it on the ramp's side (a glitch in a pour), the last
        followed value otherwise (a bump's top, a swing turning, a pour
        slowing down), and a second rejection in a row ends the ramp with the last
        followed value.  Returns (y, status)."""
        rejected = (ret & WARN_REJECTED) != 0
        finite = self.fixed or math.isfinite(x)
        if self.ramp:
            if ret & LIMIT_RESEEDED:
                self.ramp = self.missed = self.paused = False
            elif not rejected:
                if not (self.missed or self.paused):    # the slope: half way to the last difference
                    d = self._diff(self._diff(x, self.last), self.slope)
                    self.slope += d >> 1 if self.fixed else d * 0.5
                self.last, self.missed, self.followed = x, False, True
                ret |= CHAIN_RAMP
            else:
                d = self._diff(x, self.origin) if finite else math.nan
                if d <= self.limit.a0 and -d <= self.limit.a0:
                    self.ramp = self.missed = self.paused = False
                    self.limit.accept(x)
                    y, ret = x, (ret & ~WARN_REJECTED) | LIMIT_RESEEDED
                elif (not self.followed and abs(self._diff(x, self.pred)) > abs(d)
                      and abs(d) <= abs(self._diff(self.last, self.origin))):
                    self.ramp = self.missed = self.paused = False
                    self.limit.set_ref(self.origin)
                    y, ret = self.origin, ret | LIMIT_RESEEDED
                else:       # a glitch in a pour, beyond the prediction: the prediction
                    beyond = x > self.pred if self.slope > 0 else x < self.pred
                    y = self.pred if beyond and not self.missed else self.last
                    if self.missed:
                        self.ramp = self.missed = self.paused = False
                    else:
                        self.missed = True
                        ret |= CHAIN_RAMP
        elif rejected and finite and self.limit.run >= 1:
            half = self.limit.a0 >> 1 if self.fixed else self.limit.a0 * 0.5
            moved = self._diff(x, self.prev_x) * self.limit.side
            before = self._diff(self.prev_x, self.limit.Dc) * self.limit.side
            if self.limit.run >= 2:
                start = moved > half and moved * 4 >= before and moved <= before * 4
            else:           # the sample before was accepted: it moved out, and the steps agree closer
                start = before > half and moved * 2 >= before and moved <= before * 2
            if start:
                self.origin = self.limit.Dc
                self.limit.accept(x)
                self.ramp, self.missed, self.paused, self.followed = True, False, False, False
                self.slope, self.last = self._diff(x, self.prev_x), x
                y, ret = x, (ret & ~WARN_REJECTED) | LIMIT_RESEEDED | CHAIN_RAMP
        if finite:
            self.prev_x = x
        return y, ret

    def _drift(self, xk):
        """auto mode: the output's drift over blocks of `window` samples from
        the first full window after a restart; `drifting` while the last block
        moved it by more than sigma (a load still creeping or swinging out
        slower than the stability step sees), and until one block is seen;
        until two when the output, as the window refilled, lay more than
        2^10 sigma from the last stable output (a change so large that a
        creep or swing of a few per mille of it still exceeds the noise when
        the first block ends)."""
        if self.ap.count < self.ap.n:
            self.anchor, self.drift_age, self.drifting = xk, 0, True
            d = self._diff(xk, self.level)
            if self.fixed:
                self.hold_block = self.has_level and (min(abs(d), INT32_MAX) >> 10) > self.noise.sigma
            else:
                self.hold_block = self.has_level and abs(d) > self.noise.sigma * 1024.0
            return
        self.drift_age += 1
        if self.drift_age >= self.ap.n:
            d = self._diff(xk, self.anchor)
            moved = (min(abs(d), INT32_MAX) if self.fixed else abs(d)) > self.noise.sigma
            self.drifting, self.hold_block = moved or self.hold_block, False
            self.anchor, self.drift_age = xk, 0

    def _trend(self, r):
        """auto mode: the residual r = y - output goes into a weighted mean
        with weight 1/2 (standard deviation sigma / sqrt(3) on a still load),
        started again while the window refills; `trending` while it is more
        than 2 of its standard deviations from 0, 2 / sqrt(3) sigma taken as
        37/32 sigma (a load that has begun to move by a few sigma per sample,
        before the motion test trips)."""
        s = self.noise.sigma
        if self.ap.count < self.ap.n:
            self.trend_mean, self.trending = 0, False
            return
        if self.fixed:
            self.trend_mean = sat32(self.trend_mean + (sat32(r - self.trend_mean) >> 1))
            self.trending = min(abs(self.trend_mean), INT32_MAX) > s + (s >> 3) + (s >> 5)
        else:
            e = self.trend_mean + (r - self.trend_mean) * 0.5
            band = s * 1.15625
            self.trend_mean, self.trending = e, e > band or -e > band

    def _backed(self, ret, y_k, m_k, xk):
        """auto mode: the stability detector's verdict counts only when the
        output is backed by the samples - none replaced, held, re-seeded or
        followed as a ramp on this sample, a full window since the last
        restart and no drift in the last block (_drift), no motion run under
        way, the sample within 2 sigma of the output and the window's trimmed
        mean within 1 sigma of it (a load that has begun to move, faster than
        the output follows), and no trend (_trend)."""
        if ret & (WARN_REJECTED | LIMIT_RESEEDED | CHAIN_MOTION | CHAIN_RAMP):
            return False
        if self.ap.count < self.ap.n or self.motion_run or self.drifting or self.trending:
            return False
        d, e = self._diff(y_k, xk), self._diff(m_k, xk)
        if self.fixed:
            d, e = min(abs(d), INT32_MAX), min(abs(e), INT32_MAX)
        return abs(d) <= self.near_band and abs(e) <= self.noise.sigma

    def _step(self, x):
        """One sample (code or float); returns (out in Q7 or float, stable, status)."""
        ret = OK
        if self.fixed and abs(x) > CODE_MAX:
            x, ret = clamp_code(x), WARN_CLAMPED
        ramp_ended = self.noise_auto and self._ramp_before(x)
        y, st = self.limit._step(x)
        if st < 0:
            return None, False, st
        ret |= st
        if self.noise_auto:
            y, ret = self._ramp_after(x, y, ret)
        if ret & LIMIT_RESEEDED:
            self.ap.reset()
            if self.motion_band > 0:
                self._restart_kf()
            self.motion_run = 0
        if self.ramp or ramp_ended:             # the window holds the ramp's last sample only
            self.ap.reset()
            self.motion_run = 0
        if ramp_ended:
            self._restart_kf()
            ret |= CHAIN_MOTION
        m, _ = self.ap._step(y)
        m_k = m * 128 if self.fixed else m
        if self.motion_band > 0 and self.kf.seeded and not self.ramp:
            e = sat32(m_k - self._kx()) if self.fixed else m_k - self._kx()
            if (min(abs(e), INT32_MAX) if self.fixed else abs(e)) > self.motion_band:
                self.motion_run = min(self.motion_run + 1, 255)
            else:
                self.motion_run = 0
            if self.motion_run >= self.motion_count:
                self.ap.reset()
                m, _ = self.ap._step(y)
                m_k = m * 128 if self.fixed else m
                self._restart_kf()
                self.motion_run = 0
                ret |= CHAIN_MOTION
        self.limit.set_ref(m)
        if self.noise_auto and (self.ap.count < self.ap.n or not self.settled):
            self.kf.reset()             # settling: the window's trimmed mean is the estimate
        xk = self.kf._step(m_k)
        self.settled = stab = self.st._step(xk)
        y_k = y * 128 if self.fixed else y
        if self.noise_auto:
            self._drift(xk)
            self._trend(self._diff(y_k, xk))
        if self.noise_auto and stab:
            stab = self._backed(ret, y_k, m_k, xk)
        if stab:
            self.level, self.has_level = xk, True
            if self.tare_pending:
                self.offset_raw = self.zero_raw = xk
                self.tare_pending = False
                ret |= CHAIN_TARED
            elif self.zero_band > 0:
                # noise_auto: tracking around the set zero (its total correction stays within
                # the band); the fixed-threshold presets: around the offset (a drift followed)
                ref = self.zero_raw if self.noise_auto else self.offset_raw
                dz = sat32(xk - self.offset_raw) if self.fixed else xk - self.offset_raw
                if self._within(xk, ref, self.zero_band):
                    dz = max(-self.zero_rate, min(self.zero_rate, dz))
                    self.offset_raw = sat32(self.offset_raw + dz) if self.fixed else self.offset_raw + dz
        self.out_raw = sat32(xk - self.offset_raw) if self.fixed else xk - self.offset_raw
        self.stable, self.has_out = stab, True
        if self.noise_auto:
            ret = self._noise_step(x, ret)
        return self.out_raw, stab, ret

    def step(self, x):
        """One sample -> (filtered, stable).  The status bits are in .status."""
        out, stab, self.status = self._step(code_of(x) if self.fixed else float(x))
        if out is None:
            return float("nan"), False
        return (out / 128 if self.fixed else float(out)), bool(stab)

    def process(self, x, flags=False):
        """Array in -> (filtered, stable[, status int16 per sample])."""
        x = np.asarray(x, dtype=float)
        if self.fixed and not np.all(np.isfinite(x)):
            i = int(np.flatnonzero(~np.isfinite(x))[0])
            raise NonFiniteError(f"sample {i}: non-finite value {float(x[i])!r}: the fixed form takes ADC codes")
        out = np.empty(x.size)
        stable = np.zeros(x.size, dtype=bool)
        status = np.zeros(x.size, dtype=np.int16)
        for i, v in enumerate(x):
            out[i], stable[i] = self.step(v)
            status[i] = self.status
        return (out, stable, status) if flags else (out, stable)

    def tare(self):
        """Offset := current Kalman output if stable, else at the next stable
        sample.  Returns True when applied now."""
        if self.has_out and self.stable:
            self.offset_raw, self.out_raw, self.tare_pending = self._kx(), 0, False
            self.zero_raw = self.offset_raw
            return True
        self.tare_pending = True
        return False

    def set_offset(self, offset):
        _finite("offset", offset)
        self.offset_raw = _round_int32("offset", offset * 128) if self.fixed else float(offset)
        self.zero_raw, self.tare_pending = self.offset_raw, False

    @property
    def offset(self):
        return self.offset_raw / 128 if self.fixed else self.offset_raw

    # the Kalman stage's estimate, variance and gain, as the chain shows them
    x = property(lambda self: self.kf.x)
    P = property(lambda self: self.kf.P)
    K = property(lambda self: self.kf.K)

    @property
    def Dc(self):
        return float(self.limit.Dc)

    @property
    def sigma(self):
        """The noise sigma the thresholds follow: measured (auto mode) or sqrt(R)."""
        if self.noise_auto:
            return float(self.noise.value)
        return math.sqrt(self.params["R"])
