"""Coefficient image: the executable spec of csrc/store/sig_crc16.c and
csrc/store/sig_image.c (validation, section lookup, A/B slot choice).

Layout (little-endian; see sig_image.h):
    magic b"psig" | version u8 (1) | flags u8 (0) | total_len u16 | sequence u32
    sections: type u16 (!= 0) | length u16 | payload, tiling [12, total_len-2)
    CRC-16/CCITT-FALSE of bytes [0, total_len-2), u16
Status codes are those of sig_status.h."""
import struct

MAGIC = b"psig"
VERSION = 1
HEADER_LEN = 12
SECTION_HDR_LEN = 4
CRC_LEN = 2
MIN_LEN = HEADER_LEN + CRC_LEN
MAX_LEN = 65535
SIG_OK, SIG_ERR_ARG, SIG_ERR_FORMAT, SIG_ERR_CRC, SIG_ERR_EMPTY = 0, -1, -3, -4, -5
SLOT_A, SLOT_B = 0, 1


def crc16_ccitt(data, crc=0xFFFF):
    """CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection, no xor-out."""
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else (crc << 1)
            crc &= 0xFFFF
    return crc


def validate(buf):
    """Status of sig_image_validate for bytes `buf` (the whole slot)."""
    buf = bytes(buf)
    if len(buf) < MIN_LEN:
        return SIG_ERR_FORMAT
    if buf[:4] != MAGIC or buf[4] != VERSION or buf[5] != 0:
        return SIG_ERR_FORMAT
    total = struct.unpack_from("<H", buf, 6)[0]
    if total < MIN_LEN or total > len(buf):
        return SIG_ERR_FORMAT
    end = total - CRC_LEN
    if crc16_ccitt(buf[:end]) != struct.unpack_from("<H", buf, end)[0]:
        return SIG_ERR_CRC
    pos = HEADER_LEN
    while pos < end:
        if end - pos < SECTION_HDR_LEN:
            return SIG_ERR_FORMAT
        typ, plen = struct.unpack_from("<HH", buf, pos)
        if typ == 0:
            return SIG_ERR_FORMAT
        pos += SECTION_HDR_LEN
        if plen > end - pos:
            return SIG_ERR_FORMAT
        pos += plen
    return SIG_OK


def sections(buf):
    """[(type, payload bytes)] of a valid image, in order."""
    buf = bytes(buf)
    rest = buf[HEADER_LEN:struct.unpack_from("<H", buf, 6)[0] - CRC_LEN]
    found = []
    while rest:
        typ, plen = struct.unpack_from("<HH", rest)
        found.append((typ, rest[SECTION_HDR_LEN:][:plen]))
        rest = rest[SECTION_HDR_LEN + plen:]
    return found


def sequence(buf):
    return struct.unpack_from("<I", bytes(buf), 8)[0]


def find_section(buf, typ):
    """(status, payload) of sig_image_find_section."""
    if typ == 0:
        return SIG_ERR_ARG, None
    st = validate(buf)
    if st != SIG_OK:
        return st, None
    for t, payload in sections(buf):
        if t == typ:
            return SIG_OK, payload
    return SIG_ERR_EMPTY, None


def select_slot(slot_a, slot_b):
    """(status, which) of sig_image_select_slot; a slot may be None."""
    ok_a = slot_a is not None and validate(slot_a) == SIG_OK
    ok_b = slot_b is not None and validate(slot_b) == SIG_OK
    if not ok_a and not ok_b:
        return SIG_ERR_EMPTY, None
    if ok_a and ok_b:
        diff = (sequence(slot_b) - sequence(slot_a)) & 0xFFFFFFFF
        return SIG_OK, (SLOT_B if 0 < diff < 0x80000000 else SLOT_A)
    return SIG_OK, (SLOT_A if ok_a else SLOT_B)


def build(section_list, seq):
    """Image bytes from [(type, payload)] and a sequence number (the writer's
    spec; pysig/store/_image.py is the checked front end)."""
    body = b"".join(struct.pack("<HH", t, len(p)) + bytes(p) for t, p in section_list)
    total = HEADER_LEN + len(body) + CRC_LEN
    head = MAGIC + struct.pack("<BBHI", VERSION, 0, total, seq & 0xFFFFFFFF)
    data = head + body
    return data + struct.pack("<H", crc16_ccitt(data))


# ---- SIG_SECTION_COMPACT_POLY: the spec of sig_tcomp16_load_image ----------
SECTION_COMPACT_POLY = 8
COMPACT_POLY_FIXED_LEN = 8     # u8 n_axes, u8 order, u8 w_shift, u8 0, i16 t_lo, i16 t_hi


def compact_payload(fields):
    """Payload bytes for the fields of sig_tcomp16_init (a dict: top, add per
    axis in evaluation order, t_lo, t_hi, w_shift); the writer's spec."""
    axes, order = len(fields["top"]), len(fields["add"][0])
    layout = "<BBBBhh" + f"h{order}i" * axes       # header, then per axis: top, add[order]
    values = [axes, order, fields["w_shift"], 0, fields["t_lo"], fields["t_hi"]]
    for top, add in zip(fields["top"], fields["add"]):
        values += [top, *add]
    return struct.pack(layout, *values)


def load_compact(buf):
    """(status, fields or None) of sig_tcomp16_load_image on bytes `buf`:
    the section lookup, the payload's length and reserved byte, then exactly
    what sig_tcomp16_init accepts (reference.tcomp16.valid)."""
    from spec import tcomp16
    st, p = find_section(buf, SECTION_COMPACT_POLY)
    if st != SIG_OK:
        return st, None
    if len(p) < COMPACT_POLY_FIXED_LEN:
        return SIG_ERR_FORMAT, None
    n_axes, order, w_shift, reserved, t_lo, t_hi = struct.unpack_from("<BBBBhh", p)
    if not (1 <= n_axes <= tcomp16.MAX_AXES and 1 <= order <= tcomp16.MAX_ORDER and reserved == 0):
        return SIG_ERR_FORMAT, None
    if len(p) != COMPACT_POLY_FIXED_LEN + n_axes * (2 + 4 * order):
        return SIG_ERR_FORMAT, None
    top, add, pos = [], [], COMPACT_POLY_FIXED_LEN
    for _ in range(n_axes):
        values = struct.unpack_from(f"<h{order}i", p, pos)
        top.append(values[0])
        add.append(list(values[1:]))
        pos += 2 + 4 * order
    fields = {"top": top, "add": add, "t_lo": t_lo, "t_hi": t_hi, "w_shift": w_shift}
    return (SIG_OK, fields) if tcomp16.valid(fields) else (SIG_ERR_FORMAT, None)
