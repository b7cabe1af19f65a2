"""Any temperature model of a coefficient image: the executable spec of
csrc/tcomp/sig_tmodel.c and csrc/tcomp/sig_tmodel_image.c, one sample at a
time, in plain Python integers.

    code kind   SECTION_TEMP_CODE payload [kind, 0]; absent: int16
    t           int16: the code's bits as two's complement (kind int16) or
                code - 32768 (kind uint16)
    family      the first of: compact section (tcomp16), offset section
                (tcomp), table section (pwl); none: SIG_ERR_EMPTY
    table corr  v = pwl.eval_q16(...) (Q16.16); corr = (v + 2^15) >> 16
    out         sat16(in - corr) per axis; status OR of clamped / saturated"""
import struct

from spec import image, pwl, tcomp, tcomp16

SECTION_OFFSET_POLY, SECTION_PWL_TABLE, SECTION_TEMP_CODE = 1, 6, 10
TCODE_INT16, TCODE_UINT16 = 0, 1
SIG_OK, SIG_WARN_CLAMPED, SIG_WARN_SATURATED = 0, 1, 2
SIG_ERR_FORMAT, SIG_ERR_EMPTY = -3, -5


def code_to_t(kind, code):
    if kind == TCODE_UINT16:
        return code - 32768
    return code - 65536 if code > 0x7FFF else code


def _offset_model(p):
    """Fields of sig_tcomp_q from an offset payload, or None when
    sig_tcomp_load_image rejects it."""
    if len(p) < 14:
        return None
    n_axes, order, u_shift, reserved, t_lo, t_hi, t_center, t0, u_mul = struct.unpack_from("<BBBBhhhhh", p)
    if not (1 <= n_axes <= 3 and 1 <= order <= 8 and reserved == 0):
        return None
    if len(p) != 14 + n_axes * (1 + 4 * (order + 1)):
        return None
    pos, q, coef = 14, [], []
    for _ in range(n_axes):
        q.append(p[pos])
        coef.append(list(struct.unpack_from(f"<{order + 1}i", p, pos + 1)))
        pos += 1 + 4 * (order + 1)
    if not (t_lo < t_hi and t_lo <= t_center <= t_hi and u_mul > 0 and u_shift <= 15):
        return None
    if t_hi - t_center > 32767 or t_lo - t_center < -32767 or any(v > 30 for v in q):
        return None
    for d in (t_hi - t_center, t_lo - t_center):
        u = (d * u_mul + ((1 << (u_shift - 1)) if u_shift else 0)) >> u_shift
        if abs(u) > 32767:
            return None
    return {"coef": coef, "q": q, "t_lo": t_lo, "t_hi": t_hi, "t_center": t_center,
            "u_mul": u_mul, "u_shift": u_shift}


def _tables(p):
    """[(table, t_lo, t_hi, recip, value_frac)] of a table payload, or None."""
    if len(p) < 10:
        return None
    axes, n, t_lo, t_hi, recip = struct.unpack_from("<BBhhI", p)
    if not 1 <= axes <= 3 or n < 2 or len(p) != 10 + axes * (1 + 2 * n):
        return None
    out = []
    for a in range(axes):
        off = 10 + a * (1 + 2 * n)
        vf = p[off]
        if not pwl.params_valid_q16(n, t_lo, t_hi, recip, vf):
            return None
        out.append((list(struct.unpack_from(f"<{n}h", p, off + 1)), t_lo, t_hi, recip, vf))
    return out


def load(buf):
    """(status, model) of sig_tmodel_load_image; model = (family, kind, data)."""
    st = image.validate(buf)
    if st != SIG_OK:
        return st, None
    found = dict((t, p) for t, p in reversed(image.sections(buf)))       # first of each type
    kind = TCODE_INT16
    if SECTION_TEMP_CODE in found:
        p = found[SECTION_TEMP_CODE]
        if len(p) != 2 or p[1] != 0 or p[0] > TCODE_UINT16:
            return SIG_ERR_FORMAT, None
        kind = p[0]
    if image.SECTION_COMPACT_POLY in found:
        st, fields = image.load_compact(buf)
        return (st, None) if st != SIG_OK else (SIG_OK, ("compact", kind, fields))
    if SECTION_OFFSET_POLY in found:
        m = _offset_model(found[SECTION_OFFSET_POLY])
        return (SIG_ERR_FORMAT, None) if m is None else (SIG_OK, ("poly", kind, m))
    if SECTION_PWL_TABLE in found:
        t = _tables(found[SECTION_PWL_TABLE])
        return (SIG_ERR_FORMAT, None) if t is None else (SIG_OK, ("table", kind, t))
    return SIG_ERR_EMPTY, None


def apply(model, code, readings):
    """(outputs, status) of sig_tmodel_apply for one uint16 code."""
    family, kind, data = model
    t = code_to_t(kind, code)
    if family == "poly":
        return tcomp.apply_q(data, t, readings)
    if family == "compact":
        return tcomp16.apply_q(data, t, readings)
    status, out = SIG_OK, []
    for (table, t_lo, t_hi, recip, vf), x in zip(data, readings):
        v, st = pwl.eval_q16(table, t_lo, t_hi, recip, vf, t)
        status |= st
        y = x - ((v + (1 << 15)) >> 16)
        if not -32768 <= y <= 32767:
            status |= SIG_WARN_SATURATED
        out.append(max(-32768, min(32767, y)))
    return out, status
