# cython: language_level=3
"""Cython bridge to csrc/weigh/sig_scale.c: apply a stored scale calibration
(counts -> mass) over numpy arrays with the C code the firmware runs."""
import numpy as np
cimport numpy as cnp
from libc.stdint cimport int16_t, int32_t, uint8_t

from ..errors import NonFiniteError, RangeError
from ..status import Status

cnp.import_array()

cdef extern from "sig_types.h":
    ctypedef double sig_real
    ctypedef int16_t sig_status

cdef extern from "sig_scale.h":
    ctypedef struct sig_scale_q16:
        pass
    ctypedef struct sig_scale_f:
        pass
    sig_status sig_scale_init_q16(sig_scale_q16 *s, int32_t offset, int32_t gain_mant, uint8_t gain_shift)
    sig_status sig_scale_apply_q16(const sig_scale_q16 *s, int32_t counts, int32_t *mass_q16) nogil
    sig_status sig_scale_init_f(sig_scale_f *s, sig_real offset, sig_real gain)
    sig_status sig_scale_apply_f(const sig_scale_f *s, sig_real counts, sig_real *mass) nogil

INT32_MIN = -(1 << 31)
INT32_MAX = (1 << 31) - 1


cdef class ScaleQ16:
    """Fixed-point calibration: Q16.16 mass = floor((counts - offset) *
    gain_mant / 2^gain_shift), saturated (see csrc/include/sig_scale.h)."""
    cdef sig_scale_q16 s
    cdef readonly int offset, gain_mant, gain_shift

    def __init__(self, offset, gain_mant, gain_shift):
        if not (INT32_MIN <= offset <= INT32_MAX and INT32_MIN <= gain_mant <= INT32_MAX
                and 0 <= gain_shift <= 255):
            raise RangeError(f"ScaleQ16: offset {offset}, gain_mant {gain_mant} or gain_shift "
                             f"{gain_shift} outside its C type")
        if sig_scale_init_q16(&self.s, <int32_t>offset, <int32_t>gain_mant, <uint8_t>gain_shift) != 0:
            raise RangeError(f"ScaleQ16: sig_scale_init_q16 rejected gain_mant={gain_mant}, "
                             f"gain_shift={gain_shift} (need gain_mant != 0, gain_shift <= 62)")
        self.offset, self.gain_mant, self.gain_shift = offset, gain_mant, gain_shift

    def apply(self, counts):
        """int32 ADC codes -> (int32 Q16.16 masses, bool saturated flags)."""
        cdef Py_ssize_t i
        cdef cnp.ndarray[cnp.int32_t, ndim=1] x = np.ascontiguousarray(np.ravel(counts), dtype=np.int32)
        if not np.array_equal(x, np.ravel(counts)):
            raise RangeError("ScaleQ16.apply: counts must be integers within int32")
        cdef cnp.ndarray[cnp.int32_t, ndim=1] out = np.zeros(x.shape[0], dtype=np.int32)
        cdef cnp.ndarray[cnp.uint8_t, ndim=1] sat = np.zeros(x.shape[0], dtype=np.uint8)
        with nogil:
            for i in range(x.shape[0]):
                sat[i] = sig_scale_apply_q16(&self.s, x[i], &out[i]) != 0
        return out, sat.astype(bool)


cdef class ScaleF:
    """Float calibration: mass = (counts - offset) * gain."""
    cdef sig_scale_f s
    cdef readonly double offset, gain

    def __init__(self, double offset, double gain):
        cdef sig_status st = sig_scale_init_f(&self.s, offset, gain)
        if st == Status.ERR_NONFINITE:
            raise NonFiniteError(f"ScaleF: offset {offset!r} and gain {gain!r} must be finite")
        if st != 0:
            raise RangeError(f"ScaleF: gain must be non-zero, got {gain!r}")
        self.offset, self.gain = offset, gain

    def apply(self, counts):
        """Float counts -> float64 masses.  Raises NonFiniteError naming the
        first non-finite index."""
        cdef cnp.ndarray[cnp.float64_t, ndim=1] x = np.ascontiguousarray(np.ravel(counts), dtype=np.float64)
        cdef Py_ssize_t n = x.shape[0], i, bad = -1
        cdef cnp.ndarray[cnp.float64_t, ndim=1] out = np.empty(n, dtype=np.float64)
        cdef double y
        with nogil:
            for i in range(n):
                y = 0.0
                if sig_scale_apply_f(&self.s, x[i], &y) != 0:
                    bad = i
                    break
                out[i] = y
        if bad >= 0:
            raise NonFiniteError(f"ScaleF.apply: non-finite counts at index {bad}")
        return out
