"""Temperature compensation: the executable spec of csrc/tcomp/sig_poly.c and
csrc/tcomp/sig_tcomp.c, one sample at a time, in plain Python integers and floats.

Fixed point (read next to sig_tcomp.h):
    t       int16, 0.01 °C; clamped to [t_lo, t_hi] (status SIG_WARN_CLAMPED)
    u       = floor(((t - t_center) * u_mul + 2^(u_shift-1)) / 2^u_shift)   Q0.15
    horner  acc = c[n];  acc = sat32(c[k] + floor(acc * u / 2^15)), k = n-1..0
    delta   acc, Q(q) reading LSB
    out     = sat16(in - floor((sat32(delta + 2^(q-1))) / 2^q))
Python's >> on negative ints floors, which is what sig_asr32 does.

Float: u = (clamp(T) - center) * inv_scale, delta by Horner, out = in - delta."""
import math

SIG_OK = 0
SIG_WARN_CLAMPED = 1
SIG_WARN_SATURATED = 2
SIG_ERR_ARG = -1
SIG_ERR_NONFINITE = -2
INT16_MIN, INT16_MAX = -(1 << 15), (1 << 15) - 1
INT32_MIN, INT32_MAX = -(1 << 31), (1 << 31) - 1
T_PER_DEGC = 100
MAX_ORDER = 8
MAX_AXES = 3
MAX_Q = 30


def clamp_t(t, t_lo, t_hi):
    """(t limited to [t_lo, t_hi], SIG_WARN_CLAMPED if it had to move else SIG_OK)."""
    if t_lo <= t <= t_hi:
        return t, SIG_OK
    return min(max(t, t_lo), t_hi), SIG_WARN_CLAMPED


def sat32(x):
    return max(INT32_MIN, min(INT32_MAX, x))


def sat16(x):
    return max(INT16_MIN, min(INT16_MAX, x))


def mul_q15(a, u):
    """floor(a * u / 2^15), u = INT16_MIN read as -32767 (sig_mul_q15_32x16)."""
    if u == INT16_MIN:
        u = -INT16_MAX
    return (a * u) >> 15


def horner_q15(coef, u):
    """(value, status) of sig_poly_horner_q15: coef ascending, Q15 abscissa."""
    status = SIG_OK
    acc = coef[-1]
    for c in reversed(coef[:-1]):
        s = c + mul_q15(acc, u)
        if s != sat32(s):
            status = SIG_WARN_SATURATED
        acc = sat32(s)
    return acc, status


def horner_f(coef, u):
    acc = coef[-1]
    for c in reversed(coef[:-1]):
        acc = c + acc * u
    return acc


def scale_q(t, t_lo, t_hi, t_center, u_mul, u_shift):
    """(u Q0.15, status) of sig_tcomp_scale_q."""
    t, status = clamp_t(t, t_lo, t_hi)
    prod = (t - t_center) * u_mul
    if u_shift > 0:
        prod += 1 << (u_shift - 1)
    return prod >> u_shift, status


def delta_q(model, axis, t):
    """(delta in Q(q[axis]), status) of sig_tcomp_delta_q.  `model` is a
    dict with the fields of sig_tcomp_q: coef (list per axis), q, t_lo, t_hi,
    t_center, u_mul, u_shift."""
    u, status = scale_q(t, model["t_lo"], model["t_hi"], model["t_center"],
                        model["u_mul"], model["u_shift"])
    value, st = horner_q15(list(model["coef"][axis]), u)
    return value, status | st


def apply_q(model, t, readings):
    """(outputs, status) of sig_tcomp_apply_q for one temperature."""
    u, status = scale_q(t, model["t_lo"], model["t_hi"], model["t_center"],
                        model["u_mul"], model["u_shift"])
    out = []
    for axis, x in enumerate(readings):
        delta, st = horner_q15(list(model["coef"][axis]), u)
        status |= st
        q = model["q"][axis]
        if q > 0:
            delta = sat32(delta + (1 << (q - 1))) >> q
        corrected = sat32(x - delta)
        if corrected != sat16(corrected):
            status |= SIG_WARN_SATURATED
        out.append(sat16(corrected))
    return out, status


def apply_f(model, t, readings):
    """(outputs, status) of sig_tcomp_apply_f; model fields: coef (per axis,
    reading units), t_lo, t_hi, center, inv_scale (°C)."""
    if math.isnan(t):
        return None, SIG_ERR_NONFINITE
    if not all(math.isfinite(x) for x in readings):
        return None, SIG_ERR_NONFINITE
    t, status = clamp_t(t, model["t_lo"], model["t_hi"])
    u = (t - model["center"]) * model["inv_scale"]
    return [x - horner_f(list(model["coef"][a]), u) for a, x in enumerate(readings)], status
