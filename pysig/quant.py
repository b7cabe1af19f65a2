"""Fixed-point formats for the temperature-compensation model (sig_tcomp.h),
chosen automatically:

* Temperature scaling.  Temperatures are int16 in 0.01 °C.  The abscissa is
  u = round((t - t_center) * u_mul / 2^u_shift), Q0.15, with t_center the
  integer middle of the calibrated range and the largest u_shift for which
  u_mul = floor(32767 * 2^u_shift / half_span) still fits in int16, so
  |u| <= 32767 over the range with 15 bits of resolution.  The float model
  uses exactly u = (T - t_center) * u_mul / 2^(u_shift + 15): both forms share
  one abscissa and differ only by the rounding of u (at most 2^-16).
* Coefficient Q format, per axis.  The largest q (0..30) with
  sum_k |round(c_k 2^q)| + order + 2^(q-1) <= INT32_MAX: no partial Horner sum
  can overflow for |u| <= 1 (partial sums are bounded by the suffix sums of
  |c_k|, plus at most one count of floor error per step) and the final
  rounding add cannot overflow either, whatever the int16 reading.
* Error bound, in reading LSB, of the fixed-point delta against float64:
  (order + 1) * 2^-(q+1) (coefficient rounding) + order * 2^-q (floors in
  Horner) + 2^-16 * sum_k k |c_k| (rounding of u)."""
import math
from dataclasses import dataclass

import numpy as np

from .errors import RangeError

INT16_MAX = (1 << 15) - 1
INT32_MAX = (1 << 31) - 1
MAX_Q = 30
MAX_ERROR_LSB = 0.5     # pysig.fit refuses a model whose fixed-point bound exceeds this
T_PER_DEGC = 100


@dataclass(frozen=True)
class TemperatureScaling:
    t_lo: int          # 0.01 °C
    t_hi: int
    t_center: int
    u_mul: int
    u_shift: int

    @property
    def scale_c(self):
        """°C per unit of u in the float model."""
        return (1 << (self.u_shift + 15)) / self.u_mul / T_PER_DEGC

    @property
    def center_c(self):
        return self.t_center / T_PER_DEGC


def to_centi(temp_c, what="temperature"):
    """°C -> int16 counts of 0.01 °C (rounded); RangeError outside int16."""
    t = np.rint(np.asarray(temp_c, dtype=float) * T_PER_DEGC)
    if t.size and (t.min() < -32768 or t.max() > 32767):
        raise RangeError(f"{what}: {float(np.max(np.abs(temp_c)))} °C does not fit an int16 "
                         f"in 0.01 °C (-327.68 .. 327.67 °C)")
    return t.astype(np.int64)


def choose_scaling(t_lo, t_hi):
    """Scaling for a calibrated range [t_lo, t_hi] in 0.01 °C (ints)."""
    t_lo, t_hi = int(t_lo), int(t_hi)
    if not (-32768 <= t_lo < t_hi <= 32767):
        raise RangeError(f"calibrated range [{t_lo}, {t_hi}] (0.01 °C) must satisfy "
                         f"-32768 <= t_lo < t_hi <= 32767")
    t_center = (t_lo + t_hi) // 2
    half = max(t_hi - t_center, t_center - t_lo)
    if half > INT16_MAX:
        raise RangeError(f"calibrated range [{t_lo}, {t_hi}] (0.01 °C) is wider than 655.34 °C")
    for shift in range(30, -1, -1):
        u_mul = (INT16_MAX << shift) // half
        if u_mul <= INT16_MAX:
            return TemperatureScaling(t_lo, t_hi, t_center, u_mul, shift)
    raise AssertionError("unreachable: shift 0 gives u_mul <= 32767 for half >= 1")


@dataclass(frozen=True)
class QuantizedAxis:
    q: int
    coef: tuple        # int32 values, ascending powers of u
    error_bound_lsb: float


def quantize_axis(coef, what="axis"):
    """Q format and int32 coefficients for one axis' delta polynomial
    (float coefficients in reading LSB, ascending powers of u)."""
    coef = [float(c) for c in coef]
    if not all(math.isfinite(c) for c in coef):
        raise RangeError(f"{what}: non-finite coefficient {coef}")
    order = len(coef) - 1
    for q in range(MAX_Q, -1, -1):
        ints = [int(round(c * (1 << q))) for c in coef]
        half = (1 << (q - 1)) if q > 0 else 0
        if sum(abs(v) for v in ints) + order + half <= INT32_MAX:
            bound = ((order + 1) * 0.5 + order) / (1 << q) \
                + sum(k * abs(c) for k, c in enumerate(coef)) / (1 << 16)
            return QuantizedAxis(q, tuple(ints), bound)
    raise RangeError(f"{what}: coefficients too large for int32 even at Q0 "
                     f"(sum |c| = {sum(abs(c) for c in coef):.4g} LSB)")
