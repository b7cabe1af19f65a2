"""Device ids of serial numbers and the image check: the executable spec of
csrc/store/sig_device_id.c (format in sig_device_id.h).

A serial of at most 16 bytes is its own id; a longer one becomes its 32-bit
FNV-1a hash (little-endian) followed by its last 12 bytes."""
import struct

from spec.image import SIG_ERR_ARG, SIG_ERR_EMPTY, SIG_ERR_FORMAT, SIG_OK, find_section

SECTION_DEVICE_ID = 9
SIG_ERR_DEVICE = -6
MAX_LEN = 16
TAIL_LEN = 12
VERBATIM, HASHED = 0, 1


def fnv1a32(data):
    h = 2166136261
    for b in data:
        h = ((h ^ b) * 16777619) & 0xFFFFFFFF
    return h


def make(serial):
    """(kind, id bytes) of a serial (bytes, at least one)."""
    serial = bytes(serial)
    if not serial:
        raise ValueError("empty serial")
    if len(serial) <= MAX_LEN:
        return VERBATIM, serial
    return HASHED, struct.pack("<I", fnv1a32(serial)) + serial[-TAIL_LEN:]


def payload(serial):
    kind, ident = make(serial)
    return bytes([kind, len(ident)]) + ident


def check_image(buf, expected):
    """Status of sig_device_id_check_image; `expected` is (kind, id bytes)."""
    if buf is None or expected is None:
        return SIG_ERR_ARG
    st, p = find_section(buf, SECTION_DEVICE_ID)
    if st == SIG_ERR_EMPTY:
        return SIG_ERR_DEVICE
    if st != SIG_OK:
        return st
    if len(p) < 2 or p[0] > HASHED or not 1 <= p[1] <= MAX_LEN or len(p) != 2 + p[1]:
        return SIG_ERR_FORMAT
    kind, ident = expected
    return SIG_OK if (p[0], bytes(p[2:])) == (kind, bytes(ident)) else SIG_ERR_DEVICE
