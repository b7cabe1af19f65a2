# cython: language_level=3
"""Cython bridge to csrc/store/sig_device_id.c: the device id of a serial and
the firmware's check that an image was made for this device."""
from libc.stdint cimport int16_t, uint8_t

cdef extern from "sig_types.h":
    ctypedef int16_t sig_status

cdef extern from "sig_device_id.h":
    ctypedef struct sig_device_id:
        uint8_t kind
        uint8_t len
        uint8_t id[16]
    sig_status sig_device_id_make(sig_device_id *out, const uint8_t *serial, size_t len) nogil
    sig_status sig_device_id_check_image(const uint8_t *buf, size_t len, const sig_device_id *expected) nogil


def device_id(serial):
    """(status, (kind, id bytes) or None) of sig_device_id_make."""
    cdef sig_device_id out
    cdef const uint8_t[::1] b = bytes(serial) + b"\0"      # never an empty view
    st = sig_device_id_make(&out, &b[0], len(serial))
    if st != 0:
        return st, None
    return st, (out.kind, bytes([out.id[k] for k in range(out.len)]))


def check_image(data, serial):
    """Status of sig_device_id_check_image for image bytes `data` and the
    device id of `serial` (the device the firmware runs on)."""
    cdef sig_device_id expected
    cdef const uint8_t[::1] s = bytes(serial) + b"\0"
    cdef const uint8_t[::1] b = bytes(data) + b"\0"
    st = sig_device_id_make(&expected, &s[0], len(serial))
    if st != 0:
        return st
    return sig_device_id_check_image(&b[0], len(data), &expected)
