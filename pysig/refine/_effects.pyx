# cython: language_level=3
"""Cython bridge to csrc/refine/ (sig_effects.h): the on-device refinement effects
over numpy arrays, with the very C code the firmware runs.  Stateful forms
take and return `state` (a tuple) so a long signal can be processed in
pieces with the same result (scipy.signal's zi/zf)."""
import numpy as np
cimport numpy as cnp
from libc.stdint cimport int8_t, int16_t, int32_t, uint8_t
from libcpp cimport bool as cbool

from ..errors import NonFiniteError, RangeError

cnp.import_array()

cdef extern from "sig_types.h":
    ctypedef double sig_real
    ctypedef int16_t sig_status

cdef extern from "sig_tcomp.h":
    ctypedef struct sig_tcomp_q:
        pass
    sig_status sig_tcomp_init_q(sig_tcomp_q *m, uint8_t n_axes, uint8_t order,
                                const int32_t *coef, const uint8_t *q,
                                int16_t t_lo, int16_t t_hi, int16_t t_center, int16_t t0,
                                int16_t u_mul, uint8_t u_shift)

cdef extern from "sig_effects.h":
    ctypedef struct sig_lag_q:
        int32_t z
        int32_t alpha_q16
        uint8_t frac
        cbool primed
    ctypedef struct sig_lag_f:
        sig_real z
        sig_real alpha
        cbool primed
    ctypedef struct sig_hyst_q:
        int32_t p
        int32_t k_q16
        int16_t width
        cbool primed
    ctypedef struct sig_hyst_f:
        sig_real p, width, k
        cbool primed
    ctypedef struct sig_creep_q:
        sig_lag_q lag
        int32_t k_q16
    ctypedef struct sig_creep_f:
        sig_lag_f lag
        sig_real k
    ctypedef struct sig_gain_q:
        pass
    ctypedef struct sig_gain_f:
        pass
    ctypedef struct sig_nonlin_q:
        pass
    ctypedef struct sig_nonlin_f:
        pass
    ctypedef struct sig_cross_q:
        pass
    ctypedef struct sig_cross_f:
        pass
    ctypedef struct sig_refined_q:
        pass
    sig_status sig_refined_init_q(sig_refined_q *r, const sig_tcomp_q *tcomp, uint8_t axis,
                                  const sig_lag_q *lag, const sig_hyst_q *hyst, const sig_gain_q *gain)
    sig_status sig_refined_step_q(sig_refined_q *r, int16_t t, int16_t y, int32_t *out_q16) nogil
    sig_status sig_lag_init_q(sig_lag_q *s, int32_t alpha_q16, uint8_t frac)
    sig_status sig_lag_step_q(sig_lag_q *s, int32_t x, int32_t *out) nogil
    sig_status sig_lag_init_f(sig_lag_f *s, sig_real alpha)
    sig_status sig_lag_step_f(sig_lag_f *s, sig_real x, sig_real *out) nogil
    sig_status sig_hyst_init_q(sig_hyst_q *s, int16_t width, int32_t k_q16, int8_t start)
    sig_status sig_hyst_step_q(sig_hyst_q *s, int16_t t, int16_t *branch, int32_t *contribution) nogil
    sig_status sig_hyst_init_f(sig_hyst_f *s, sig_real width, sig_real k, int8_t start)
    sig_status sig_hyst_step_f(sig_hyst_f *s, sig_real t, sig_real *branch, sig_real *contribution) nogil
    sig_status sig_creep_init_q(sig_creep_q *s, int32_t alpha_q16, uint8_t frac, int32_t k_q16)
    sig_status sig_creep_step_q(sig_creep_q *s, int32_t x, int32_t *contribution, int32_t *corrected) nogil
    sig_status sig_creep_init_f(sig_creep_f *s, sig_real alpha, sig_real k)
    sig_status sig_creep_step_f(sig_creep_f *s, sig_real x, sig_real *contribution, sig_real *corrected) nogil
    sig_status sig_gain_init_q(sig_gain_q *g, const int32_t *coef, uint8_t order)
    sig_status sig_gain_apply_q(const sig_gain_q *g, int16_t u_q15, int32_t x, int32_t *out) nogil
    sig_status sig_gain_init_f(sig_gain_f *g, const sig_real *coef, uint8_t order)
    sig_status sig_gain_apply_f(const sig_gain_f *g, sig_real u, sig_real x, sig_real *out) nogil
    sig_status sig_nonlin_init_q(sig_nonlin_q *m, const int32_t *coef, uint8_t order,
                                 int32_t center, int32_t k_q16, uint8_t shift)
    sig_status sig_nonlin_apply_q(const sig_nonlin_q *m, int32_t x, int32_t *out) nogil
    sig_status sig_nonlin_init_f(sig_nonlin_f *m, const sig_real *coef, uint8_t order,
                                 sig_real center, sig_real inv_scale)
    sig_status sig_nonlin_apply_f(const sig_nonlin_f *m, sig_real x, sig_real *out) nogil
    sig_status sig_cross_init_q(sig_cross_q *c, const int32_t *k_q16, uint8_t n)
    sig_status sig_cross_apply_q(const sig_cross_q *c, int32_t x, const int32_t *others, int32_t *out) nogil
    sig_status sig_cross_init_f(sig_cross_f *c, const sig_real *k, uint8_t n)
    sig_status sig_cross_apply_f(const sig_cross_f *c, sig_real x, const sig_real *others, sig_real *out) nogil


def _i32(a):
    return np.ascontiguousarray(np.ravel(a), dtype=np.int32)


def _f64(a):
    return np.ascontiguousarray(np.ravel(a), dtype=np.float64)


ctypedef fused lag_like_q:
    sig_lag_q
    sig_creep_q

ctypedef fused stateful_f:
    sig_lag_f
    sig_hyst_f
    sig_creep_f


cdef inline sig_status _step_q(lag_like_q *s, int32_t x, int32_t *a, int32_t *b) noexcept nogil:
    if lag_like_q is sig_lag_q:
        return sig_lag_step_q(s, x, a)
    else:
        return sig_creep_step_q(s, x, a, b)


cdef inline sig_status _step_f(stateful_f *s, double x, double *a, double *b) noexcept nogil:
    if stateful_f is sig_lag_f:
        return sig_lag_step_f(s, x, a)
    elif stateful_f is sig_hyst_f:
        return sig_hyst_step_f(s, x, a, b)
    else:
        return sig_creep_step_f(s, x, a, b)


cdef tuple _run_q(lag_like_q *s, x):
    """The fixed-point lag-like effects over int32 x: (first output, second
    output (zeros for the lag), status per sample)."""
    cdef cnp.ndarray[cnp.int32_t, ndim=1] xs = _i32(x)
    cdef Py_ssize_t n = xs.shape[0], i
    cdef cnp.ndarray[cnp.int32_t, ndim=1] a = np.zeros(n, dtype=np.int32)
    cdef cnp.ndarray[cnp.int32_t, ndim=1] b = np.zeros(n, dtype=np.int32)
    cdef cnp.ndarray[cnp.int16_t, ndim=1] st = np.empty(n, dtype=np.int16)
    with nogil:
        for i in range(n):
            st[i] = _step_q(s, xs[i], &a[i], &b[i])
    return a, b, st


cdef tuple _run_f(stateful_f *s, x, what):
    """A float effect over float64 x: (first output, second output); the
    first input the C refuses raises NonFiniteError naming its index."""
    cdef cnp.ndarray[cnp.float64_t, ndim=1] xs = _f64(x)
    cdef Py_ssize_t n = xs.shape[0], i = 0
    cdef cnp.ndarray[cnp.float64_t, ndim=1] a = np.empty(n, dtype=np.float64)
    cdef cnp.ndarray[cnp.float64_t, ndim=1] b = np.empty(n, dtype=np.float64)
    cdef sig_status rc = 0
    with nogil:
        for i in range(n):
            rc = _step_f(s, xs[i], &a[i], &b[i])
            if rc < 0:
                break
    if rc < 0:
        raise NonFiniteError(f"{what} at index {i}")
    return a, b


def lag_q(x, int alpha_q16, int frac, state=None):
    """sig_lag_step_q over int32 `x`.  Returns (out int32, status int16, state)."""
    cdef sig_lag_q s
    if not (0 <= frac <= 255) or sig_lag_init_q(&s, alpha_q16, <uint8_t>frac) != 0:
        raise RangeError(f"lag: alpha_q16={alpha_q16} (1..65536), frac={frac} (0..16) rejected")
    if state is not None:
        s.z, s.primed = state
    out, _, st = _run_q(&s, x)
    return out, st, (int(s.z), bool(s.primed))


def lag_f(x, double alpha, state=None):
    """sig_lag_step_f over float64 `x`.  Returns (out, state)."""
    cdef sig_lag_f s
    if sig_lag_init_f(&s, alpha) != 0:
        raise RangeError(f"lag: alpha={alpha} outside (0, 1]")
    if state is not None:
        s.z, s.primed = state
    out, _ = _run_f(&s, x, "lag: non-finite input")
    return out, (float(s.z), bool(s.primed))


def hyst_q(t, int width, int k_q16, int start=0, state=None):
    """sig_hyst_step_q over int16 temperatures (0.01 °C).
    Returns (branch int16, contribution int32, status int16, state)."""
    cdef sig_hyst_q s
    if (not (-32768 <= width <= 32767) or start not in (-1, 0, 1)
            or sig_hyst_init_q(&s, <int16_t>width, k_q16, <int8_t>start) != 0):
        raise RangeError(f"hysteresis: width={width} must be 1..32767, start={start} in -1, 0, 1")
    if state is not None:
        s.p, s.primed = state
    cdef Py_ssize_t i
    cdef cnp.ndarray[cnp.int16_t, ndim=1] ts = np.ascontiguousarray(np.ravel(t), dtype=np.int16)
    cdef cnp.ndarray[cnp.int16_t, ndim=1] br = np.zeros(ts.shape[0], dtype=np.int16)
    cdef cnp.ndarray[cnp.int32_t, ndim=1] c = np.zeros(ts.shape[0], dtype=np.int32)
    cdef cnp.ndarray[cnp.int16_t, ndim=1] st = np.empty(ts.shape[0], dtype=np.int16)
    with nogil:
        for i in range(ts.shape[0]):
            st[i] = sig_hyst_step_q(&s, ts[i], &br[i], &c[i])
    return br, c, st, (int(s.p), bool(s.primed))


def hyst_f(t, double width, double k, int start=0, state=None):
    """sig_hyst_step_f.  Returns (branch, contribution, state)."""
    cdef sig_hyst_f s
    if start not in (-1, 0, 1) or sig_hyst_init_f(&s, width, k, <int8_t>start) != 0:
        raise RangeError(f"hysteresis: width={width} must be finite and > 0, k={k} finite, "
                         f"start={start} in -1, 0, 1")
    if state is not None:
        s.p, s.primed = state
    br, c = _run_f(&s, t, "hysteresis: non-finite temperature")
    return br, c, (float(s.p), bool(s.primed))


def creep_q(x, int alpha_q16, int frac, int k_q16, state=None):
    """sig_creep_step_q.  Returns (contribution, corrected, status, state)."""
    cdef sig_creep_q s
    if not (0 <= frac <= 255) or sig_creep_init_q(&s, alpha_q16, <uint8_t>frac, k_q16) != 0:
        raise RangeError(f"creep: alpha_q16={alpha_q16} (1..65536), frac={frac} (0..16) rejected")
    if state is not None:
        s.lag.z, s.lag.primed = state
    c, y, st = _run_q(&s, x)
    return c, y, st, (int(s.lag.z), bool(s.lag.primed))


def creep_f(x, double alpha, double k, state=None):
    """sig_creep_step_f.  Returns (contribution, corrected, state)."""
    cdef sig_creep_f s
    if sig_creep_init_f(&s, alpha, k) != 0:
        raise RangeError(f"creep: alpha={alpha} outside (0, 1] or k={k} not finite")
    if state is not None:
        s.lag.z, s.lag.primed = state
    c, y = _run_f(&s, x, "creep: non-finite input")
    return c, y, (float(s.lag.z), bool(s.lag.primed))


ctypedef fused applied_q:
    sig_gain_q
    sig_nonlin_q
    sig_cross_q

ctypedef fused applied_f:
    sig_gain_f
    sig_nonlin_f
    sig_cross_f


def _side_input(side, dtype, Py_ssize_t n, what):
    """The second input of an effect, one entry or row per reading (the
    gain's temperatures, the cross-axis rows of other axes), as a contiguous
    `dtype` array; `what` names it in the error when its length is not `n`
    (`"gain: {m} temperatures"`)."""
    arr = np.ascontiguousarray(side, dtype=dtype)
    if arr.shape[0] != n:
        raise RangeError(what.format(m=arr.shape[0]) + f" for {n} readings")
    return arr


cdef tuple _apply_q(applied_q *m, x, side, what):
    """A stateless fixed effect over int32 x: (out int32, status int16 per
    reading); `side` as _side_input takes it (None for the nonlinearity)."""
    cdef cnp.ndarray[cnp.int32_t, ndim=1] xs = _i32(x)
    cdef Py_ssize_t n = xs.shape[0], i
    cdef cnp.ndarray[cnp.int16_t, ndim=1] us
    cdef cnp.ndarray[cnp.int32_t, ndim=2] os
    if applied_q is sig_gain_q:
        us = _side_input(np.ravel(side), np.int16, n, what)
    elif applied_q is sig_cross_q:
        os = _side_input(side, np.int32, n, what)
    cdef cnp.ndarray[cnp.int32_t, ndim=1] out = np.zeros(n, dtype=np.int32)
    cdef cnp.ndarray[cnp.int16_t, ndim=1] st = np.empty(n, dtype=np.int16)
    with nogil:
        for i in range(n):
            if applied_q is sig_gain_q:
                st[i] = sig_gain_apply_q(m, us[i], xs[i], &out[i])
            elif applied_q is sig_nonlin_q:
                st[i] = sig_nonlin_apply_q(m, xs[i], &out[i])
            else:
                st[i] = sig_cross_apply_q(m, xs[i], &os[i, 0], &out[i])
    return out, st


cdef _apply_f(applied_f *m, x, rows, what, refused):
    """A stateless float effect over float64 x: the output; `rows` the second
    input as a 2-D array, one row per reading (None for the nonlinearity); the
    first reading the C refuses raises NonFiniteError (`refused`, at its index)."""
    cdef cnp.ndarray[cnp.float64_t, ndim=1] xs = _f64(x)
    cdef cnp.ndarray[cnp.float64_t, ndim=2] side
    if applied_f is not sig_nonlin_f:
        side = _side_input(rows, np.float64, xs.shape[0], what)
    cdef cnp.ndarray[cnp.float64_t, ndim=1] out = np.empty(xs.shape[0], dtype=np.float64)
    cdef double y
    cdef sig_status rc
    cdef Py_ssize_t i
    for i in range(xs.shape[0]):
        if applied_f is sig_gain_f:
            rc = sig_gain_apply_f(m, side[i, 0], xs[i], &y)
        elif applied_f is sig_nonlin_f:
            rc = sig_nonlin_apply_f(m, xs[i], &y)
        else:
            rc = sig_cross_apply_f(m, xs[i], &side[i, 0], &y)
        if rc < 0:
            raise NonFiniteError(f"{refused} at index {i}")
        out[i] = y
    return out


def gain_q(coef, u, x):
    """sig_gain_apply_q: out = x * G(u), G Q16.16 by Horner in Q15 u."""
    cdef sig_gain_q g
    cdef cnp.ndarray[cnp.int32_t, ndim=1] cs = _i32(coef)
    if cs.shape[0] < 1 or cs.shape[0] > 9 or sig_gain_init_q(&g, &cs[0], <uint8_t>(cs.shape[0] - 1)) != 0:
        raise RangeError(f"gain: {cs.shape[0]} coefficients, need 1..9")
    return _apply_q(&g, x, u, "gain: {m} temperatures")


def gain_f(coef, u, x):
    cdef sig_gain_f g
    cdef cnp.ndarray[cnp.float64_t, ndim=1] cs = _f64(coef)
    if cs.shape[0] < 1 or cs.shape[0] > 9 or sig_gain_init_f(&g, &cs[0], <uint8_t>(cs.shape[0] - 1)) != 0:
        raise RangeError(f"gain: {cs.shape[0]} finite coefficients needed, 1..9")
    return _apply_f(&g, x, np.reshape(u, (-1, 1)), "gain: {m} temperatures", "gain: non-finite input or result")


def nonlin_q(coef, int center, int k_q16, int shift, x):
    cdef sig_nonlin_q m
    cdef cnp.ndarray[cnp.int32_t, ndim=1] cs = _i32(coef)
    if (cs.shape[0] < 1 or cs.shape[0] > 9 or not (0 <= shift <= 255)
            or sig_nonlin_init_q(&m, &cs[0], <uint8_t>(cs.shape[0] - 1), center, k_q16, <uint8_t>shift) != 0):
        raise RangeError(f"nonlinearity: {cs.shape[0]} coefficients, k_q16={k_q16}, shift={shift} rejected")
    return _apply_q(&m, x, None, None)


def nonlin_f(coef, double center, double inv_scale, x):
    cdef sig_nonlin_f m
    cdef cnp.ndarray[cnp.float64_t, ndim=1] cs = _f64(coef)
    if (cs.shape[0] < 1 or cs.shape[0] > 9
            or sig_nonlin_init_f(&m, &cs[0], <uint8_t>(cs.shape[0] - 1), center, inv_scale) != 0):
        raise RangeError("nonlinearity: bad coefficients or scaling")
    return _apply_f(&m, x, None, None, "nonlinearity: non-finite input")


def cross_q(k_q16, x, others):
    """sig_cross_apply_q; `others` shape (n, n_axes)."""
    cdef sig_cross_q c
    cdef cnp.ndarray[cnp.int32_t, ndim=1] ks = _i32(k_q16)
    if ks.shape[0] < 1 or ks.shape[0] > 3 or sig_cross_init_q(&c, &ks[0], <uint8_t>ks.shape[0]) != 0:
        raise RangeError(f"cross-axis: {ks.shape[0]} coefficients, need 1..3")
    return _apply_q(&c, x, np.reshape(others, (-1, ks.shape[0])), "cross-axis: {m} rows of other axes")


def cross_f(k, x, others):
    cdef sig_cross_f c
    cdef cnp.ndarray[cnp.float64_t, ndim=1] ks = _f64(k)
    if ks.shape[0] < 1 or ks.shape[0] > 3 or sig_cross_init_f(&c, &ks[0], <uint8_t>ks.shape[0]) != 0:
        raise RangeError(f"cross-axis: {ks.shape[0]} finite coefficients, need 1..3")
    return _apply_f(&c, x, np.reshape(others, (-1, ks.shape[0])), "cross-axis: {m} rows of other axes",
                    "cross-axis: non-finite input")


def refined_q(t, y, offset, lag=None, hyst=None, gain=None):
    """sig_refined_step_q over int16 temperatures t (0.01 °C) and readings y.

    offset: dict coef (int32, one axis, ascending powers of u), q, t_lo, t_hi,
    t_center, t0, u_mul, u_shift (the sig_tcomp_q fields); lag: alpha_q16 or
    None; hyst: (width, k_q16, start) or None; gain: Q16 coefficients or None.
    Returns (corrected readings int32 Q16.16, status int16)."""
    cdef sig_tcomp_q m
    cdef sig_lag_q lg
    cdef sig_hyst_q hy
    cdef sig_gain_q gn
    cdef sig_refined_q r
    cdef cnp.ndarray[cnp.int32_t, ndim=1] c = _i32(offset["coef"])
    cdef cnp.ndarray[cnp.uint8_t, ndim=1] qa = np.array([int(offset["q"])], dtype=np.uint8)
    cdef cnp.ndarray[cnp.int32_t, ndim=1] gc
    if c.shape[0] < 2 or c.shape[0] > 9 or sig_tcomp_init_q(
            &m, 1, <uint8_t>(c.shape[0] - 1), &c[0], &qa[0], <int16_t>offset["t_lo"],
            <int16_t>offset["t_hi"], <int16_t>offset["t_center"], <int16_t>offset["t0"],
            <int16_t>offset["u_mul"], <uint8_t>offset["u_shift"]) != 0:
        raise RangeError(f"refined: sig_tcomp_init_q rejected the offset model {offset}")
    if lag is not None and sig_lag_init_q(&lg, int(lag), 16) != 0:
        raise RangeError(f"refined: lag alpha_q16={lag} outside 1..65536")
    if hyst is not None and (hyst[2] not in (-1, 0, 1) or not (1 <= hyst[0] <= 32767)
                             or sig_hyst_init_q(&hy, <int16_t>hyst[0], int(hyst[1]), <int8_t>hyst[2]) != 0):
        raise RangeError(f"refined: hysteresis {hyst} rejected")
    if gain is not None:
        gc = _i32(gain)
        if gc.shape[0] < 1 or gc.shape[0] > 9 or sig_gain_init_q(&gn, &gc[0], <uint8_t>(gc.shape[0] - 1)) != 0:
            raise RangeError(f"refined: gain polynomial of {gc.shape[0]} coefficients rejected")
    if sig_refined_init_q(&r, &m, 0, &lg if lag is not None else NULL,
                          &hy if hyst is not None else NULL, &gn if gain is not None else NULL) != 0:
        raise RangeError("refined: sig_refined_init_q rejected the model")
    cdef cnp.ndarray[cnp.int16_t, ndim=1] ts = np.ascontiguousarray(np.ravel(t), dtype=np.int16)
    cdef cnp.ndarray[cnp.int16_t, ndim=1] ys = np.ascontiguousarray(np.ravel(y), dtype=np.int16)
    cdef Py_ssize_t n = ts.shape[0], i
    if ys.shape[0] != n:
        raise RangeError(f"refined: {n} temperatures for {ys.shape[0]} readings")
    cdef cnp.ndarray[cnp.int32_t, ndim=1] out = np.zeros(n, dtype=np.int32)
    cdef cnp.ndarray[cnp.int16_t, ndim=1] st = np.empty(n, dtype=np.int16)
    with nogil:
        for i in range(n):
            st[i] = sig_refined_step_q(&r, ts[i], ys[i], &out[i])
    return out, st
