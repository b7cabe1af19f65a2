"""Compact temperature compensation: the executable spec of csrc/tcomp/sig_tcomp16.c,
in plain Python integers (read next to sig_tcomp16.h).

    t       int16, 0.01 °C; clamped to [t_lo, t_hi] (status SIG_WARN_CLAMPED)
    v       = t - t_lo                 (0 .. t_hi - t_lo)
    w       = v << w_shift             (<= 65535)
    h       = top;  h = floor((h * w + add[k]) / 2^16)  for k = 0 .. order-2
    corr    = floor((h * v + add[order-1]) / 2^16)
    out     = sat16(in - corr)         (status SIG_WARN_SATURATED at a rail)

The C code computes the same numbers with unsigned 16x16 products on offset
binary values; this file is the plain arithmetic it must equal.  `fits` is
the bound sig_tcomp16_init checks (no intermediate leaves int16 / int32)."""
SIG_OK = 0
SIG_WARN_CLAMPED = 1
SIG_WARN_SATURATED = 2
INT16_MIN, INT16_MAX = -(1 << 15), (1 << 15) - 1
INT32_MAX = (1 << 31) - 1
MAX_AXES = 3
MAX_ORDER = 5


def fits(top, add, v_max, w_max):
    """sig_tcomp16_init's bound for one axis: |h| <= 32767 at every inner
    level and every |h * x + add| <= INT32_MAX, for all 0 <= v <= v_max."""
    b = abs(top)
    for c in add[:-1]:
        x = b * w_max + abs(c)
        if x > INT32_MAX:
            return False
        b = -(-x // 65536)
        if b > INT16_MAX:
            return False
    return b * v_max + abs(add[-1]) <= INT32_MAX


def valid(model):
    """True when sig_tcomp16_init accepts the fields of `model` (a dict:
    top, add (per axis, evaluation order), t_lo, t_hi, w_shift)."""
    n, order = len(model["top"]), len(model["add"][0]) if model["add"] else 0
    if not 1 <= n <= MAX_AXES or not 1 <= order <= MAX_ORDER:
        return False
    if len(model["add"]) != n or any(len(r) != order for r in model["add"]):
        return False
    t_lo, t_hi, j = model["t_lo"], model["t_hi"], model["w_shift"]
    if not t_lo < t_hi or not 0 <= j <= 15 or (order > 1 and j < 1):
        return False
    v_max = t_hi - t_lo
    if v_max << j > 0xFFFF:
        return False
    return all(fits(model["top"][a], model["add"][a], v_max, v_max << j) for a in range(n))


def corrections(model, t):
    """(per-axis corr, status): the int16 amounts subtracted from the readings."""
    status = SIG_OK
    t_lo, t_hi = model["t_lo"], model["t_hi"]
    if t < t_lo:
        t, status = t_lo, SIG_WARN_CLAMPED
    elif t > t_hi:
        t, status = t_hi, SIG_WARN_CLAMPED
    v = t - t_lo
    w = v << model["w_shift"]
    out = []
    for top, add in zip(model["top"], model["add"]):
        h = top
        for c in add[:-1]:
            h = (h * w + c) >> 16
        out.append((h * v + add[-1]) >> 16)
    return out, status


def apply_q(model, t, readings):
    """(outputs, status) of sig_tcomp16_apply_q for one temperature."""
    corr, status = corrections(model, t)
    out = []
    for x, c in zip(readings, corr):
        y = x - c
        if y != max(INT16_MIN, min(INT16_MAX, y)):
            status |= SIG_WARN_SATURATED
        out.append(max(INT16_MIN, min(INT16_MAX, y)))
    return out, status
