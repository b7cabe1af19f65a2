# cython: language_level=3
"""Cython bridge to csrc/tcomp/sig_tcomp16.c: the compact fixed-point temperature
compensation (int16 multiplicands, 16x16 products) over numpy arrays.  The
coefficients come from pysig.tcomp._quant.quantize_compact, or from a coefficient
image through the firmware's loader (Tcomp16Q.from_image)."""
import numpy as np
cimport numpy as cnp
from libc.stdint cimport int16_t, int32_t, uint8_t, uint16_t, uint32_t

from ._tcomp import _int16, _int16_readings    # the same int16 checks as the int32 form
from ..errors import ModelFileError, RangeError
from ..status import describe

from ._axes cimport apply_axes, sig_tcomp16_q

cnp.import_array()

cdef extern from "sig_types.h":
    ctypedef int16_t sig_status

cdef extern from "sig_tcomp16.h":
    sig_status sig_tcomp16_init(sig_tcomp16_q *m, uint8_t n_axes, uint8_t order, const int16_t *top,
                                const int32_t *add, int16_t t_lo, int16_t t_hi, uint8_t w_shift)
    sig_status sig_tcomp16_load_image(sig_tcomp16_q *m, const uint8_t *image, size_t len)


def _s16(v):
    return v - 0x10000 if v & 0x8000 else v


def _s32(v):
    v &= 0xFFFFFFFF
    return v - (1 << 32) if v & 0x80000000 else v


cdef class Tcomp16Q:
    """The compact model of sig_tcomp16.h (temperature int16 in 0.01 °C, int16
    readings).  Tcomp16Q.from_fields(top, add, t_lo, t_hi, w_shift) or
    Tcomp16Q.from_compact(pysig.tcomp._quant.CompactModel)."""
    cdef sig_tcomp16_q m

    @staticmethod
    def from_fields(top, add, int t_lo, int t_hi, int w_shift):
        cdef Tcomp16Q self = Tcomp16Q.__new__(Tcomp16Q)
        rows = [[int(v) for v in r] for r in add]
        tops = [int(v) for v in top]
        n_axes, order = len(rows), (len(rows[0]) if rows else 0)
        if not 1 <= n_axes <= 3 or not 1 <= order <= 5 or len(tops) != n_axes \
                or any(len(r) != order for r in rows):
            raise RangeError(f"Tcomp16Q: {n_axes} axes of order {order}, {len(tops)} top "
                             f"coefficients (need 1..3 axes, order 1..5, one top per axis)")
        if any(not -32768 <= v <= 32767 for v in tops) or \
                any(not -(1 << 31) <= v < (1 << 31) for r in rows for v in r):
            raise RangeError("Tcomp16Q: top coefficients must be int16, add constants int32")
        for name, v in (("t_lo", t_lo), ("t_hi", t_hi)):
            if not -32768 <= v <= 32767:
                raise RangeError(f"Tcomp16Q: {name} = {v} outside int16")
        if not 0 <= w_shift <= 255:
            raise RangeError(f"Tcomp16Q: w_shift = {w_shift} outside uint8")
        cdef cnp.ndarray[cnp.int16_t, ndim=1] tp = np.array(tops, dtype=np.int16)
        cdef cnp.ndarray[cnp.int32_t, ndim=1] ad = np.array([v for r in rows for v in r], dtype=np.int32)
        st = sig_tcomp16_init(&self.m, <uint8_t>n_axes, <uint8_t>order, &tp[0], &ad[0],
                              <int16_t>t_lo, <int16_t>t_hi, <uint8_t>w_shift)
        if st != 0:
            raise RangeError(f"Tcomp16Q: sig_tcomp16_init rejected the parameters (status {st}): "
                             f"range, w_shift, or coefficients whose intermediates could overflow")
        return self

    @staticmethod
    def from_compact(compact):
        return Tcomp16Q.from_fields(**compact.fields())

    @staticmethod
    def from_image(data, where="image"):
        """sig_tcomp16_load_image on image bytes; ModelFileError naming the
        status when the loader refuses them."""
        cdef Tcomp16Q self = Tcomp16Q.__new__(Tcomp16Q)
        data = bytes(data)
        cdef const uint8_t[::1] b = data + b"\0"       # never a zero-length view
        st = sig_tcomp16_load_image(&self.m, &b[0], len(data))
        if st != 0:
            text = describe(st, "compact-polynomial")
            raise ModelFileError(f"{where}: the C loader rejected the image: {text}")
        return self

    def load(self, data):
        """sig_tcomp16_load_image into this model: its status (0 loaded; on
        any error the C struct is left exactly as it was)."""
        data = bytes(data)
        cdef const uint8_t[::1] b = data + b"\0"
        return sig_tcomp16_load_image(&self.m, &b[0], len(data))

    def raw(self):
        """The bytes of the C struct (to show a failed load changed nothing)."""
        return (<char *>&self.m)[:sizeof(sig_tcomp16_q)]

    def fields(self):
        """The sig_tcomp16_init arguments held by the C struct (top, add,
        t_lo, t_hi, w_shift), decoded from its packed offset-binary stream
        (the inverse of store_axis in sig_tcomp16.c)."""
        cdef int n = self.m.n_axes, order = self.m.order, a, k, base
        tops, adds = [], []
        for a in range(n):
            base = a * (1 + 2 * order)
            word = self.m.coef[base]
            top = _s16(word ^ 0x8000) if order > 1 else _s16(word)
            add = []
            for k in range(order):
                c = self.m.coef[base + 1 + 2 * k] | (self.m.coef[base + 2 + 2 * k] << 16)
                if k + 2 != order:
                    c -= 1 << 31
                if order == 1:
                    c -= top << 15
                add.append(_s32(c))
            tops.append(top)
            adds.append(add)
        return {"top": tops, "add": adds, "t_lo": self.m.t_lo, "t_hi": self.m.t_hi,
                "w_shift": self.m.w_shift}

    @property
    def n_axes(self):
        """Axes in the model (1..3, SIG_TCOMP16_MAX_AXES)."""
        return self.m.n_axes

    @property
    def order(self):
        """Polynomial order in temperature (SIG_TCOMP16_MIN_ORDER..SIG_TCOMP16_MAX_ORDER)."""
        return self.m.order

    def apply(self, temp, readings):
        """sig_tcomp16_apply_q per sample: temp int16 (n,), readings int16
        (n, n_axes) -> (int16 (n, n_axes), status (n,))."""
        t = _int16(temp, "temperature")
        x = _int16_readings(readings, self.m.n_axes, t.shape[0], "Tcomp16Q.apply")
        return apply_axes(&self.m, t.view(np.uint16), x)

