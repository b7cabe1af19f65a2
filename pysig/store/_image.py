"""The coefficient image's container (docs/image-format.md): written here,
read through the C reader (pysig.store._image_c).  `build_image(sections,
sequence)`, `read_image(data)` and `find_section` work on any list of
(type id, payload bytes); the section ids are registered here as in
sig_image.h, and each payload belongs to the area whose model it holds
(the temperature models' in pysig.tcomp._sections, the refined effects' in
pysig.refine._device, the device id's in pysig.store._device)."""
import struct

from . import _image_c
from ..errors import ModelFileError
from ..status import Status

SECTION_OFFSET_POLY = 1
SECTION_GAIN_POLY = 2
SECTION_THERMAL_LAG = 3
SECTION_HYSTERESIS = 4
SECTION_CREEP = 5
SECTION_PWL_TABLE = 6
SECTION_LINEAR_SCALE = 7
SECTION_COMPACT_POLY = 8
SECTION_DEVICE_ID = 9       # its payload: pysig.store._device
SECTION_TEMP_CODE = 10
SECTION_UNITS = 11          # its payload: units_payload; read by sig_tmodel_load_units (sig_tmodel.h)
SECTION_EXPERIMENTAL = 0x8000

MAGIC = b"psig"
FORMAT_VERSION = 1
HEADER_LEN = 12
SECTION_HDR_LEN = 4
CRC_LEN = 2
MIN_LEN = HEADER_LEN + CRC_LEN
MAX_LEN = 65535


def crc16_ccitt(data, crc=0xFFFF):
    """CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF): the C core's
    sig_crc16_ccitt, continuing from `crc`.

    Examples
    --------
    >>> hex(crc16_ccitt(b"123456789"))
    '0x29b1'
    """
    return _image_c.crc16(data, crc)


def build_image(sections, sequence=1):
    """The bytes of a coefficient image (format: csrc/include/sig_image.h):
    header, sections, CRC.

    Parameters
    ----------
    sections : iterable of (int, bytes)
        (type id 1..65535, payload) pairs, in order.
    sequence : int, optional
        uint32 sequence number (the A/B slot with the higher one wins).

    Returns
    -------
    bytes

    Raises
    ------
    ValueError
        A type id, payload or image size, or a sequence out of range.

    Examples
    --------
    >>> image = build_image([(SECTION_EXPERIMENTAL, b"hello")], sequence=7)
    >>> len(image), image[:4]
    (23, b'psig')
    >>> read_image(image)
    (7, [(32768, b'hello')])
    """
    sections = [(int(t), bytes(p)) for t, p in sections]
    for t, p in sections:
        if not 1 <= t <= 0xFFFF:
            raise ValueError(f"section type {t} outside 1..65535")
        if len(p) > 0xFFFF:
            raise ValueError(f"section {t}: payload of {len(p)} bytes exceeds 65535")
    size = MIN_LEN + sum(SECTION_HDR_LEN + len(p) for _, p in sections)
    if size > MAX_LEN:
        raise ValueError(f"image of {size} bytes exceeds {MAX_LEN}")
    if not 0 <= int(sequence) <= 0xFFFFFFFF:
        raise ValueError(f"sequence {sequence} outside uint32")
    body = b"".join(struct.pack("<HH", t, len(p)) + p for t, p in sections)
    data = MAGIC + struct.pack("<BBHI", FORMAT_VERSION, 0, size, int(sequence)) + body
    return data + struct.pack("<H", crc16_ccitt(data))


def _check_valid(data, where):
    """The C reader's verdict (sig_image_validate), as a named error."""
    status = _image_c.image_validate(data)
    if status == Status.ERR_CRC:
        raise ModelFileError(f"{where}: corrupt coefficient image: CRC mismatch (corrupt or partly written)")
    if status != Status.OK:
        raise ModelFileError(f"{where}: corrupt coefficient image: bad magic, version, length or section layout")


def read_image(data, where="image"):
    """Validate an image (magic, version, lengths, CRC) and split it.

    Parameters
    ----------
    data : bytes-like
        The image.
    where : str, optional
        Names the image in error messages.

    Returns
    -------
    sequence : int
    sections : list of (int, bytes)

    Raises
    ------
    ModelFileError
        A corrupt image, saying what is wrong (format or CRC).

    Examples
    --------
    >>> image = bytearray(build_image([(SECTION_EXPERIMENTAL, b"hello")]))
    >>> image[-1] ^= 1                                   # one flipped bit
    >>> read_image(image)
    Traceback (most recent call last):
        ...
    pysig.errors.ModelFileError: image: corrupt coefficient image: CRC mismatch (corrupt or partly written)
    """
    data = bytes(data)
    _check_valid(data, where)
    end = struct.unpack_from("<H", data, 6)[0] - CRC_LEN
    out, pos = [], HEADER_LEN
    while pos < end:
        typ, plen = struct.unpack_from("<HH", data, pos)
        out.append((typ, data[pos + SECTION_HDR_LEN:pos + SECTION_HDR_LEN + plen]))
        pos += SECTION_HDR_LEN + plen
    return struct.unpack_from("<I", data, 8)[0], out


def find_section(data, typ, where="image"):
    """The payload of the first section of type `typ` in a valid image.

    Parameters
    ----------
    data : bytes-like
        The image.
    typ : int
        The section type (SECTION_*).
    where : str, optional
        Names the image in error messages.

    Returns
    -------
    bytes

    Raises
    ------
    ModelFileError
        A corrupt image, or no section of that type.

    Examples
    --------
    >>> image = build_image([(SECTION_EXPERIMENTAL, b"hello")])
    >>> find_section(image, SECTION_EXPERIMENTAL)
    b'hello'
    >>> find_section(image, SECTION_OFFSET_POLY)
    Traceback (most recent call last):
        ...
    pysig.errors.ModelFileError: image: no section of type 1 in the image
    """
    data = bytes(data)
    _check_valid(data, where)
    status, payload = _image_c.image_find_section(data, typ)
    if status != Status.OK:
        raise ModelFileError(f"{where}: no section of type {typ} in the image")
    return payload


