# cython: language_level=3
"""Cython bridge to the coefficient image's container in C
(csrc/store/sig_image.c, sig_crc16.c): validation, section lookup, sequence
number, A/B slot choice and the CRC.  The library reads every image through
these, so the C reader is the one definition of a valid image."""
from libc.stdint cimport int16_t, uint8_t, uint16_t, uint32_t

from ..errors import RangeError

cdef extern from "sig_types.h":
    ctypedef int16_t sig_status

cdef extern from "sig_crc16.h":
    uint16_t sig_crc16_ccitt(uint16_t crc, const uint8_t *data, size_t len) nogil

cdef extern from "sig_image.h":
    sig_status sig_image_validate(const uint8_t *buf, size_t len) nogil
    sig_status sig_image_sequence(const uint8_t *buf, size_t len, uint32_t *seq) nogil
    sig_status sig_image_find_section(const uint8_t *buf, size_t len, uint16_t type,
                                      const uint8_t **payload, uint16_t *payload_len) nogil
    sig_status sig_image_select_slot(const uint8_t *slot_a, size_t len_a, const uint8_t *slot_b,
                                     size_t len_b, uint8_t *which) nogil


def crc16(data, uint16_t crc=0xFFFF):
    """sig_crc16_ccitt: CRC-16/CCITT-FALSE of `data`, continuing from `crc`."""
    cdef const uint8_t[::1] b = bytes(data)
    if len(b) == 0:
        return sig_crc16_ccitt(crc, NULL, 0)
    return sig_crc16_ccitt(crc, &b[0], len(b))


def image_validate(data):
    """Status of sig_image_validate."""
    cdef const uint8_t[::1] b = bytes(data) + b"\0"   # never an empty view
    return sig_image_validate(&b[0], len(data))


def image_sequence(data):
    cdef const uint8_t[::1] b = bytes(data) + b"\0"
    cdef uint32_t seq = 0
    st = sig_image_sequence(&b[0], len(data), &seq)
    return st, (seq if st == 0 else None)


def image_find_section(data, int type_id):
    """(status, payload bytes or None) of sig_image_find_section."""
    cdef bytes raw = bytes(data) + b"\0"
    cdef const uint8_t[::1] b = raw
    cdef const uint8_t *p = NULL
    cdef uint16_t plen = 0
    if not 0 <= type_id <= 0xFFFF:
        raise RangeError(f"section type {type_id} outside uint16")
    st = sig_image_find_section(&b[0], len(data), <uint16_t>type_id, &p, &plen)
    if st != 0:
        return st, None
    off = p - &b[0]
    return st, raw[off:off + plen]


def image_select_slot(slot_a, slot_b):
    """(status, which) of sig_image_select_slot: which 0 = A, 1 = B, None
    when neither slot holds a valid image.  A slot may be None."""
    cdef const uint8_t[::1] a = (bytes(slot_a) if slot_a is not None else b"") + b"\0"
    cdef const uint8_t[::1] b = (bytes(slot_b) if slot_b is not None else b"") + b"\0"
    cdef uint8_t which = 255
    st = sig_image_select_slot(&a[0] if slot_a is not None else NULL, len(slot_a) if slot_a is not None else 0,
                               &b[0] if slot_b is not None else NULL, len(slot_b) if slot_b is not None else 0,
                               &which)
    return st, (which if st == 0 else None)
