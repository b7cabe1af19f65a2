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

from ..errors import RangeError

INT16_MAX = (1 << 15) - 1
INT32_MAX = (1 << 31) - 1
MAX_Q = 30
MAX_ERROR_LSB = 0.5     # pysig.tcomp._poly_fit refuses a model whose fixed-point bound exceeds this
T_PER_DEGC = 100


@dataclass(frozen=True)
class TemperatureScaling:
    t_lo: int          # 0.01 °C
    t_hi: int
    t_center: int
    u_mul: int
    u_shift: int
    units_per: int = T_PER_DEGC   # t counts per unit of the float abscissa (100: 0.01 °C; 1: raw codes)

    @property
    def scale_c(self):
        """°C per unit of u in the float model."""
        return (1 << (self.u_shift + 15)) / self.u_mul / self.units_per

    @property
    def center_c(self):
        return self.t_center / self.units_per


def to_centi(temp_c, what="temperature"):
    """°C -> counts of 0.01 °C, the temperature unit of the C models.

    Parameters
    ----------
    temp_c : array_like
        Temperatures, °C.
    what : str, optional
        Names the data in the error message.

    Returns
    -------
    ndarray of int64
        Rounded to the nearest 0.01 °C (half to even), each within int16.

    Raises
    ------
    RangeError
        A temperature outside -327.68 .. 327.67 °C (the out-of-range rule
        for fitting, stated in pysig.tcomp._tempcode).
    NonFiniteError
        A NaN or inf temperature.

    Examples
    --------
    >>> to_centi([25.0, -0.125])
    array([2500,  -12])
    >>> to_centi([25.0, 400.0])
    Traceback (most recent call last):
        ...
    pysig.errors.RangeError: temperature: 400.0 °C at index 1 does not fit the int16 temperature ...
    """
    from ._tempcode import CELSIUS
    return CELSIUS.to_t(temp_c, "raise", what)


def choose_scaling(t_lo, t_hi, units_per=T_PER_DEGC):
    """The int16 temperature scaling of a calibrated range.

    u = (t - t_center) * u_mul >> u_shift maps [t_lo, t_hi] onto about
    [-32767, 32767] (Q15), the abscissa of the C polynomial.

    Parameters
    ----------
    t_lo, t_hi : int
        The calibrated range of the int16 temperature t, t_lo < t_hi.
    units_per : int, optional
        t counts per unit of the float model's abscissa: 100 for t in
        0.01 °C (the default), 1 for raw sensor codes.

    Returns
    -------
    TemperatureScaling

    Raises
    ------
    RangeError
        A range outside int16 or empty.

    Examples
    --------
    >>> choose_scaling(-19, 7012)
    TemperatureScaling(t_lo=-19, t_hi=7012, t_center=3496, u_mul=19086, u_shift=11, units_per=100)
    >>> choose_scaling(100, 100)
    Traceback (most recent call last):
        ...
    pysig.errors.RangeError: calibrated range [100, 100] (0.01 °C) must satisfy -32768 <= t_lo < t_hi <= 32767
    """
    t_lo, t_hi = int(t_lo), int(t_hi)
    if not (-32768 <= t_lo < t_hi <= 32767):
        raise RangeError(f"calibrated range [{t_lo}, {t_hi}] (0.01 °C) must satisfy "
                         f"-32768 <= t_lo < t_hi <= 32767")
    if t_hi - t_lo == 65535:
        # the whole int16 span: |t - t_center| <= 32767 needs one code less;
        # the lowest code is then clamped (and flagged) like any outside one
        t_lo += 1
    t_center = (t_lo + t_hi) // 2
    half = max(t_hi - t_center, t_center - t_lo)
    if half > INT16_MAX:
        raise RangeError(f"calibrated range [{t_lo}, {t_hi}] (0.01 °C) is wider than 655.34 °C")
    for shift in range(30, -1, -1):
        u_mul = (INT16_MAX << shift) // half
        if u_mul <= INT16_MAX:
            return TemperatureScaling(t_lo, t_hi, t_center, u_mul, shift, int(units_per))
    raise AssertionError("unreachable: shift 0 gives u_mul <= 32767 for half >= 1")


@dataclass(frozen=True)
class QuantizedAxis:
    q: int
    coef: tuple        # int32 values, ascending powers of u
    error_bound_lsb: float


def quantize_axis(coef, what="axis"):
    """Q format and int32 coefficients for one axis' delta polynomial.

    Parameters
    ----------
    coef : sequence of float
        Coefficients in reading LSB, ascending powers of u.
    what : str, optional
        Names the axis in error messages.

    Returns
    -------
    QuantizedAxis
        q (the most fraction bits whose Horner sums fit int32), the int32
        coefficients, and a bound on |fixed delta - float delta| in LSB.

    Raises
    ------
    RangeError
        A non-finite coefficient, or one too large for int32 even at Q0.

    Examples
    --------
    >>> qa = quantize_axis([12.5, -3.25, 0.75])
    >>> qa.q, qa.coef
    (26, (838860800, -218103808, 50331648))
    """
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


# ---- compact form (csrc/include/sig_tcomp16.h) ---------------------------------------
from fractions import Fraction  # noqa: E402  (exact re-expansion of the float polynomial)

# int16 multiplicands and 16x16 products only: v = t - t_lo in 0.01 °C (exact,
# unscaled), w = v << w_shift, Horner with a fixed 16-bit shift per level.
# Level k of a polynomial of order n carries p_k(v) = sum_{i>=k} d_i v^(i-k)
# with 2^E_k units per LSB / (0.01 °C)^k: E_1 = 16, E_(k+1) = E_k + 16 - w_shift.
COMPACT_MAX_ORDER = 5
COMPACT_MAX_ERROR_LSB = 0.25    # quantize_compact refuses a larger (measured) error


@dataclass(frozen=True)
class CompactModel:
    """Fields of sig_tcomp16_init and what quantisation cost.  top[a] is the
    int16 highest-level coefficient of axis a, add[a] its int32 constants in
    evaluation order (add_(n-1) .. add_1, add_0).  error_lsb[a] is the largest
    |compact correction (before its final rounding) - float64 delta| over every
    0.01 °C of [t_lo, t_hi]: exact, not an estimate; an output is then within
    0.5 + error_lsb LSB of the float64 compensation (unless it saturates)."""
    t_lo: int
    t_hi: int
    w_shift: int
    top: tuple
    add: tuple
    error_lsb: tuple

    @property
    def order(self):
        return len(self.add[0])

    def fields(self):
        return {"top": list(self.top), "add": [list(r) for r in self.add], "t_lo": self.t_lo,
                "t_hi": self.t_hi, "w_shift": self.w_shift}


def _compose_in_v(coef, scaling, what):
    """Exact coefficients d_i (Fractions, LSB per (0.01 °C)^i) of the float
    polynomial in u = (T - center) / scale, rewritten in v = t - t_lo."""
    center = Fraction(scaling.center_c)
    scale = Fraction(scaling.scale_c)
    alpha = (Fraction(scaling.t_lo, scaling.units_per) - center) / scale       # u at v = 0
    beta = 1 / (scaling.units_per * scale)                                       # du / dv
    d = [Fraction(0)] * len(coef)
    power = [Fraction(1)]                                                 # (alpha + beta v)^k
    for k, c in enumerate(coef):
        if not math.isfinite(c):
            raise RangeError(f"{what}: non-finite coefficient {c}")
        if k > 0:
            nxt = [Fraction(0)] * (len(power) + 1)
            for i, p in enumerate(power):
                nxt[i] += p * alpha
                nxt[i + 1] += p * beta
            power = nxt
        for i, p in enumerate(power):
            d[i] += Fraction(c) * p
    return d


def _round_fraction(x):
    return math.floor(x + Fraction(1, 2))


def compact_eval(top, add, w_shift, v):
    """The compact correction before its final floor, in LSB (numpy int64 v
    array in, float64 out): (h_1 v + add_0 - 2^15) / 2^16.  Intermediates
    stay far inside int64."""
    v = np.asarray(v, dtype=np.int64)
    w = v << w_shift
    h = np.full(v.shape, int(top), dtype=np.int64)
    for c in add[:-1]:
        h = (h * w + int(c)) >> 16
    return (h * v + int(add[-1]) - (1 << 15)) / 65536.0


def _compact_axis_accepted(cls, top, add, scaling, w_shift):
    """True when sig_tcomp16_init accepts one axis (its no-overflow bound)."""
    try:
        cls.from_fields([top], [list(add)], scaling.t_lo, scaling.t_hi, w_shift)
    except RangeError:
        return False
    return True


def quantize_compact(model, max_error_lsb=COMPACT_MAX_ERROR_LSB, what="compact form"):
    """The compact (16x16-multiply) form of a model, for sig_tcomp16.

    Parameters
    ----------
    model : TcompModel
        A fitted model (pysig.tcomp._poly_model), in °C or raw codes.
    max_error_lsb : float, optional
        The largest accepted |compact correction - float64 delta|, LSB.
    what : str, optional
        Names the model in error messages.

    Returns
    -------
    CompactModel
        The fields of sig_tcomp16_init and the error per axis, measured
        exactly at every step of t over the range against the model's
        float64 delta.

    Raises
    ------
    RangeError
        Naming the axis and the limit it breaks: order above 5, a range
        wider than 327.67 °C (order >= 2), a drift whose Horner partial sums
        the int16 levels cannot hold (sig_tcomp16_init's bound: e.g. a slope
        of 50 LSB/°C or more), or a measured error above `max_error_lsb`.

    Examples
    --------
    >>> from pysig.sim._chamber import ChamberParams, simulate
    >>> from pysig.tcomp._poly_fit import fit_tcomp
    >>> run = simulate(ChamberParams(dwell_s=600.0))
    >>> compact = quantize_compact(fit_tcomp(run["temp"], {"x": run["x"]}, order=2))
    >>> compact.t_lo, compact.t_hi, compact.top
    (-19, 7012, (1605,))
    >>> [round(e, 2) for e in compact.error_lsb]
    [0.07]
    >>> quantize_compact(fit_tcomp(run["temp"], {"x": run["x"]}, order=6))
    Traceback (most recent call last):
        ...
    pysig.errors.RangeError: compact form: order 6 is not supported (1..5)
    """
    from ._tcomp16 import Tcomp16Q
    s = model.scaling
    order = int(model.order)
    if not 1 <= order <= COMPACT_MAX_ORDER:
        raise RangeError(f"{what}: order {order} is not supported (1..{COMPACT_MAX_ORDER})")
    v_max = s.t_hi - s.t_lo
    w_shift = 0
    while (v_max << (w_shift + 1)) <= 0xFFFF and w_shift < 15:
        w_shift += 1
    if order > 1 and w_shift < 1:
        raise RangeError(f"{what}: calibrated range {s.t_lo / 100:.2f}..{s.t_hi / 100:.2f} °C is "
                         f"wider than 327.67 °C (order >= 2 needs (t_hi - t_lo) * 2 <= 65535)")
    exps = [16]
    for _ in range(order - 1):
        exps.append(exps[-1] + 16 - w_shift)              # exps[k-1] = E_k
    v = np.arange(v_max + 1, dtype=np.int64)
    temp = (s.t_lo + v) / s.units_per
    tops, adds, errors = [], [], []
    for axis, name in enumerate(model.axes):
        where = f"{what}, axis '{name}'"
        d = _compose_in_v([float(c) for c in model.coef[axis]], s, where)
        top = _round_fraction(d[order] * Fraction(2) ** exps[order - 1])
        add = [_round_fraction(d[k] * Fraction(2) ** (exps[k - 1] + 16)) + (1 << 15)
               for k in range(order - 1, 0, -1)]
        add.append(_round_fraction(d[0] * 65536) + (1 << 15))
        if not -32768 <= top <= 32767 or not all(-(1 << 31) <= c <= INT32_MAX for c in add) \
                or not _compact_axis_accepted(Tcomp16Q, top, add, s, w_shift):
            slope = max(abs(float(sum(k * d[k] * Fraction(int(x)) ** (k - 1)
                                      for k in range(1, order + 1)))) for x in (0, v_max)) * 100
            raise RangeError(
                f"{where}: the drift does not fit the int16 levels of the compact form "
                f"(slope up to {slope:.3g} LSB/°C at the range ends; the form holds Horner "
                f"partial sums below 0.5 LSB per 0.01 °C^k): use the int32 form (sig_tcomp)")
        user_temp = model.temp_code.from_domain(temp) if hasattr(model, "temp_code") else temp
        err = float(np.max(np.abs(compact_eval(top, add, w_shift, v) - model.delta(user_temp, axis))))
        if err > max_error_lsb:
            raise RangeError(f"{where}: compact quantisation error {err:.3f} LSB exceeds "
                             f"{max_error_lsb} LSB over {s.t_lo / 100:.2f}..{s.t_hi / 100:.2f} °C "
                             f"(it grows with the range width): use the int32 form (sig_tcomp)")
        tops.append(top)
        adds.append(tuple(add))
        errors.append(err)
    return CompactModel(s.t_lo, s.t_hi, w_shift, tuple(tops), tuple(adds), tuple(errors))
