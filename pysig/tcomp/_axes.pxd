# The three C models that correct a reading per axis from a 16-bit
# temperature - the offset polynomial (sig_tcomp.h), the compact polynomial
# (sig_tcomp16.h) and any model loaded from an image (sig_tmodel.h) - and
# one loop that applies any of them to numpy arrays.  Their entry points
# share one shape: status = apply(model, t, const int16_t in[n_axes],
# int16_t out[n_axes]); t is int16 for the first two and the raw uint16
# code for the image model, so the loop passes the 16 bits and each call
# reads them as its own type.
from libc.stdint cimport int16_t, int32_t, uint8_t, uint16_t

cdef extern from "sig_types.h":
    ctypedef int16_t sig_status

cdef extern from "sig_tcomp.h":
    ctypedef struct sig_tcomp_q:
        uint8_t n_axes
        uint8_t order
        int16_t t_lo
        int16_t t_hi
        int16_t t_center
        int16_t t0
        int16_t u_mul
        uint8_t u_shift
        uint8_t q[3]
        int32_t coef[3][9]
        bint no_overflow
    sig_status sig_tcomp_apply_q(const sig_tcomp_q *m, int16_t t, const int16_t *inp, int16_t *out) nogil

cdef extern from "sig_tcomp16.h":
    ctypedef struct sig_tcomp16_q:
        uint16_t coef[33]
        uint8_t n_axes
        uint8_t order
        int16_t t_lo
        int16_t t_hi
        uint8_t w_shift
    sig_status sig_tcomp16_apply_q(const sig_tcomp16_q *m, int16_t t, const int16_t *inp,
                                   int16_t *out) nogil

cdef extern from "sig_tmodel.h":
    ctypedef struct sig_tmodel:
        uint8_t family
        uint8_t code_kind
        uint8_t n_axes
    sig_status sig_tmodel_apply(const sig_tmodel *m, uint16_t code, const int16_t *inp,
                                int16_t *out) nogil

ctypedef fused axes_model:
    sig_tcomp_q
    sig_tcomp16_q
    sig_tmodel


cdef inline sig_status apply_one(axes_model *m, uint16_t t, const int16_t *x, int16_t *y) noexcept nogil:
    if axes_model is sig_tcomp_q:
        return sig_tcomp_apply_q(m, <int16_t>t, x, y)
    elif axes_model is sig_tcomp16_q:
        return sig_tcomp16_apply_q(m, <int16_t>t, x, y)
    else:
        return sig_tmodel_apply(m, t, x, y)


cdef inline tuple apply_axes(axes_model *m, object t_bits, object readings):
    """(int16 (n, n_axes) outputs, int16 (n,) statuses): the model per sample.
    t_bits: the n temperatures' 16 bits (a uint16 array); readings: int16
    (n, n_axes), checked by the caller."""
    import numpy
    cdef const uint16_t[::1] t = t_bits
    cdef const int16_t[:, ::1] x = readings
    out = numpy.zeros((t.shape[0], m.n_axes), dtype=numpy.int16)
    status = numpy.empty(t.shape[0], dtype=numpy.int16)
    cdef int16_t[:, ::1] y = out
    cdef int16_t[::1] st = status
    cdef Py_ssize_t i
    with nogil:
        for i in range(t.shape[0]):
            st[i] = apply_one(m, t[i], &x[i, 0], &y[i, 0])
    return out, status
