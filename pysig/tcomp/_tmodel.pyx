# cython: language_level=3
"""Cython bridge to csrc/tcomp/sig_tmodel.c: the one firmware entry point that
evaluates whatever temperature model a coefficient image holds (int32
polynomial, compact polynomial or table), loaded by sig_tmodel_load_image."""
import numpy as np
cimport numpy as cnp
from libc.stdint cimport int8_t, int16_t, int32_t, uint8_t, uint16_t

from ._tcomp import _int16_readings
from ..errors import ModelFileError, RangeError
from ..status import Status, describe
from ._axes cimport apply_axes, sig_tmodel

cnp.import_array()

cdef extern from "sig_types.h":
    ctypedef int16_t sig_status

cdef extern from "sig_tmodel.h":
    int SIG_TMODEL_POLY, SIG_TMODEL_COMPACT, SIG_TMODEL_TABLE
    int16_t sig_tmodel_code_to_t(uint8_t code_kind, uint16_t code) nogil
    sig_status sig_tmodel_load_image(sig_tmodel *m, int16_t *storage, uint16_t storage_len,
                                     const uint8_t *image, size_t len)
    ctypedef struct sig_decimal:
        int32_t mantissa
        int8_t exp10
    ctypedef struct sig_tmodel_units:
        sig_decimal value_scale
        sig_decimal temp_scale
        sig_decimal temp_offset
        uint8_t flags
    sig_status sig_tmodel_load_units(sig_tmodel_units *u, const uint8_t *image, size_t len)

FAMILY_NAMES = {SIG_TMODEL_POLY: "poly", SIG_TMODEL_COMPACT: "compact", SIG_TMODEL_TABLE: "table"}
CODE_KINDS = {0: "int16", 1: "uint16"}
STORAGE_ENTRIES = 3 * 255


def _load_problem(st):
    """What a refused sig_tmodel_load_image status means (ERR_ARG: here the
    table storage is what was too small)."""
    if st == Status.ERR_ARG:
        return "too little table storage or a NULL pointer"
    return describe(st, "model")


def code_to_t(code_kind, codes):
    """sig_tmodel_code_to_t over uint16 codes (numpy in, int16 out)."""
    cdef cnp.ndarray[cnp.uint16_t, ndim=1] c = np.ascontiguousarray(np.ravel(codes), dtype=np.uint16)
    cdef cnp.ndarray[cnp.int16_t, ndim=1] out = np.empty(c.shape[0], dtype=np.int16)
    cdef uint8_t kind = <uint8_t>int(code_kind)
    cdef Py_ssize_t i
    with nogil:
        for i in range(c.shape[0]):
            out[i] = sig_tmodel_code_to_t(kind, c[i])
    return out


def load_units(data):
    """sig_tmodel_load_units on image bytes: (status, fields), fields a dict
    of the decoded section (mantissa, exponent pairs and flags) on SIG_OK,
    else None."""
    data = bytes(data)
    cdef const uint8_t[::1] b = data + b"\0"
    cdef sig_tmodel_units u
    st = sig_tmodel_load_units(&u, &b[0], len(data))
    if st != 0:
        return st, None
    return st, {"value_scale": (u.value_scale.mantissa, u.value_scale.exp10),
                "temp_scale": (u.temp_scale.mantissa, u.temp_scale.exp10),
                "temp_offset": (u.temp_offset.mantissa, u.temp_offset.exp10), "flags": u.flags}


cdef class TModel:
    """A model loaded by the firmware's loader: TModel.from_image(bytes)."""
    cdef sig_tmodel m
    cdef cnp.ndarray storage

    @staticmethod
    def from_image(data, where="image"):
        """sig_tmodel_load_image; ModelFileError naming the loader's status."""
        cdef TModel self = TModel.__new__(TModel)
        st = self.load(data)
        if st != 0:
            raise ModelFileError(f"{where}: the C loader rejected the image: "
                                 f"{_load_problem(st)}")
        return self

    def load(self, data):
        """sig_tmodel_load_image into this object: its status (on error the
        C struct is unchanged)."""
        data = bytes(data)
        if self.storage is None:
            self.storage = np.zeros(STORAGE_ENTRIES, dtype=np.int16)
        cdef cnp.ndarray[cnp.int16_t, ndim=1] s = self.storage
        cdef const uint8_t[::1] b = data + b"\0"
        return sig_tmodel_load_image(&self.m, &s[0], <uint16_t>STORAGE_ENTRIES, &b[0], len(data))

    @property
    def family(self):
        return FAMILY_NAMES.get(self.m.family, f"unknown {self.m.family}")

    @property
    def code_kind(self):
        return CODE_KINDS.get(self.m.code_kind, f"unknown {self.m.code_kind}")

    @property
    def n_axes(self):
        return self.m.n_axes

    def apply(self, codes, readings):
        """sig_tmodel_apply per sample: codes uint16 (n,) (the 16 bits the
        temperature source gives), readings int16 (n, n_axes) ->
        (int16 (n, n_axes), status (n,))."""
        c_arr = np.asarray(codes)
        if c_arr.size and (c_arr.min() < 0 or c_arr.max() > 0xFFFF):
            raise RangeError("TModel.apply: temperature codes must be 16-bit (0..65535)")
        c = np.ascontiguousarray(np.ravel(c_arr), dtype=np.uint16)
        x = _int16_readings(readings, self.m.n_axes, c.shape[0], "TModel.apply")
        return apply_axes(&self.m, c, x)
