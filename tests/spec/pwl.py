"""Piecewise-linear lookup table with uniform knots: the executable spec of
csrc/tcomp/sig_pwl.c, one scalar at a time, in plain Python integers.

Fixed point (read next to sig_pwl.h):
    d    = clamp(t, t_lo, t_hi) - t_lo                 0 <= d <= 65535
    pos  = (d * recip) >> 16                           Q16.16 segment position
    seg  = pos >> 16,  frac = (pos & 0xFFFF) >> 4      frac Q0.12
    acc  = (table[seg] << 12) + (table[seg+1] - table[seg]) * frac
           (seg >= n - 1: acc = table[n-1] << 12)      unit 2^-(value_frac+12)
    out  = floor(acc * 2^(4 - value_frac))             Q16.16
Python's >> on negative ints floors.  (The C forms the same numbers with
16x16-bit products; the identities are in sig_pwl.c.)"""
import math

from spec.tcomp import clamp_t

FRAC_BITS = 12
MIN_KNOTS = 2
MAX_KNOTS = 255
SIG_OK = 0
SIG_WARN_CLAMPED = 1


def params_valid_q16(n_knots, t_lo, t_hi, recip, value_frac):
    """The checks of sig_pwl_init_q16 (True when it returns SIG_OK)."""
    if not (MIN_KNOTS <= n_knots <= MAX_KNOTS) or t_hi <= t_lo or not 0 < recip < 1 << 32:
        return False
    if not 0 <= value_frac <= 15:
        return False
    span = t_hi - t_lo
    if (recip >> 16) > (255 << 16) // span:
        return False
    end = (span * recip) >> 16
    return (end >> 16) >= n_knots - 2 and end <= (n_knots - 1) << 16


def eval_q16(table, t_lo, t_hi, recip, value_frac, t):
    """(value Q16.16, status) for one int16 temperature t."""
    n = len(table)
    t, status = clamp_t(t, t_lo, t_hi)
    pos = ((t - t_lo) * recip) >> 16
    seg = pos >> 16
    if seg >= n - 1:
        acc = table[n - 1] << FRAC_BITS
    else:
        lo = table[seg]
        acc = (lo << FRAC_BITS) + (table[seg + 1] - lo) * ((pos & 0xFFFF) >> 4)
    if value_frac >= 4:
        return acc >> (value_frac - 4), status
    return acc << (4 - value_frac), status


def knot_offsets_q16(n_knots, recip):
    """Exact positions of the knots as offsets from t_lo, in temperature
    units (real numbers): knot k where d * recip / 2^32 == k."""
    return [k * float(1 << 32) / recip for k in range(n_knots)]


def eval_f(table, t_lo, t_hi, inv_step, t):
    """(value, status) of the float form; status -2 (SIG_ERR_NONFINITE) for NaN."""
    if math.isnan(t):
        return None, -2
    n = len(table)
    t, status = clamp_t(t, t_lo, t_hi)
    pos = (t - t_lo) * inv_step
    seg = int(pos)
    if seg >= n - 1:
        return table[n - 1], status
    lo, hi = table[seg], table[seg + 1]
    frac = pos - seg
    y = (1.0 - frac) * lo + frac * hi
    return min(max(y, min(lo, hi)), max(lo, hi)), status
