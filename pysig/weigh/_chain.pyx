# cython: language_level=3, boundscheck=False, wraparound=False
"""The weighing chain of csrc/ (limit, anti-pulse, Kalman, stability, chain)
as Python classes.  Same names, parameters and results as the pure-Python
spec in pysig/reference/chain.py; `fixed=True` runs the C fixed-point form.

process() loops in C without the GIL over a whole float64 array; state is
carried across calls, so a signal processed in pieces gives the same result
as in one call."""
import numpy as np
cimport numpy as cnp
from libc.math cimport NAN

from ..errors import NonFiniteError, RangeError
from ..reference import chain as _ref

cnp.import_array()

OK = _ref.OK
WARN_CLAMPED = _ref.WARN_CLAMPED
WARN_REJECTED = _ref.WARN_REJECTED
LIMIT_RESEEDED = _ref.LIMIT_RESEEDED
CHAIN_MOTION = _ref.CHAIN_MOTION
CHAIN_TARED = _ref.CHAIN_TARED


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


# ---- stage 1 ---------------------------------------------------------------
cdef class LimitFilter:
    """Limit filter, the chain's first stage: a sample further than `a0`
    from the reference Dc is replaced by Dc.  Used alone, an accepted sample
    becomes Dc.

    Parameters
    ----------
    a0 : float
        The largest accepted |x - Dc|, in signal units (> 0).
    lockout_n : int, optional
        0 (the weighing paper's behaviour) or the number of successive
        rejections on one side after which the filter accepts the level
        and re-seeds (a real load change larger than a0).
    fixed : bool, optional
        The firmware's fixed-point form: samples are int32 ADC codes.

    Raises
    ------
    RangeError
        A parameter outside its range (named in the message).

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
    cdef readonly bint fixed
    cdef readonly int status

    def __init__(self, a0, lockout_n=0, fixed=False):
        ref = _ref.LimitFilter(a0, lockout_n, fixed)      # validates, names the bad parameter
        self.fixed = fixed
        self.status = 0
        if fixed:
            _check_init(sig_limit_init_q(&self.q, ref.a0, ref.lockout_n), "LimitFilter")
        else:
            _check_init(sig_limit_init_f(&self.f, ref.a0, ref.lockout_n), "LimitFilter")

    def reset(self):
        sig_limit_reset_q(&self.q) if self.fixed else sig_limit_reset_f(&self.f)

    def step(self, x):
        return self.process(np.array([x], dtype=np.float64))[0]

    def process(self, x, flags=False):
        cdef cnp.ndarray[cnp.float64_t] out
        cdef cnp.ndarray[cnp.int16_t] stat
        cdef cnp.ndarray[cnp.float64_t] xf
        cdef cnp.ndarray[cnp.int32_t] xq
        cdef Py_ssize_t i, n
        cdef sig_real y
        cdef int32_t yq
        cdef sig_status st = 0
        if self.fixed:
            xq = _codes(x)
            n = xq.shape[0]
        else:
            xf = _as_float(x)
            n = xf.shape[0]
        out = np.empty(n)
        stat = np.empty(n, dtype=np.int16)
        with nogil:
            for i in range(n):
                if self.fixed:
                    st = sig_limit_step_q(&self.q, xq[i], &yq)
                    out[i] = yq
                else:
                    st = sig_limit_step_f(&self.f, xf[i], &y)
                    out[i] = y if st >= 0 else NAN
                stat[i] = st
        if n:
            self.status = stat[n - 1]
        return (out, stat) if flags else out

    @property
    def Dc(self):
        return float(self.q.dc if self.fixed else self.f.dc)

    @property
    def run(self):
        return self.q.run if self.fixed else self.f.run

    @property
    def seeded(self):
        return bool(self.q.seeded if self.fixed else self.f.seeded)


# ---- stage 2 ---------------------------------------------------------------
cdef class AntiPulse:
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
    cdef readonly bint fixed
    cdef readonly int status

    def __init__(self, window=12, fixed=False):
        ref = _ref.AntiPulse(window, fixed)
        self.fixed = fixed
        self.status = 0
        if fixed:
            _check_init(sig_antipulse_init_q(&self.q, ref.n), "AntiPulse")
        else:
            _check_init(sig_antipulse_init_f(&self.f, ref.n), "AntiPulse")

    def reset(self):
        sig_antipulse_reset_q(&self.q) if self.fixed else sig_antipulse_reset_f(&self.f)

    def step(self, x):
        return self.process(np.array([x], dtype=np.float64))[0]

    def process(self, x):
        cdef cnp.ndarray[cnp.float64_t] out
        cdef cnp.ndarray[cnp.float64_t] xf
        cdef cnp.ndarray[cnp.int32_t] xq
        cdef Py_ssize_t i, n
        cdef sig_real y
        cdef int32_t yq
        cdef sig_status st = 0
        if self.fixed:
            xq = _codes(x)
            n = xq.shape[0]
        else:
            xf = _as_float(x)
            _finite_or_raise(xf, "the anti-pulse stage alone takes finite samples")
            n = xf.shape[0]
        out = np.empty(n)
        with nogil:
            for i in range(n):
                if self.fixed:
                    st = sig_antipulse_step_q(&self.q, xq[i], &yq)
                    out[i] = yq
                else:
                    st = sig_antipulse_step_f(&self.f, xf[i], &y)
                    out[i] = y
        if n:
            self.status = st
        return out

    @property
    def window(self):
        return self.q.n if self.fixed else self.f.n

    @property
    def count(self):
        return self.q.count if self.fixed else self.f.count


# ---- stage 3 ---------------------------------------------------------------
cdef class Kalman1:
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
        A parameter outside its range (named in the message).

    Examples
    --------
    >>> import numpy as np
    >>> k = Kalman1(Q=1e-4, R=0.05, x0=0.0, P0=10.0)
    >>> np.round(k.process([1.0, 1.0, 1.0]), 4)
    array([0.995 , 0.9975, 0.9983])
    """
    cdef sig_kalman1_f f
    cdef sig_kalman1_q q
    cdef readonly bint fixed
    cdef readonly double R

    def __init__(self, Q=1e-7, R=0.05, x0=1.0, P0=10.0, seed_first=False, fixed=False):
        ref = _ref.Kalman1(Q, R, x0, P0, seed_first, fixed)
        self.fixed = fixed
        self.R = ref.R
        if fixed:
            _check_init(sig_kalman1_init_q(&self.q, ref.q, ref.p0, ref.x0_q7, ref.seed_first), "Kalman1")
        else:
            _check_init(sig_kalman1_init_f(&self.f, ref.Q, ref.R, ref.P0, ref.x0, ref.seed_first), "Kalman1")

    def reset(self):
        sig_kalman1_reset_q(&self.q) if self.fixed else sig_kalman1_reset_f(&self.f)

    def restart(self):
        """P back to P0, x kept (what the motion-aware chain does)."""
        sig_kalman1_restart_q(&self.q) if self.fixed else sig_kalman1_restart_f(&self.f)

    def step(self, z):
        return self.process(np.array([z], dtype=np.float64))[0]

    def process(self, z):
        cdef cnp.ndarray[cnp.float64_t] out
        cdef cnp.ndarray[cnp.float64_t] zf
        cdef cnp.ndarray[cnp.int32_t] zq
        cdef Py_ssize_t i, n
        cdef sig_real y
        cdef int32_t yq
        if self.fixed:
            zq = np.clip(_codes(z), -_ref.CODE_MAX, _ref.CODE_MAX).astype(np.int32) * np.int32(128)
            n = zq.shape[0]
        else:
            zf = _as_float(z)
            _finite_or_raise(zf, "the Kalman stage alone takes finite samples")
            n = zf.shape[0]
        out = np.empty(n)
        with nogil:
            if self.fixed:
                for i in range(n):
                    sig_kalman1_step_q(&self.q, zq[i], &yq)
                    out[i] = yq / 128.0
            else:
                for i in range(n):
                    sig_kalman1_step_f(&self.f, zf[i], &y)
                    out[i] = y
        return out

    @property
    def x(self):
        return self.q.x / 128.0 if self.fixed else self.f.x

    @property
    def K(self):
        return (1073741824 - self.q.y) / 1073741824.0 if self.fixed else self.f.k

    @property
    def P(self):
        """P (for the fixed form: K * R, since P/R equals K after an update)."""
        if not self.fixed:
            return self.f.p
        return self.q.p0 / 65536.0 * self.R if self.q.phase == 0 else self.K * self.R

    @property
    def innovation(self):
        return self.q.innov / 128.0 if self.fixed else self.f.innov

    @property
    def seeded(self):
        return bool(self.q.seeded if self.fixed else self.f.seeded)


# ---- stage 4 ---------------------------------------------------------------
cdef class StabilityDetector:
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
    cdef readonly bint fixed

    def __init__(self, step=0.01, count=1, fixed=False):
        ref = _ref.StabilityDetector(step, count, fixed)
        self.fixed = fixed
        if fixed:
            _check_init(sig_stable_init_q(&self.q, ref.step_value, ref.count), "StabilityDetector")
        else:
            _check_init(sig_stable_init_f(&self.f, ref.step_value, ref.count), "StabilityDetector")

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


# ---- the chain ---------------------------------------------------------------
cdef class Chain:
    """The weighing chain: limit -> anti-pulse -> Kalman -> stability, with
    tare and zero tracking (csrc/weigh/sig_chain.c).  State is carried
    across `process` calls, so a long signal may be fed in pieces.

    Parameters
    ----------
    preset : {"recommended", "adaptive", "paper"}, optional
        "paper" reproduces the weighing paper; "recommended" (default) adds
        the lock-out fix, motion-aware settling and zero tracking;
        "adaptive" the first two.
    fixed : bool, optional
        The firmware's fixed-point form: samples are int32 ADC codes.
    units_per_kg : float, optional
        Signal units per kg: the parameters are in kg and are converted
        with it (the presets' own scale when None).
    **overrides
        Any of A0, window, Q, R, x0, P0, seed_first, stable_step,
        stable_count, lockout_n, motion_band, motion_count, zero_band,
        zero_rate, in kg.  A0 and motion_band "auto" (presets recommended,
        adaptive) follow from R, the variance of one reading:
        A0_sigmas * sqrt(R) and motion_sigmas * sqrt(R / (window - 2)).

    Raises
    ------
    RangeError
        An unknown preset or a parameter outside its range (named).

    See Also
    --------
    pysig.weigh.scale.noise_sigma : R from a still record.

    Examples
    --------
    >>> import numpy as np
    >>> kg = np.full(40, 10.0) + np.tile([0.02, -0.02], 20)
    >>> filtered, stable = Chain("recommended", units_per_kg=1.0, R=0.01).process(kg)
    >>> round(float(filtered[-1]), 2), bool(stable[-1])
    (10.0, True)
    >>> Chain(window=2)
    Traceback (most recent call last):
        ...
    pysig.errors.RangeError: parameter window=2: must be in 3..32
    """
    cdef sig_chain_f f
    cdef sig_chain_q q
    cdef readonly bint fixed
    cdef readonly dict params
    cdef readonly int status
    cdef double R

    def __init__(self, preset="recommended", fixed=False, units_per_kg=None, **overrides):
        cdef sig_chain_params_f pf
        cdef sig_chain_params_q pq
        p = _ref.chain_params(preset, units_per_kg, **overrides)
        self.params = p
        self.fixed = fixed
        self.status = 0
        self.R = p["R"]
        if fixed:
            fp = _ref.chain_fixed_params(p)
            pq.a0 = fp["a0"]; pq.window = fp["window"]; pq.q_q30 = fp["q_q30"]
            pq.p0_q16 = fp["p0_q16"]; pq.x0_q7 = fp["x0_q7"]; pq.seed_first = fp["seed_first"]
            pq.stable_step_q7 = fp["stable_step_q7"]; pq.stable_count = fp["stable_count"]
            pq.lockout_n = fp["lockout_n"]; pq.motion_band_q7 = fp["motion_band_q7"]
            pq.motion_count = fp["motion_count"]; pq.zero_band_q7 = fp["zero_band_q7"]
            pq.zero_rate_q7 = fp["zero_rate_q7"]
            _check_init(sig_chain_init_q(&self.q, &pq), "Chain")
        else:
            pf.a0 = p["A0"]; pf.window = p["window"]; pf.q = p["Q"]; pf.r = p["R"]
            pf.p0 = p["P0"]; pf.x0 = p["x0"]; pf.seed_first = p["seed_first"]
            pf.stable_step = p["stable_step"]; pf.stable_count = p["stable_count"]
            pf.lockout_n = p["lockout_n"]; pf.motion_band = p["motion_band"]
            pf.motion_count = p["motion_count"]; pf.zero_band = p["zero_band"]
            pf.zero_rate = p["zero_rate"]
            _check_init(sig_chain_init_f(&self.f, &pf), "Chain")

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
        if self.fixed:
            xq = _codes(x)
            n = xq.shape[0]
        else:
            xf = _as_float(x)
            n = xf.shape[0]
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
        _ref._finite("offset", offset)
        if self.fixed:
            sig_chain_set_offset_q(&self.q, _ref._round_int32("offset", offset * 128))
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
    def x(self):
        return self.q.kf.x / 128.0 if self.fixed else self.f.kf.x

    @property
    def K(self):
        return (1073741824 - self.q.kf.y) / 1073741824.0 if self.fixed else self.f.kf.k

    @property
    def P(self):
        if not self.fixed:
            return self.f.kf.p
        if self.q.kf.phase == 0:
            return self.q.kf.p0 / 65536.0 * self.R
        return self.K * self.R

    @property
    def innovation(self):
        return self.q.kf.innov / 128.0 if self.fixed else self.f.kf.innov

    @property
    def Dc(self):
        return float(self.q.limit.dc if self.fixed else self.f.limit.dc)

    @property
    def window_count(self):
        return self.q.ap.count if self.fixed else self.f.ap.count
