"""Coefficient image for non-volatile memory (format: csrc/include/sig_image.h),
written and read from Python.

Generic part: `build_image(sections, sequence)` and `read_image(data)` work
on any list of (type id, payload bytes), so other modules add their own
section types (ids in SECTION_*) without touching this file's reader.
Specific part: the offset-polynomial section of the temperature model
(`offset_poly_payload`, `parse_offset_poly`, `model_image`) and the compact
section of pysig.tcomp._quant.CompactModel (`compact_poly_payload`,
`parse_compact_poly`, `compact_image`; C loader sig_tcomp16_load_image)."""
import struct

from . import _image_c
from ..errors import ModelFileError, RangeError
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
SECTION_EXPERIMENTAL = 0x8000
OFFSET_POLY_FIXED_LEN = 14
COMPACT_POLY_FIXED_LEN = 8

MAGIC = b"psig"
FORMAT_VERSION = 1
HEADER_LEN = 12
SECTION_HDR_LEN = 4
CRC_LEN = 2
MIN_LEN = HEADER_LEN + CRC_LEN
MAX_LEN = 65535

#: temperature-code kinds of SECTION_TEMP_CODE (sig_tmodel.h)
TCODE_INT16, TCODE_UINT16 = 0, 1


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


def temp_code_payload(kind):
    """Payload of SECTION_TEMP_CODE: how the firmware reads its temperature
    code (TCODE_INT16 or TCODE_UINT16; sig_tmodel.h)."""
    if kind not in (TCODE_INT16, TCODE_UINT16):
        raise RangeError(f"temperature-code kind {kind!r} is not {TCODE_INT16} or {TCODE_UINT16}")
    return struct.pack("<BB", kind, 0)


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


def offset_poly_payload(model):
    """Payload of SECTION_OFFSET_POLY for a TcompModel (fixed-point form).

    Parameters
    ----------
    model : TcompModel
        A fitted model (pysig.tcomp._poly_model).

    Returns
    -------
    bytes
        14 header bytes, then per axis q (u8) and order + 1 int32
        coefficients, little-endian (layout in csrc/include/sig_image.h).

    Examples
    --------
    See `model_image`, which wraps it into an image.
    """
    f = model.fixed_fields()
    out = struct.pack("<BBBBhhhhh", len(model.axes), model.order, f["u_shift"], 0,
                      f["t_lo"], f["t_hi"], f["t_center"], f["t0"], f["u_mul"])
    for q, coef in zip(f["q"], f["coef"]):
        out += struct.pack("<B", q) + struct.pack(f"<{len(coef)}i", *coef)
    return out


def parse_offset_poly(payload, where="image"):
    """Fields of sig_tcomp_q from a SECTION_OFFSET_POLY payload.

    Parameters
    ----------
    payload : bytes
        The section's payload (see `find_section`).
    where : str, optional
        Names the image in error messages.

    Returns
    -------
    dict
        n_axes, order, u_shift, t_lo, t_hi, t_center, t0, u_mul, q, coef.

    Raises
    ------
    ModelFileError
        The checks of sig_tcomp_load_image: length, axes, order, reserved
        byte.

    Examples
    --------
    >>> parse_offset_poly(bytes(14))
    Traceback (most recent call last):
        ...
    pysig.errors.ModelFileError: image: offset section: 0 axes, order 0, reserved 0
    """
    if len(payload) < OFFSET_POLY_FIXED_LEN:
        raise ModelFileError(f"{where}: offset section of {len(payload)} bytes is too short")
    n_axes, order, u_shift, reserved, t_lo, t_hi, t_center, t0, u_mul = \
        struct.unpack_from("<BBBBhhhhh", payload)
    if not (1 <= n_axes <= 3 and 1 <= order <= 8 and reserved == 0):
        raise ModelFileError(f"{where}: offset section: {n_axes} axes, order {order}, reserved {reserved}")
    want = OFFSET_POLY_FIXED_LEN + n_axes * (1 + 4 * (order + 1))
    if len(payload) != want:
        raise ModelFileError(f"{where}: offset section is {len(payload)} bytes, expected {want}")
    pos, q, coef = OFFSET_POLY_FIXED_LEN, [], []
    for _ in range(n_axes):
        q.append(payload[pos])
        coef.append(list(struct.unpack_from(f"<{order + 1}i", payload, pos + 1)))
        pos += 1 + 4 * (order + 1)
    return {"n_axes": n_axes, "order": order, "u_shift": u_shift, "t_lo": t_lo, "t_hi": t_hi,
            "t_center": t_center, "t0": t0, "u_mul": u_mul, "q": q, "coef": coef}


def model_image(model, sequence=1, extra_sections=()):
    """The NVM image of a temperature model: its offset section (the
    fixed-point form sig_tcomp_load_image reads) plus any others.

    Parameters
    ----------
    model : TcompModel
        A fitted model (pysig.tcomp._poly_model).
    sequence, extra_sections : optional
        The image's sequence number and more (type, payload) sections
        after the offset one, as for `build_image` (which raises
        ValueError for a bad one).

    Returns
    -------
    bytes

    Examples
    --------
    >>> from pysig.sim._chamber import ChamberParams, simulate
    >>> from pysig.tcomp._poly_fit import fit_tcomp
    >>> run = simulate(ChamberParams(dwell_s=600.0))
    >>> image = model_image(fit_tcomp(run["temp"], {"x": run["x"]}, order=2), sequence=3)
    >>> fields = parse_offset_poly(find_section(image, SECTION_OFFSET_POLY))
    >>> fields["order"], fields["t_lo"], fields["t_hi"]
    (2, -19, 7012)
    """
    return build_image([(SECTION_OFFSET_POLY, offset_poly_payload(model)), *extra_sections], sequence)


def compact_poly_payload(compact):
    """Payload of SECTION_COMPACT_POLY for the compact model form.

    Parameters
    ----------
    compact : CompactModel or dict
        A pysig.tcomp._quant.CompactModel, or the dict of its fields().

    Returns
    -------
    bytes

    Raises
    ------
    RangeError
        Fields sig_tcomp16_init would refuse (it is the judge).

    Examples
    --------
    >>> fields = {"top": [1605], "add": [[-25140702, -242974]], "t_lo": -19, "t_hi": 7012,
    ...           "w_shift": 3}
    >>> len(compact_poly_payload(fields))
    18
    >>> compact_poly_payload({**fields, "w_shift": 99})
    Traceback (most recent call last):
        ...
    pysig.errors.RangeError: compact section: the fields are not a model sig_tcomp16_init accepts ...
    """
    from ..tcomp._tcomp16 import Tcomp16Q
    fields = compact.fields() if hasattr(compact, "fields") else compact
    try:
        Tcomp16Q.from_fields(**fields)          # sig_tcomp16_init is the judge
    except RangeError:
        raise RangeError("compact section: the fields are not a model sig_tcomp16_init accepts "
                         "(axes 1..3, order 1..5, range, w_shift or the no-overflow bound)") from None
    order = len(fields["add"][0])
    out = struct.pack("<BBBBhh", len(fields["top"]), order, fields["w_shift"], 0,
                      fields["t_lo"], fields["t_hi"])
    for top, add in zip(fields["top"], fields["add"]):
        out += struct.pack(f"<h{order}i", top, *add)
    return out


def parse_compact_poly(data, where="image"):
    """Fields of sig_tcomp16_init from the compact section of an image.

    Parameters
    ----------
    data : bytes-like
        The whole image.
    where : str, optional
        Names the image in error messages.

    Returns
    -------
    dict
        top, add, t_lo, t_hi, w_shift.

    Raises
    ------
    ModelFileError
        A corrupt image, no compact section, or one sig_tcomp16_load_image
        refuses (the message says which checks).

    Examples
    --------
    >>> fields = {"top": [1605], "add": [[-25140702, -242974]], "t_lo": -19, "t_hi": 7012,
    ...           "w_shift": 3}
    >>> parse_compact_poly(compact_image(fields, sequence=2)) == fields
    True
    >>> parse_compact_poly(build_image([(SECTION_OFFSET_POLY, b"")]))
    Traceback (most recent call last):
        ...
    pysig.errors.ModelFileError: image: ...
    """
    from ..tcomp._tcomp16 import Tcomp16Q
    payload = find_section(data, SECTION_COMPACT_POLY, where)
    try:
        return Tcomp16Q.from_image(data, where=where).fields()     # the firmware's loader
    except ModelFileError:
        raise ModelFileError(f"{where}: compact section of {len(payload)} bytes is malformed or holds "
                             f"a model sig_tcomp16_init rejects (counts, length, reserved byte, "
                             f"range, w_shift or the no-overflow bound)") from None


def compact_image(compact, sequence=1, extra_sections=()):
    """The NVM image of a compact model: its compact section plus any others
    (`sequence`, `extra_sections` as for `build_image`).

    Parameters
    ----------
    compact : CompactModel or dict
        As for `compact_poly_payload`.
    sequence : int, optional
    extra_sections : iterable of (int, bytes), optional

    Returns
    -------
    bytes

    Examples
    --------
    See `parse_compact_poly`.
    """
    return build_image([(SECTION_COMPACT_POLY, compact_poly_payload(compact)), *extra_sections], sequence)
