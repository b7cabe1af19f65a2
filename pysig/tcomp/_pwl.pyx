# cython: language_level=3
"""Cython bridge to csrc/tcomp/sig_pwl.c: evaluate a piecewise-linear table over a
numpy array of temperatures with the very C code the firmware runs."""
import numpy as np
cimport numpy as cnp
from libc.stdint cimport int16_t, int32_t, uint8_t, uint16_t, uint32_t
from libc.math cimport NAN

from ..errors import ModelFileError, RangeError, NonFiniteError
from ..status import Status, describe

cnp.import_array()

cdef extern from "sig_types.h":
    ctypedef double sig_real
    ctypedef int16_t sig_status

cdef extern from "sig_pwl.h":
    ctypedef struct sig_pwl_q16:
        const int16_t *table
        uint32_t recip
        int16_t t_lo
        int16_t t_hi
        uint8_t n_knots
        uint8_t value_frac
    ctypedef struct sig_pwl_f:
        pass
    sig_status sig_pwl_init_q16(sig_pwl_q16 *p, const int16_t *table, uint8_t n_knots,
                                int16_t t_lo, int16_t t_hi, uint32_t recip, uint8_t value_frac)
    sig_status sig_pwl_eval_q16(const sig_pwl_q16 *p, int16_t t, int32_t *out_q16) nogil
    sig_status sig_pwl_load_image(sig_pwl_q16 *tables, uint8_t max_axes, uint8_t *n_axes,
                                  int16_t *storage, uint16_t storage_len,
                                  const uint8_t *image, size_t len)
    sig_status sig_pwl_init_f(sig_pwl_f *p, const sig_real *table, uint8_t n_knots,
                              sig_real t_lo, sig_real t_hi, sig_real inv_step)
    sig_status sig_pwl_eval_f(const sig_pwl_f *p, sig_real t, sig_real *out) nogil


def _arrays(table, t, dtype, out_dtype):
    """What both forms loop over: the table and the temperatures as contiguous
    `dtype` arrays (the temperatures flattened), and for each temperature a
    value (`out_dtype`, zeros) and a status (int16)."""
    tab = np.ascontiguousarray(table, dtype=dtype)
    temps = np.ascontiguousarray(np.ravel(t), dtype=dtype)
    n = temps.shape[0]
    return tab, temps, np.zeros(n, dtype=out_dtype), np.empty(n, dtype=np.int16)


def eval_q16(table, long long t_lo, long long t_hi, long long recip, long long value_frac, t):
    """C sig_pwl_eval_q16 over int16 temperatures `t`.

    Returns (values int32 Q16.16, status int16 per element).  Raises
    RangeError when sig_pwl_init_q16 rejects the parameters."""
    cdef cnp.ndarray[cnp.int16_t, ndim=1] tab, temps, status
    cdef cnp.ndarray[cnp.int32_t, ndim=1] out
    tab, temps, out, status = _arrays(table, t, np.int16, np.int32)
    cdef Py_ssize_t n = temps.shape[0], i
    cdef sig_pwl_q16 p
    if tab.shape[0] > 255 or not (-32768 <= t_lo <= 32767 and -32768 <= t_hi <= 32767
                                  and 0 <= recip <= 0xFFFFFFFF and 0 <= value_frac <= 255):
        raise RangeError("pwl: table or parameters out of their C types' range")
    if tab.shape[0] == 0 or sig_pwl_init_q16(&p, &tab[0], <uint8_t>tab.shape[0], <int16_t>t_lo,
                                             <int16_t>t_hi, <uint32_t>recip,
                                             <uint8_t>value_frac) != 0:
        raise RangeError(f"pwl: sig_pwl_init_q16 rejected n_knots={tab.shape[0]}, t_lo={t_lo}, "
                         f"t_hi={t_hi}, recip={recip}, value_frac={value_frac}")
    with nogil:
        for i in range(n):
            status[i] = sig_pwl_eval_q16(&p, temps[i], &out[i])
    return out, status


def eval_f(table, double t_lo, double t_hi, double inv_step, t):
    """C sig_pwl_eval_f (host build: sig_real = double) over float temperatures.

    Returns (values float64, status int16); NaN temperatures give status -2
    and a NaN value."""
    cdef cnp.ndarray[cnp.float64_t, ndim=1] tab, temps, out
    cdef cnp.ndarray[cnp.int16_t, ndim=1] status
    tab, temps, out, status = _arrays(table, t, np.float64, np.float64)
    cdef Py_ssize_t n = temps.shape[0], i
    cdef sig_pwl_f p
    cdef sig_status st
    cdef double y
    if tab.shape[0] == 0 or tab.shape[0] > 255:
        raise RangeError(f"pwl: {tab.shape[0]} knots, the C table takes 2..255")
    st = sig_pwl_init_f(&p, &tab[0], <uint8_t>tab.shape[0], t_lo, t_hi, inv_step)
    if st == Status.ERR_NONFINITE:
        raise NonFiniteError("pwl: non-finite table entry")
    if st != 0:
        raise RangeError(f"pwl: sig_pwl_init_f rejected n_knots={tab.shape[0]}, t_lo={t_lo}, "
                         f"t_hi={t_hi}, inv_step={inv_step}")
    with nogil:
        for i in range(n):
            y = 0.0
            status[i] = sig_pwl_eval_f(&p, temps[i], &y)
            out[i] = y if status[i] >= 0 else NAN
    return out, status


def load_image(data, where="image"):
    """C sig_pwl_load_image on image bytes: a list of dicts (table int16 array,
    t_lo, t_hi, recip, value_frac) as the C loaded them.  ModelFileError
    names the C status when it rejects the image."""
    cdef bytes raw = bytes(data)
    cdef const uint8_t[::1] b = raw + b"\0"
    cdef sig_pwl_q16 tabs[3]
    cdef int16_t storage[3 * 255]
    cdef uint8_t n_axes = 0
    st = sig_pwl_load_image(tabs, 3, &n_axes, storage, 3 * 255, &b[0], len(raw))
    if st != 0:
        text = ("more axes or entries than the loader has room for" if st == Status.ERR_ARG
                else describe(st, "piecewise-linear table"))
        raise ModelFileError(f"{where}: the C loader rejected the image: {text}")
    out = []
    for a in range(n_axes):
        out.append({"table": np.array([tabs[a].table[k] for k in range(tabs[a].n_knots)], dtype=np.int16),
                    "t_lo": tabs[a].t_lo, "t_hi": tabs[a].t_hi, "recip": tabs[a].recip,
                    "value_frac": tabs[a].value_frac})
    return out
