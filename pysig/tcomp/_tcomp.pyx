# cython: language_level=3
"""Cython bridge to csrc/tcomp/sig_poly.c and sig_tcomp.c: the
temperature compensation the firmware runs, over numpy arrays, and its C
image loader (sig_tcomp_load_image)."""
import numpy as np
cimport numpy as cnp
from libc.stdint cimport int16_t, int32_t, uint8_t, uint16_t, uint32_t

from ..errors import ModelFileError, NonFiniteError, RangeError
from ..status import Status, describe

from ._axes cimport apply_axes, sig_tcomp_q

cnp.import_array()

cdef extern from "sig_types.h":
    ctypedef double sig_real
    ctypedef int16_t sig_status

cdef extern from "sig_poly.h":
    int32_t sig_mul_q15_32x16(int32_t a, int16_t u) nogil
    sig_status sig_poly_horner_q15(const int32_t *c, uint8_t order, int16_t u, int32_t *out) nogil
    sig_status sig_poly_horner_f(const sig_real *c, uint8_t order, sig_real u, sig_real *out) nogil

cdef extern from "sig_tcomp.h":
    ctypedef struct sig_tcomp_f:
        uint8_t n_axes
    sig_status sig_tcomp_init_q(sig_tcomp_q *m, uint8_t n_axes, uint8_t order, const int32_t *coef,
                                const uint8_t *q, int16_t t_lo, int16_t t_hi, int16_t t_center,
                                int16_t t0, int16_t u_mul, uint8_t u_shift)
    sig_status sig_tcomp_scale_q(const sig_tcomp_q *m, int16_t t, int16_t *u) nogil
    sig_status sig_tcomp_delta_q(const sig_tcomp_q *m, uint8_t axis, int16_t t, int32_t *delta) nogil
    sig_status sig_tcomp_init_f(sig_tcomp_f *m, uint8_t n_axes, uint8_t order, const sig_real *coef,
                                sig_real t_lo, sig_real t_hi, sig_real center, sig_real inv_scale)
    sig_status sig_tcomp_apply_f(const sig_tcomp_f *m, sig_real t, const sig_real *inp, sig_real *out) nogil
    sig_status sig_tcomp_load_image(sig_tcomp_q *m, const uint8_t *image, size_t len)


def mul_q15(int32_t a, int16_t u):
    return sig_mul_q15_32x16(a, u)


def _coefficients(coef, dtype, what):
    """The polynomial's coefficients as one contiguous `dtype` array (at least one)."""
    c = np.ascontiguousarray(coef, dtype=dtype)
    if c.ndim != 1 or c.shape[0] < 1:
        raise RangeError(f"{what}: no coefficients")
    return c


def horner_q15(coef, int16_t u):
    """(value, status) of sig_poly_horner_q15."""
    cdef const int32_t[::1] c = _coefficients(coef, np.int32, "horner_q15")
    cdef int32_t out = 0
    st = sig_poly_horner_q15(&c[0], <uint8_t>(c.shape[0] - 1), u, &out)
    return out, st


def horner_f(coef, double u):
    """(value, status) of sig_poly_horner_f."""
    cdef const double[::1] c = _coefficients(coef, np.float64, "horner_f")
    cdef double out = 0.0
    st = sig_poly_horner_f(&c[0], <uint8_t>(c.shape[0] - 1), u, &out)
    return out, st


cdef class TcompQ:
    """The fixed-point model of sig_tcomp.h (temperature int16 in 0.01 °C,
    int16 readings).  Build with TcompQ.from_fields(...) or
    TcompQ.from_image(bytes) (the C loader)."""
    cdef sig_tcomp_q m

    @staticmethod
    def from_fields(coef, q, int t_lo, int t_hi, int t_center, int t0, int u_mul, int u_shift):
        cdef TcompQ self = TcompQ.__new__(TcompQ)
        rows = [list(r) for r in coef]
        n_axes, order = len(rows), len(rows[0]) - 1 if rows else 0
        if not 1 <= n_axes <= 3 or not 1 <= order <= 8 or any(len(r) != order + 1 for r in rows):
            raise RangeError(f"TcompQ: {n_axes} axes of order {order} (need 1..3 axes, order 1..8)")
        flat = [int(v) for r in rows for v in r]
        if any(not -(1 << 31) <= v < (1 << 31) for v in flat) or len(q) != n_axes:
            raise RangeError("TcompQ: coefficients must be int32, one q per axis")
        for name, v in (("t_lo", t_lo), ("t_hi", t_hi), ("t_center", t_center), ("t0", t0), ("u_mul", u_mul)):
            if not -32768 <= v <= 32767:
                raise RangeError(f"TcompQ: {name} = {v} outside int16")
        if not 0 <= u_shift <= 255 or any(not 0 <= int(v) <= 255 for v in q):
            raise RangeError("TcompQ: u_shift and q must fit uint8")
        cdef cnp.ndarray[cnp.int32_t, ndim=1] c = np.array(flat, dtype=np.int32)
        cdef cnp.ndarray[cnp.uint8_t, ndim=1] qa = np.array([int(v) for v in q], dtype=np.uint8)
        st = sig_tcomp_init_q(&self.m, <uint8_t>n_axes, <uint8_t>order, &c[0], &qa[0], <int16_t>t_lo,
                              <int16_t>t_hi, <int16_t>t_center, <int16_t>t0, <int16_t>u_mul, <uint8_t>u_shift)
        if st != 0:
            raise RangeError(f"TcompQ: sig_tcomp_init_q rejected the parameters (status {st})")
        return self

    @staticmethod
    def from_image(data, where="image"):
        cdef TcompQ self = TcompQ.__new__(TcompQ)
        cdef const uint8_t[::1] b = bytes(data) + b"\0"
        st = sig_tcomp_load_image(&self.m, &b[0], len(data))
        if st != 0:
            text = describe(st, "offset-polynomial")
            raise ModelFileError(f"{where}: the C loader rejected the image: {text}")
        return self

    @property
    def n_axes(self):
        return self.m.n_axes

    @property
    def order(self):
        return self.m.order

    @property
    def no_overflow(self):
        """True when init proved no sum can overflow (fast, unsaturated Horner)."""
        return bool(self.m.no_overflow)

    def fields(self):
        n, k = self.m.n_axes, self.m.order
        return {"coef": [[self.m.coef[a][i] for i in range(k + 1)] for a in range(n)],
                "q": [self.m.q[a] for a in range(n)], "t_lo": self.m.t_lo, "t_hi": self.m.t_hi,
                "t_center": self.m.t_center, "t0": self.m.t0, "u_mul": self.m.u_mul,
                "u_shift": self.m.u_shift}

    def scale(self, temp):
        """(u Q0.15 int16 array, status array) for int16 temperatures."""
        cdef Py_ssize_t i
        cdef cnp.ndarray[cnp.int16_t, ndim=1] t = _int16(temp, "temperature")
        cdef cnp.ndarray[cnp.int16_t, ndim=1] u = np.zeros(t.shape[0], dtype=np.int16)
        cdef cnp.ndarray[cnp.int16_t, ndim=1] st = np.empty(t.shape[0], dtype=np.int16)
        with nogil:
            for i in range(t.shape[0]):
                st[i] = sig_tcomp_scale_q(&self.m, t[i], &u[i])
        return u, st

    def delta(self, int axis, temp):
        """(int32 delta in Q(q[axis]) array, status array)."""
        if not 0 <= axis < self.m.n_axes:
            raise RangeError(f"TcompQ.delta: axis {axis} outside 0..{self.m.n_axes - 1}")
        cdef Py_ssize_t i
        cdef uint8_t ax = <uint8_t>axis
        cdef cnp.ndarray[cnp.int16_t, ndim=1] t = _int16(temp, "temperature")
        cdef cnp.ndarray[cnp.int32_t, ndim=1] d = np.zeros(t.shape[0], dtype=np.int32)
        cdef cnp.ndarray[cnp.int16_t, ndim=1] st = np.empty(t.shape[0], dtype=np.int16)
        with nogil:
            for i in range(t.shape[0]):
                st[i] = sig_tcomp_delta_q(&self.m, ax, t[i], &d[i])
        return d, st

    def apply(self, temp, readings):
        """sig_tcomp_apply_q per sample: temp int16 (n,), readings int16
        (n, n_axes) -> (int16 (n, n_axes), status (n,))."""
        t = _int16(temp, "temperature")
        x = _int16_readings(readings, self.m.n_axes, t.shape[0], "TcompQ.apply")
        return apply_axes(&self.m, t.view(np.uint16), x)


cdef class TcompF:
    """The float model of sig_tcomp.h (temperature in °C, host build in double)."""
    cdef sig_tcomp_f m
    cdef int n_axes

    def __init__(self, coef, double t_lo, double t_hi, double center, double inv_scale):
        rows = [list(r) for r in coef]
        n_axes, order = len(rows), len(rows[0]) - 1 if rows else 0
        if not 1 <= n_axes <= 3 or not 1 <= order <= 8 or any(len(r) != order + 1 for r in rows):
            raise RangeError(f"TcompF: {n_axes} axes of order {order} (need 1..3 axes, order 1..8)")
        cdef cnp.ndarray[cnp.float64_t, ndim=1] c = np.array([float(v) for r in rows for v in r])
        st = sig_tcomp_init_f(&self.m, <uint8_t>n_axes, <uint8_t>order, &c[0], t_lo, t_hi, center, inv_scale)
        if st == Status.ERR_NONFINITE:
            raise NonFiniteError("TcompF: non-finite parameter or coefficient")
        if st != 0:
            raise RangeError(f"TcompF: sig_tcomp_init_f rejected the parameters (status {st})")
        self.n_axes = n_axes

    def apply(self, temp, readings):
        """(float64 (n, n_axes), status (n,)); rows with a NaN temperature or
        reading get status -2 and NaN outputs."""
        cdef cnp.ndarray[cnp.float64_t, ndim=1] t = np.ascontiguousarray(np.ravel(temp), dtype=np.float64)
        x_in = np.asarray(readings, dtype=np.float64)
        if x_in.ndim == 1 and self.n_axes == 1:
            x_in = x_in[:, None]
        if x_in.ndim != 2 or x_in.shape[1] != self.n_axes or x_in.shape[0] != t.shape[0]:
            raise RangeError(f"TcompF.apply: readings must be ({t.shape[0]}, {self.n_axes})")
        cdef cnp.ndarray[cnp.float64_t, ndim=2] x = np.ascontiguousarray(x_in)
        cdef Py_ssize_t n = t.shape[0], i
        cdef cnp.ndarray[cnp.float64_t, ndim=2] out = np.full((n, self.n_axes), np.nan)
        cdef cnp.ndarray[cnp.int16_t, ndim=1] st = np.empty(n, dtype=np.int16)
        with nogil:
            for i in range(n):
                st[i] = sig_tcomp_apply_f(&self.m, t[i], &x[i, 0], &out[i, 0])
        return out, st


def _int16(values, what):
    arr = np.asarray(values)
    flat = np.ravel(arr)
    if flat.size and (not np.all(np.isfinite(flat.astype(float))) or np.any(flat != np.round(flat))
                      or flat.min() < -32768 or flat.max() > 32767):
        raise RangeError(f"{what}: values must be integers within int16")
    return np.ascontiguousarray(flat, dtype=np.int16)


def _int16_readings(readings, n_axes, n, what):
    """Readings as a contiguous int16 (n, n_axes) array (a 1-D array for one
    axis), or a RangeError naming `what`."""
    x_in = np.asarray(readings)
    if x_in.ndim == 1 and n_axes == 1:
        x_in = x_in[:, None]
    if x_in.ndim != 2 or x_in.shape[1] != n_axes or x_in.shape[0] != n:
        raise RangeError(f"{what}: readings must be ({n}, {n_axes})")
    return np.ascontiguousarray(_int16(x_in, "reading").reshape(x_in.shape))
