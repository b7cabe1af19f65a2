"""The payloads of the temperature models' image sections: the offset
polynomial (section 1), the compact polynomial (8), the temperature code (10)
and the units (11), written and parsed here; the container (header, CRC,
section walk) is pysig.store's, and the C loaders of these sections are
csrc/tcomp/sig_*_image.c and sig_tcomp_load_image (docs/image-format.md:
the store owns the container, an area owns its sections)."""
import decimal
import math
import struct

from ..errors import ModelFileError, RangeError
from ..store._image import (SECTION_COMPACT_POLY, SECTION_OFFSET_POLY, build_image, find_section)


OFFSET_POLY_FIXED_LEN = 14


COMPACT_POLY_FIXED_LEN = 8


#: temperature-code kinds of SECTION_TEMP_CODE (sig_tmodel.h)
TCODE_INT16, TCODE_UINT16 = 0, 1


def temp_code_payload(kind):
    """Payload of SECTION_TEMP_CODE: how the firmware reads its temperature
    code (TCODE_INT16 or TCODE_UINT16; sig_tmodel.h)."""
    if kind not in (TCODE_INT16, TCODE_UINT16):
        raise RangeError(f"temperature-code kind {kind!r} is not {TCODE_INT16} or {TCODE_UINT16}")
    return struct.pack("<BB", kind, 0)


UNITS_LEN = 16


UNITS_RAW_CODES, UNITS_CELSIUS = 1, 2      # flag bits of SECTION_UNITS (sig_tmodel.h)


DECIMAL_EXP_LIMIT = 38


def to_decimal(x):
    """(mantissa, exponent) with mantissa * 10**exponent == x to 9
    significant digits, mantissa within int32 (0 -> (0, 0))."""
    x = float(x)
    if x == 0.0:
        return 0, 0
    if not math.isfinite(x):
        raise RangeError(f"{x!r} has no decimal form")
    sign, digits, exp = decimal.Decimal(f"{x:.9g}").normalize().as_tuple()
    m = int("".join(map(str, digits))) * (-1 if sign else 1)
    if not -DECIMAL_EXP_LIMIT <= exp <= DECIMAL_EXP_LIMIT:
        raise RangeError(f"{x!r} is outside the decimal form's 10^-38..10^38")
    return m, exp


def from_decimal(m, e):
    """The float of mantissa * 10**e (exactly as Python parses the decimal)."""
    return float(f"{int(m)}e{int(e)}")


def units_payload(value_scale, raw_codes, temp_scale=None, temp_offset=None):
    """Payload of SECTION_UNITS: the reading's value scale (the int16
    reading = round(value * value_scale)), whether the temperature is the
    sensor's raw code (else 0.01 °C), and for raw codes the optional °C
    conversion (°C = code * temp_scale + temp_offset); layout in sig_tmodel.h."""
    if not (math.isfinite(value_scale) and value_scale > 0):
        raise RangeError(f"value scale must be a positive number, got {value_scale!r}")
    celsius = temp_scale is not None
    if celsius and not raw_codes:
        raise RangeError("a °C conversion applies to raw temperature codes only")
    flags = (UNITS_RAW_CODES if raw_codes else 0) | (UNITS_CELSIUS if celsius else 0)
    fields = [to_decimal(value_scale), to_decimal(temp_scale if celsius else 0.0),
              to_decimal((temp_offset or 0.0) if celsius else 0.0)]
    (vm, ve), (sm, se), (om, oe) = fields
    return struct.pack("<ibBibib", vm, ve, flags, sm, se, om, oe)


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
