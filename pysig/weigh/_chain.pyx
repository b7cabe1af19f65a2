# cython: language_level=3, boundscheck=False, wraparound=False
"""The weighing chain of csrc/ (limit, anti-pulse, Kalman, stability, chain)
as Python classes.  Same names, parameters and results as the pure-Python
spec in tests/spec/chain.py; `fixed=True` runs the C fixed-point form.

process() loops in C without the GIL over a whole float64 array; state is
carried across calls, so a signal processed in pieces gives the same result
as in one call."""
import numpy as np
cimport numpy as cnp
from libc.math cimport NAN, sqrt

from ..errors import NonFiniteError, RangeError
from . import _presets as _p

cnp.import_array()

OK = _p.OK
WARN_CLAMPED = _p.WARN_CLAMPED
WARN_REJECTED = _p.WARN_REJECTED
LIMIT_RESEEDED = _p.LIMIT_RESEEDED
CHAIN_MOTION = _p.CHAIN_MOTION
CHAIN_TARED = _p.CHAIN_TARED
CHAIN_NOISE_FLOOR = _p.CHAIN_NOISE_FLOOR
CHAIN_RAMP = _p.CHAIN_RAMP


cdef _as_float(x):
    return np.ascontiguousarray(x, dtype=np.float64).ravel()


cdef _finite_or_raise(cnp.ndarray a, what):
    ok = np.isfinite(a)
    if not ok.all():
        i = int(np.flatnonzero(~ok)[0])
        raise NonFiniteError(f"sample {i}: non-finite value {float(a[i])!r} ({what})")


cdef _codes(x):
    """float64 samples -> int32 codes (nearest, ties to even, saturated)."""
    a = _as_float(x)
    _finite_or_raise(a, "the fixed form takes ADC codes")
    return np.clip(np.rint(a), -2147483648.0, 2147483647.0).astype(np.int32)


cdef _check_init(sig_status st, what):
    if st < 0:
        raise RangeError(f"{what}: parameters rejected by the C core (status {st})")


def _stage_input(x, fixed, finite_note=None, code_range=False, q7=False):
    """What a stage's process() loops over: (codes, floats, n), one of the
    two arrays None.  The fixed form takes int32 ADC codes (clipped to the
    24-bit input range with `code_range`; times 128 for a Q24.7 stage with
    `q7`); the float form takes float64, checked finite when the stage
    cannot take NaN or inf alone (`finite_note` says why, for the error)."""
    if fixed:
        codes = _codes(x)
        if code_range:
            codes = np.clip(codes, -_p.CODE_MAX, _p.CODE_MAX).astype(np.int32)
        if q7:
            codes = codes * np.int32(128)
        return codes, None, codes.shape[0]
    values = _as_float(x)
    if finite_note is not None:
        _finite_or_raise(values, finite_note)
    return None, values, values.shape[0]


def auto_params(fixed=False):
    """The default chain's parameters as the C core's constructors give them
    (sig_chain_params_auto_f / sig_chain_params_auto_q): a dict of the
    sig_chain_params_f / sig_chain_params_q fields.  The auto preset of
    pysig.weigh._presets must produce the same (tests/test_chain_auto_params.py)."""
    cdef sig_chain_params_f pf
    cdef sig_chain_params_q pq
    if fixed:
        sig_chain_params_auto_q(&pq)
        return pq
    sig_chain_params_auto_f(&pf)
    return pf


# ---- what every stage shares ------------------------------------------------
cdef class _Stage:
    """The numeric form (`fixed`) and one-sample stepping, shared by the
    stages and the chain."""
    cdef readonly bint fixed

    def step(self, x):
        """One sample through process(), the state carried on."""
        return self.process(np.array([x], dtype=np.float64))[0]


# ---- the loop of the stages that give one value per sample ------------------
# Limit, anti-pulse and Kalman share one step shape in both numeric forms:
# status = step(state, sample, &value), sample and value a sig_real in the
# float form, an int32 in the fixed form (codes; Q24.7 in the Kalman
# stage, whose input is scaled by 128 and output divided by 128).  One loop
# runs any of them.
cdef class LimitFilter
cdef class AntiPulse
cdef class Kalman1

ctypedef fused value_stage:
    LimitFilter
    AntiPulse
    Kalman1

ctypedef fused sample:
    sig_real            # the float form
    int32_t             # the fixed form: ADC codes, or Q24.7 in the Kalman stage


cdef inline sig_status _value_step(value_stage stage, sample x, sample *y) noexcept nogil:
    """One sample through the stage, in the numeric form of `sample`."""
    if value_stage is LimitFilter:
        if sample is int32_t:
            return sig_limit_step_q(&stage.q, x, y)
        else:
            return sig_limit_step_f(&stage.f, x, y)
    elif value_stage is AntiPulse:
        if sample is int32_t:
            return sig_antipulse_step_q(&stage.q, x, y)
        else:
            return sig_antipulse_step_f(&stage.f, x, y)
    else:
        if sample is int32_t:
            return sig_kalman1_step_q(&stage.q, x, y)
        else:
            return sig_kalman1_step_f(&stage.f, x, y)


cdef sig_status _value_loop(value_stage stage, const sample[::1] x, double[::1] out,
                            int16_t[::1] status) noexcept nogil:
    """Every sample of `x` through the stage: its value in `out` (in codes
    for the fixed form; NaN where the step failed), its status in `status`
    unless that is empty.  Returns the last status."""
    cdef Py_ssize_t i
    cdef sample y
    cdef sig_status st = 0
    cdef bint keep = status.shape[0] != 0
    for i in range(x.shape[0]):
        st = _value_step(stage, x[i], &y)
        if st < 0:
            out[i] = NAN
        elif sample is int32_t and value_stage is Kalman1:
            out[i] = y / 128.0          # Q24.7
        else:
            out[i] = y
        if keep:
            status[i] = st
    return st


cdef tuple _process_values(value_stage stage, x, bint keep_status, finite_note):
    """process() of a stage that gives one value per sample: (float64
    values, int16 status per sample (empty unless `keep_status`), the last
    status).  The input as _stage_input takes it (`finite_note` for the
    float form's finiteness check, None when the stage takes NaN and inf).
    The Kalman stage's fixed form runs in Q24.7: codes clipped to the
    24-bit range, times 128, in; its values divided by 128."""
    cdef bint q7 = value_stage is Kalman1
    codes, values, n = _stage_input(x, stage.fixed, finite_note, code_range=q7, q7=q7)
    out = np.empty(n)
    status = np.empty(n if keep_status else 0, dtype=np.int16)
    cdef double[::1] out_view = out
    cdef int16_t[::1] status_view = status
    cdef const int32_t[::1] xq
    cdef const sig_real[::1] xf
    cdef sig_status last = 0
    if stage.fixed:
        xq = codes
        with nogil:
            last = _value_loop(stage, xq, out_view, status_view)
    else:
        xf = values
        with nogil:
            last = _value_loop(stage, xf, out_view, status_view)
    return out, status, last


# ---- stage 1 ---------------------------------------------------------------
cdef class LimitFilter(_Stage):
    """Limit filter, the chain's first stage: a sample further than `a0`
    from the reference Dc is replaced by Dc.  Used alone, an accepted sample
    becomes Dc.

    Parameters
    ----------
    a0 : float
        The largest accepted ``|x - Dc|``, in signal units (> 0).
    lockout_n : int, optional
        0 (the weighing paper's behaviour) or the number of successive
        rejections on one side after which the filter accepts the level
        and re-seeds (a real load change larger than a0).
    fixed : bool, optional
        The firmware's fixed-point form: samples are int32 ADC codes.

    Raises
    ------
    RangeError
        `a0` not a finite number > 0 (in the fixed form: 0 codes once
        rounded) or `lockout_n` not an integer in 0..255, named in the
        message.

    Examples
    --------
    >>> out, status = LimitFilter(2.0).process([10.0, 10.5, 30.0, 10.2], flags=True)
    >>> out                      # the 30.0 pulse is replaced by the reference
    array([10. , 10.5, 10.5, 10.2])
    >>> status                   # 4: WARN_REJECTED
    array([0, 0, 4, 0], dtype=int16)
    """
    cdef sig_limit_f f
    cdef sig_limit_q q
    cdef readonly int status

    def __init__(self, a0, lockout_n=0, fixed=False):
        a, n = _p.limit_params(a0, lockout_n, fixed)     # validates, names the bad parameter
        self.fixed = fixed
        self.status = 0
        _check_init(sig_limit_init_q(&self.q, a, n) if fixed else sig_limit_init_f(&self.f, a, n),
                    "LimitFilter")

    def reset(self):
        sig_limit_reset_q(&self.q) if self.fixed else sig_limit_reset_f(&self.f)

    def process(self, x, flags=False):
        out, status, last = _process_values[LimitFilter](self, x, flags, None)
        if out.shape[0]:
            self.status = last
        return (out, status) if flags else out

    @property
    def Dc(self):
        return float(self.q.dc if self.fixed else self.f.dc)

    @property
    def run(self):
        return self.q.t.run if self.fixed else self.f.t.run

    @property
    def seeded(self):
        return bool(self.q.t.seeded if self.fixed else self.f.t.seeded)


# ---- stage 2 ---------------------------------------------------------------
cdef class AntiPulse(_Stage):
    """Anti-pulse filter, the chain's second stage: the mean of the last
    `window` samples without one max and one min (while it fills: 1 sample
    -> itself, 2 -> their mean, k -> the trimmed mean of k).

    Parameters
    ----------
    window : int, optional
        Samples averaged (the weighing paper's N).
    fixed : bool, optional
        The firmware's fixed-point form: samples are int32 ADC codes.

    Raises
    ------
    RangeError
        `window` outside the range the C core accepts.

    Examples
    --------
    >>> AntiPulse(4).process([1.0, 2.0, 9.0, 3.0, 4.0])
    array([1. , 1.5, 2. , 2.5, 3.5])
    """
    cdef sig_antipulse_f f
    cdef sig_antipulse_q q
    cdef readonly int status

    def __init__(self, window=12, fixed=False):
        n = _p.window_param(window)
        self.fixed = fixed
        self.status = 0
        _check_init(sig_antipulse_init_q(&self.q, n) if fixed else sig_antipulse_init_f(&self.f, n),
                    "AntiPulse")

    def reset(self):
        sig_antipulse_reset_q(&self.q) if self.fixed else sig_antipulse_reset_f(&self.f)

    def process(self, x):
        out, _, last = _process_values[AntiPulse](self, x, False,
                                                  "the anti-pulse stage alone takes finite samples")
        if out.shape[0]:
            self.status = last
        return out

    @property
    def window(self):
        return self.q.n if self.fixed else self.f.n

    @property
    def count(self):
        return self.q.count if self.fixed else self.f.count


# ---- the Kalman estimate, read from the stage alone or from the chain -------
cdef class _KalmanReadings(_Stage):
    """x, K, P and the innovation of a Kalman state in signal units, for
    the Kalman stage and for the chain (its third stage)."""
    cdef const sig_kalman1_f *kalman_f      # the state inside the object, set by __cinit__
    cdef const sig_kalman1_q *kalman_q
    cdef double r                           # R, signal units squared

    @property
    def x(self):
        return self.kalman_q.x / 128.0 if self.fixed else self.kalman_f.x

    @property
    def K(self):
        return (1073741824 - self.kalman_q.y) / 1073741824.0 if self.fixed else self.kalman_f.k

    @property
    def P(self):
        """P (for the fixed form: K * R, since P/R equals K after an update)."""
        if not self.fixed:
            return self.kalman_f.p
        return self.kalman_q.p0 / 65536.0 * self.r if self.kalman_q.phase == 0 else self.K * self.r

    @property
    def innovation(self):
        return self.kalman_q.innov / 128.0 if self.fixed else self.kalman_f.innov


# ---- stage 3 ---------------------------------------------------------------
cdef class Kalman1(_KalmanReadings):
    """Scalar Kalman filter, A = H = 1, the chain's third stage.

    Parameters
    ----------
    Q, R : float, optional
        Process and measurement noise variances (signal units squared);
        the defaults are the weighing paper's (kg).
    x0, P0 : float, optional
        Initial estimate and its variance.
    seed_first : bool, optional
        Start from the first sample instead of x0.
    fixed : bool, optional
        The firmware's fixed-point form: samples are codes, x in Q24.7,
        gain in Q2.30.

    Raises
    ------
    RangeError
        Q, R, x0 or P0 not finite, Q or P0 negative, R not positive (the
        fixed form: Q/R outside 0..1 or P0/R outside 0..16384), named in
        the message.

    Examples
    --------
    >>> import numpy as np
    >>> k = Kalman1(Q=1e-4, R=0.05, x0=0.0, P0=10.0)
    >>> np.round(k.process([1.0, 1.0, 1.0]), 4)
    array([0.995 , 0.9975, 0.9983])
    """
    cdef sig_kalman1_f f
    cdef sig_kalman1_q q

    def __cinit__(self, *args, **kwargs):
        self.kalman_f, self.kalman_q = &self.f, &self.q

    def __init__(self, Q=1e-7, R=0.05, x0=1.0, P0=10.0, seed_first=False, fixed=False):
        Q, R, x0, P0 = _p.kalman_params(Q, R, x0, P0)
        self.fixed = fixed
        self.r = R
        if fixed:
            q, p0, x0_q7 = _p.kalman_fixed_params(Q, R, P0, x0)
            _check_init(sig_kalman1_init_q(&self.q, q, p0, x0_q7, bool(seed_first)), "Kalman1")
        else:
            _check_init(sig_kalman1_init_f(&self.f, Q, R, P0, x0, bool(seed_first)), "Kalman1")

    def reset(self):
        sig_kalman1_reset_q(&self.q) if self.fixed else sig_kalman1_reset_f(&self.f)

    def restart(self):
        """P back to P0, x kept (what the motion-aware chain does)."""
        sig_kalman1_restart_q(&self.q) if self.fixed else sig_kalman1_restart_f(&self.f)

    def process(self, z):
        out, _, _ = _process_values[Kalman1](self, z, False, "the Kalman stage alone takes finite samples")
        return out

    @property
    def R(self):
        """The measurement noise variance, signal units squared."""
        return self.r

    @property
    def seeded(self):
        return bool(self.q.seeded if self.fixed else self.f.seeded)


# ---- stage 4 ---------------------------------------------------------------
cdef class StabilityDetector(_Stage):
    """Stability detector, the chain's last stage: stable once successive
    values have differed by at most `step` for `count` samples.

    Parameters
    ----------
    step : float, optional
        The largest change between successive values that counts as still.
    count : int, optional
        Successive still samples needed (the weighing paper: 1).
    fixed : bool, optional
        The firmware's fixed-point form: values and step rounded to Q24.7.

    Raises
    ------
    RangeError
        A parameter outside its range.
    NonFiniteError
        `process` given NaN or inf (this stage alone takes finite values).

    Examples
    --------
    >>> StabilityDetector(step=0.1, count=2).process([1.0, 1.05, 1.02, 1.5, 1.52, 1.55])
    array([False, False,  True, False, False,  True])
    """
    cdef sig_stable_f f
    cdef sig_stable_q q

    def __init__(self, step=0.01, count=1, fixed=False):
        step_value, n = _p.stable_params(step, count, fixed)
        self.fixed = fixed
        _check_init(sig_stable_init_q(&self.q, step_value, n) if fixed
                    else sig_stable_init_f(&self.f, step_value, n), "StabilityDetector")

    def reset(self):
        sig_stable_reset_q(&self.q) if self.fixed else sig_stable_reset_f(&self.f)

    def step(self, x):
        return bool(self.process(np.array([x], dtype=np.float64))[0])

    def process(self, x):
        cdef cnp.ndarray[cnp.uint8_t] out
        cdef cnp.ndarray[cnp.float64_t] xf
        cdef cnp.ndarray[cnp.int32_t] xq
        cdef Py_ssize_t i, n
        cdef c_bool s = 0
        if self.fixed:
            xf = _as_float(x)
            _finite_or_raise(xf, "stability input")
            xq = np.clip(np.rint(xf * 128.0), -2147483648.0, 2147483647.0).astype(np.int32)
            n = xq.shape[0]
        else:
            xf = _as_float(x)
            _finite_or_raise(xf, "the stability stage alone takes finite values")
            n = xf.shape[0]
        out = np.empty(n, dtype=np.uint8)
        with nogil:
            for i in range(n):
                if self.fixed:
                    sig_stable_step_q(&self.q, xq[i], &s)
                else:
                    sig_stable_step_f(&self.f, xf[i], &s)
                out[i] = s
        return out.view(bool)

    @property
    def run(self):
        return self.q.run if self.fixed else self.f.run


# ---- the noise estimator ------------------------------------------------------
cdef class NoiseEstimator(_Stage):
    """The per-sample noise sigma measured on the fly (csrc/include/sig_noise.h):
    a quantile tracker on ``|x_k - x_{k-1}|`` that glitches and steps move by one
    small step only.  Fixed: samples are codes, sigma in codes (Q24.7 inside).

    Examples
    --------
    >>> import numpy as np
    >>> x = np.random.default_rng(1).normal(0.0, 3.0, 2000)
    >>> s = NoiseEstimator().process(x)
    >>> bool(2.4 < np.median(s[200:]) < 3.6)
    True
    """
    cdef sig_noise_f f
    cdef sig_noise_q q

    def __init__(self, fixed=False):
        self.fixed = fixed
        self.reset()

    def reset(self):
        sig_noise_reset_q(&self.q) if self.fixed else sig_noise_reset_f(&self.f)

    def process(self, x, update=None):
        """Samples (and optionally a per-sample update flag) -> sigma after each."""
        cdef cnp.ndarray[cnp.float64_t] out, xf
        cdef cnp.ndarray[cnp.int32_t] xq
        cdef cnp.ndarray[cnp.uint8_t] up
        cdef Py_ssize_t i, n
        xq, xf, n = _stage_input(x, self.fixed, code_range=True)
        up = (np.ones(n, dtype=np.uint8) if update is None
              else np.ascontiguousarray(update, dtype=bool).ravel().view(np.uint8))
        if up.shape[0] != n:
            raise RangeError(f"update has {up.shape[0]} flags for {n} samples")
        out = np.empty(n)
        with nogil:
            for i in range(n):
                if self.fixed:
                    sig_noise_step_q(&self.q, xq[i], up[i] != 0)
                    out[i] = self.q.sigma / 128.0
                else:
                    sig_noise_step_f(&self.f, xf[i], up[i] != 0)
                    out[i] = self.f.sigma
        return out

    @property
    def sigma(self):
        return self.q.sigma / 128.0 if self.fixed else self.f.sigma

    @property
    def at_floor(self):
        return bool(sig_noise_at_floor_q(&self.q) if self.fixed else sig_noise_at_floor_f(&self.f))

    @property
    def count(self):
        return self.q.count if self.fixed else self.f.count


# ---- the chain ---------------------------------------------------------------
cdef class Chain(_KalmanReadings):
    """limit -> anti-pulse -> Kalman -> stability (csrc/weigh/sig_chain.c).

    Parameters
    ----------
    preset : str
        "auto" (default): no sensor constant and no unit; the noise sigma is
        measured on the fly and A0, the motion band, the stability step and
        the zero-tracking band and rate follow it (pysig.weigh._presets).
        "paper" reproduces the weighing paper; "recommended" and "adaptive"
        derive their thresholds from a fixed R.
    fixed : bool
        Run the firmware's fixed-point form (samples rounded to codes).
    units_per_kg : float, optional
        Scale of the kg parameters into signal units.
    **overrides
        Parameters (A0, window, Q, R, x0, P0, seed_first, stable_step,
        stable_count, lockout_n, motion_band, motion_count, zero_band,
        zero_rate), in kg.  With the auto preset an explicit R fixes
        sigma = sqrt(R) instead of measuring it.

    Raises
    ------
    RangeError
        A parameter out of its range, named.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.r_[np.zeros(50), np.full(50, 1000.0)] + np.random.default_rng(0).normal(0, 5, 100)
    >>> out, stable = Chain().process(x)
    >>> bool(abs(out[-1] - 1000.0) < 5.0)
    True
    """
    cdef sig_chain_f f
    cdef sig_chain_q q
    cdef readonly dict params
    cdef readonly int status

    def __cinit__(self, *args, **kwargs):
        self.kalman_f, self.kalman_q = &self.f.kf, &self.q.kf

    def __init__(self, preset="auto", fixed=False, units_per_kg=None, **overrides):
        cdef sig_chain_params_f pf
        cdef sig_chain_params_q pq
        p = _p.chain_params(preset, units_per_kg, **overrides)
        self.params = p
        self.fixed = fixed
        self.status = 0
        self.r = p["R"]
        if fixed:
            pq = _p.chain_fixed_params(p)       # exactly the sig_chain_params_q fields
        else:
            pf = {name.lower(): value for name, value in p.items()}     # the C fields: the names in lower case
        _check_init(sig_chain_init_q(&self.q, &pq) if fixed else sig_chain_init_f(&self.f, &pf), "Chain")

    def reset(self):
        sig_chain_reset_q(&self.q) if self.fixed else sig_chain_reset_f(&self.f)

    def step(self, x):
        """Filter one sample.

        Parameters
        ----------
        x : float
            The sample (an ADC code in the fixed form).

        Returns
        -------
        filtered : float
        stable : bool
            The status bits of the step are in `.status`.
        """
        out, stable = self.process(np.array([x], dtype=np.float64))
        return float(out[0]), bool(stable[0])

    def process(self, x, flags=False):
        """Filter an array, carrying the state on from the previous call.

        Parameters
        ----------
        x : array_like
            Samples (float; in the fixed form ADC codes, rounded).
        flags : bool, optional
            Also return the status of each sample.

        Returns
        -------
        filtered : ndarray of float64
        stable : ndarray of bool
        status : ndarray of int16
            Only with `flags`: warning bits per sample, or a negative
            status code.  A float non-finite sample is an impulse (status
            WARN_REJECTED); one before any finite sample gives NaN, not
            stable, status -2 (SIG_ERR_NONFINITE).

        Raises
        ------
        NonFiniteError
            The fixed form given NaN or inf (ADC codes are finite).

        Examples
        --------
        >>> chain = Chain("paper", units_per_kg=1.0)
        >>> first, _ = chain.process([10.0] * 20)
        >>> rest, stable = chain.process([10.0] * 20)    # continues where it stopped
        >>> bool(stable[-1])
        True
        """
        cdef cnp.ndarray[cnp.float64_t] out
        cdef cnp.ndarray[cnp.uint8_t] stable
        cdef cnp.ndarray[cnp.int16_t] stat
        cdef cnp.ndarray[cnp.float64_t] xf
        cdef cnp.ndarray[cnp.int32_t] xq
        cdef cnp.ndarray[cnp.int32_t] outq
        cdef Py_ssize_t i, n
        cdef sig_real y
        cdef int32_t yq
        cdef c_bool s = 0
        cdef sig_status st = 0
        cdef bint want = flags
        xq, xf, n = _stage_input(x, self.fixed)
        out = np.empty(n)
        stable = np.empty(n, dtype=np.uint8)
        stat = np.empty(n if want else 1, dtype=np.int16)
        if n and not want:
            # the batch entry points of csrc/weigh/sig_chain.c (same results as the step loop)
            if self.fixed:
                outq = np.empty(n, dtype=np.int32)
                with nogil:
                    st = sig_chain_process_q(&self.q, &xq[0], <size_t>n, &outq[0], &stable[0])
                np.divide(outq, 128.0, out=out)
            else:
                with nogil:
                    st = sig_chain_process_f(&self.f, &xf[0], <size_t>n, &out[0], &stable[0])
        elif n:
            with nogil:
                if self.fixed:
                    for i in range(n):
                        st = sig_chain_step_q(&self.q, xq[i], &yq, &s)
                        out[i] = yq / 128.0
                        stable[i] = s
                        stat[i] = st
                else:
                    for i in range(n):
                        st = sig_chain_step_f(&self.f, xf[i], &y, &s)
                        if st < 0:
                            y = NAN
                            s = 0
                        out[i] = y
                        stable[i] = s
                        stat[i] = st
        if n:
            self.status = st
        if want:
            return out, stable.view(bool), stat
        return out, stable.view(bool)

    def tare(self):
        """Offset := the current Kalman output if stable (returns True), else
        at the next stable sample (returns False, tare_pending)."""
        st = sig_chain_tare_q(&self.q) if self.fixed else sig_chain_tare_f(&self.f)
        return st == CHAIN_TARED

    def set_offset(self, offset):
        _p._finite("offset", offset)
        if self.fixed:
            sig_chain_set_offset_q(&self.q, _p.offset_q7(offset))
        else:
            sig_chain_set_offset_f(&self.f, offset)

    @property
    def offset(self):
        return self.q.offset / 128.0 if self.fixed else self.f.offset

    @property
    def tare_pending(self):
        return bool(self.q.tare_pending if self.fixed else self.f.tare_pending)

    @property
    def stable(self):
        return bool(self.q.stable if self.fixed else self.f.stable)

    @property
    def Dc(self):
        return float(self.q.limit.dc if self.fixed else self.f.limit.dc)

    @property
    def sigma(self):
        """The noise sigma the thresholds follow, in signal units: measured
        on the fly (auto preset) or sqrt(R)."""
        if self.fixed and self.q.noise_auto:
            return self.q.noise.sigma / 128.0
        if not self.fixed and self.f.noise_auto:
            return self.f.noise.sigma
        return sqrt(self.r)

    @property
    def noise_at_floor(self):
        """True while the measured noise sits at its floor (stuck sensor)."""
        if self.fixed:
            return bool(self.q.noise_auto and sig_noise_at_floor_q(&self.q.noise))
        return bool(self.f.noise_auto and sig_noise_at_floor_f(&self.f.noise))

    @property
    def window_count(self):
        return self.q.ap.count if self.fixed else self.f.ap.count
