"""Reference: apply a stored linear scale calibration, counts -> mass.

The executable spec of csrc/weigh/sig_scale.c.

Float form:   mass = (counts - offset) * gain            (gain: unit per count)

Fixed form (Q16.16 output, 32-bit integers only on the MCU):
    d        = sat32(counts - offset)                    offset: int32 ADC code
    mass_q16 = sat32(floor(d * gain_mant / 2**gain_shift))
where gain_mant = round(gain * 2**(16 + gain_shift)) is an int32 and
0 <= gain_shift <= 62.  The product d * gain_mant is exact (the C builds it
from 16-bit halves in two 32-bit words, no int64); the floor division by
2**gain_shift rounds towards minus infinity, as Python's >> does.  The mass
unit (kg, lb) is the calibration's; Q16.16 holds +-32768 of it.
"""
import numpy as np

from pysig.errors import RangeError

INT32_MIN = -(1 << 31)
INT32_MAX = (1 << 31) - 1
MAX_SHIFT = 62
OUT_FRAC = 16


def sat32(v):
    return INT32_MIN if v < INT32_MIN else INT32_MAX if v > INT32_MAX else v


def apply_q16_one(counts, offset, gain_mant, gain_shift):
    """One sample, plain integers: the spec line by line.
    Returns (mass_q16, saturated): saturated when d or the result left int32."""
    raw_d = int(counts) - int(offset)
    d = sat32(raw_d)
    raw = (d * int(gain_mant)) >> int(gain_shift)
    out = sat32(raw)
    return out, (d != raw_d or out != raw)


def apply_q16(counts, offset, gain_mant, gain_shift):
    """Vector form of apply_q16_one: (int32 masses, bool saturated flags)."""
    pairs = [apply_q16_one(c, offset, gain_mant, gain_shift) for c in np.ravel(counts)]
    return (np.array([p[0] for p in pairs], dtype=np.int32),
            np.array([p[1] for p in pairs], dtype=bool))


def apply_f(counts, offset, gain):
    """Float form: (counts - offset) * gain, float64."""
    return (np.asarray(counts, dtype=float) - float(offset)) * float(gain)


def quantize(offset, gain, out_frac=OUT_FRAC):
    """Integer image (offset, gain_mant, gain_shift) of a float calibration.

    offset is rounded to the nearest code (error at most half a code, i.e.
    0.5 * |gain| of mass); gain_shift is the largest in 0..62 that keeps
    |gain_mant| <= INT32_MAX, so the gain keeps at least 30 significant bits
    unless it is smaller than 2^-(out_frac + 62 - 30)."""
    offset, gain = float(offset), float(gain)
    if not (np.isfinite(offset) and np.isfinite(gain)) or gain == 0.0:
        raise RangeError(f"scale quantize: offset {offset!r} and gain {gain!r} must be finite, gain != 0")
    off = round(offset)
    if off < INT32_MIN or off > INT32_MAX:
        raise RangeError(f"scale quantize: offset {offset!r} counts does not fit int32")
    target = gain * 2.0 ** out_frac
    # the definition: the largest shift whose rounded mantissa fits int32
    fitting = [k for k in range(MAX_SHIFT + 1) if abs(round(target * 2.0 ** k)) <= INT32_MAX]
    if not fitting:
        raise RangeError(f"scale quantize: gain {gain!r} unit/count is too large for a Q{out_frac} output")
    shift = max(fitting)
    mant = round(target * 2.0 ** shift)
    if mant == 0:
        raise RangeError(f"scale quantize: gain {gain!r} unit/count underflows the Q{out_frac} image")
    return off, mant, shift
