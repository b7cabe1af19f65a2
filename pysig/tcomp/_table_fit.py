"""Piecewise-linear lookup tables with uniform knots: least-squares fit on
the hat-function basis (pysig.lsq.fit_linear_model, the one solver) and
quantisation to the fixed-point form of csrc/tcomp/sig_pwl.c.

A table with knots k_0 < ... < k_{n-1} (uniform) is f(T) = sum_j v_j h_j(T),
h_j the hat function that is 1 at k_j and 0 at the neighbouring knots, so
the knot values v_j are the least-squares coefficients.  Outside
[k_0, t_hi] the table is flat (the C flags it SIG_WARN_CLAMPED).

The fixed-point form places its knots where the C puts them: the segment
position is d * recip / 2^32, d = t - t_lo in the integer temperature unit,
so knot k is at t_lo + k * 2^32 / recip units exactly; the fixed-point table is fitted on those knots, then rounded to
int16 with the largest value_frac (fraction bits) that fits."""
from dataclasses import dataclass

import numpy as np

from . import _pwl
import struct

from ..errors import InsufficientDataError, ModelFileError, NonFiniteError, RangeError
from ..store._image import SECTION_PWL_TABLE, build_image, find_section
from ..lsq import finite_pairs, fit_linear_model

FRAC_BITS = 12          # SIG_PWL_FRAC_BITS
MIN_KNOTS = 2
MAX_KNOTS = 255
#: the int16 temperature unit of the temperature-compensation module
#: (csrc/include/sig_tcomp.h, SIG_TCOMP_T_PER_DEGC): 0.01 °C.
TEMP_UNITS_PER_C = 100
#: bytes of the fixed-point parameters besides the table: recip (uint32),
#: t_lo, t_hi (int16), n_knots, value_frac (uint8).
Q16_HEADER_BYTES = 10


@dataclass(frozen=True)
class PwlFit:
    """Float table: values at uniform knots knots[0] + k * step, flat outside
    [knots[0], t_hi]."""
    knots: np.ndarray
    values: np.ndarray
    t_hi: float
    rms: float                 # in-sample residual RMS of the fit

    @property
    def n_knots(self):
        return len(self.knots)

    @property
    def t_lo(self):
        return float(self.knots[0])

    @property
    def inv_step(self):
        return 1.0 / float(self.knots[1] - self.knots[0])

    def __call__(self, temp):
        """Evaluate in numpy (the model; the C float form is eval_c)."""
        t = np.clip(np.asarray(temp, dtype=float), self.t_lo, self.t_hi)
        return np.interp(t, self.knots, self.values)

    def eval_c(self, temp):
        """(values, status) from csrc sig_pwl_eval_f."""
        return _pwl.eval_f(self.values, self.t_lo, self.t_hi, self.inv_step, temp)

    @property
    def data_bytes(self):
        """float32 table + t_lo, t_hi, inv_step (float32) + n_knots (uint8)."""
        return 4 * self.n_knots + 13


@dataclass(frozen=True)
class PwlQ16:
    """Fixed-point table for sig_pwl_eval_q16 (see sig_pwl.h for the format).
    `units_per_c` converts °C to the int16 temperature unit: t = round(T * units_per_c)."""
    table: np.ndarray          # int16, value = entry * 2^-value_frac
    t_lo: int
    t_hi: int
    recip: int                 # segments per temperature unit, Q0.32
    value_frac: int
    units_per_c: float
    rms: float                 # in-sample RMS of the fixed-point table on the fitted data

    @property
    def n_knots(self):
        return len(self.table)

    @property
    def data_bytes(self):
        return 2 * self.n_knots + Q16_HEADER_BYTES

    def knots_c(self):
        """Exact knot temperatures in °C."""
        return (self.t_lo + np.asarray(knot_offsets_q16(self.n_knots, self.recip))) \
            / self.units_per_c

    def temp_int(self, temp_c):
        """°C -> the int16 temperature unit (rounded, saturated)."""
        return temp_to_int(temp_c, self.units_per_c)

    def eval_c(self, temp_int):
        """(Q16.16 int32 values, status) from csrc sig_pwl_eval_q16."""
        return _pwl.eval_q16(self.table, self.t_lo, self.t_hi, self.recip, self.value_frac,
                             temp_int)

    def __call__(self, temp_c):
        """Value in the data's unit of the C fixed-point evaluation at °C temperatures."""
        q, _ = self.eval_c(self.temp_int(temp_c))
        return q / 65536.0


def temp_to_int(temp_c, units_per_c):
    """°C -> int16 temperature units: rounded to nearest (half to even),
    saturated to int16 (the rule of pysig.tcomp._tempcode for applying a
    model: the C then clamps and flags)."""
    from ._tempcode import to_int16
    x = np.asarray(temp_c, dtype=float) * float(units_per_c)
    if not np.all(np.isfinite(x)):
        raise NonFiniteError("pwl: non-finite temperature")
    return to_int16(x, "saturate").astype(np.int16)


def knot_offsets_q16(n_knots, recip):
    """Exact knot positions as offsets from t_lo, in temperature units: knot
    k where d * recip / 2^32 == k."""
    return [k * float(1 << 32) / recip for k in range(n_knots)]


def params_valid_q16(n_knots, t_lo, t_hi, recip, value_frac):
    """True when sig_pwl_init_q16 (the C itself) accepts the parameters."""
    if not (MIN_KNOTS <= n_knots <= MAX_KNOTS and -32768 <= t_lo <= 32767 and -32768 <= t_hi <= 32767
            and 0 < recip < 1 << 32 and 0 <= value_frac <= 15):
        return False
    try:
        _pwl.eval_q16(np.zeros(n_knots, np.int16), t_lo, t_hi, recip, value_frac, np.zeros(0, np.int16))
    except RangeError:
        return False
    return True


def _check_data(temp, y, what):
    temp, y = finite_pairs(temp, y, what, names=("temperature", "value"))
    if temp.size == 0:
        raise InsufficientDataError(f"{what}: no data")
    return temp, y


def _check_n_knots(n_knots, what):
    if not isinstance(n_knots, (int, np.integer)) or not MIN_KNOTS <= n_knots <= MAX_KNOTS:
        raise RangeError(f"{what}: a table needs {MIN_KNOTS}..{MAX_KNOTS} knots, got {n_knots!r}")


def _check_range(temp, lo, hi, what):
    tmin, tmax = float(temp.min()), float(temp.max())
    lo = tmin if lo is None else float(lo)
    hi = tmax if hi is None else float(hi)
    if not (np.isfinite(lo) and np.isfinite(hi)):
        raise NonFiniteError(f"{what}: non-finite table range [{lo}, {hi}]")
    if lo < tmin or hi > tmax:
        raise RangeError(f"{what}: knots span [{lo:g}, {hi:g}] °C but the data only covers "
                         f"[{tmin:g}, {tmax:g}] °C; a knot outside the data has nothing to fit")
    if not hi > lo:
        raise RangeError(f"{what}: empty table range [{lo:g}, {hi:g}] °C")
    return lo, hi


def hat_basis(temp, knots):
    """Design matrix (len(temp) x len(knots)) of the hat functions on uniform
    knots; temperatures beyond the last knot are flat (weight on it only)."""
    knots = np.asarray(knots, dtype=float)
    step = knots[1] - knots[0]
    pos = np.clip((np.asarray(temp, dtype=float) - knots[0]) / step, 0.0, len(knots) - 1.0)
    seg = np.minimum(np.floor(pos).astype(int), len(knots) - 2)
    frac = pos - seg
    design = np.zeros((pos.size, len(knots)))
    rows = np.arange(pos.size)
    design[rows, seg] = 1.0 - frac
    design[rows, seg + 1] += frac
    return design


#: weight of the smoothness rows that bridge data gaps (relative to a data row)
BRIDGE_WEIGHT = 1e-3


def _solve(temp, y, knots, bridge, what):
    design = hat_basis(temp, knots)
    n = len(knots)
    if np.linalg.matrix_rank(design) == n:
        values, resid = fit_linear_model(design, y, what=what)
        return values, float(np.sqrt(np.mean(resid ** 2)))
    if not bridge:
        # a knot touched only by rounding (a point sitting on its neighbour)
        # has no data of its own either
        empty = np.flatnonzero(design.sum(axis=0) <= 1e-9)
        if empty.size:
            k = int(empty[0])
            raise InsufficientDataError(
                f"{what}: knot {k} at {knots[k]:.4g} °C has no data within one knot spacing "
                f"({knots[1] - knots[0]:.4g} °C); use fewer knots")
        raise InsufficientDataError(
            f"{what}: {n} knots are not determined by the {np.unique(temp).size} distinct "
            f"temperatures between them; use fewer knots")
    # Knots the data does not determine (a held-out block in cross-validation)
    # are tied to their neighbours by a zero second difference: the table is
    # linear across the gap.  "Not determined": less than half a data point's
    # weight on the knot (a gap, or only the tail of a point that sits on the
    # neighbouring knot).  Each such row has an unknown of its own, so the
    # determined knots keep their least-squares values.
    weak = np.flatnonzero(design.sum(axis=0) < 0.5)
    rows = np.zeros((weak.size, n))
    for r, k in enumerate(weak):
        c = min(max(int(k), 1), n - 2)
        rows[r, c - 1:c + 2] = (1.0, -2.0, 1.0)
    full = np.vstack([design, rows])
    if np.linalg.matrix_rank(full) < n:
        # still short (isolated points far apart): a faint smoothness prior
        smooth = np.zeros((n - 2, n))
        for r in range(n - 2):
            smooth[r, r:r + 3] = (BRIDGE_WEIGHT, -2.0 * BRIDGE_WEIGHT, BRIDGE_WEIGHT)
        full = np.vstack([full, smooth])
    if np.linalg.matrix_rank(full) < n:
        raise InsufficientDataError(f"{what}: fewer than 2 distinct temperatures to fit a table")
    target = np.concatenate([y, np.zeros(full.shape[0] - y.size)])
    values, _ = fit_linear_model(full, target, what=what)
    resid = y - design @ values
    return values, float(np.sqrt(np.mean(resid ** 2)))


def fit_pwl(temp, y, n_knots, lo=None, hi=None, bridge=False, what="pwl fit"):
    """Least-squares table of values at uniform knots (linear between
    knots, flat outside), the float form of ``sig_pwl``.

    Parameters
    ----------
    temp, y : array_like
        Temperatures (°C) and readings, the same length.
    n_knots : int
        2..255 uniform knots.
    lo, hi : float, optional
        The table's range, °C (default: the data's range); inside the data.
    bridge : bool, optional
        Make the table linear across knots with no data near them (as
        cross-validation needs) instead of refusing.
    what : str, optional
        The command named in error messages.

    Returns
    -------
    PwlFit
        ``knots``, ``values``, ``t_hi`` and the in-sample residual ``rms``.

    Raises
    ------
    RangeError
        Fewer than 2 or more than 255 knots, or a range outside the data.
    InsufficientDataError
        A knot with no data near it (unless `bridge`).
    NonFiniteError
        A non-finite temperature or reading.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 60.0, 61)
    >>> f = fit_pwl(t, np.abs(t - 30.0), 3)
    >>> f.knots.tolist(), np.allclose(f.values, [30.0, 0.0, 30.0]), f.rms < 1e-9
    ([0.0, 30.0, 60.0], True, True)
    """
    temp, y = _check_data(temp, y, what)
    _check_n_knots(n_knots, what)
    lo, hi = _check_range(temp, lo, hi, what)
    knots = np.linspace(lo, hi, int(n_knots))
    values, rms = _solve(temp, y, knots, bridge, what)
    return PwlFit(knots=knots, values=values, t_hi=hi, rms=rms)


def plan_q16(t_lo, t_hi, n_knots, what="pwl"):
    """recip (segments per temperature unit, Q0.32) for sig_pwl_q16, rounded
    down so the last knot is at or just past t_hi."""
    span = int(t_hi) - int(t_lo)
    if not 0 < span <= 65535:
        raise RangeError(f"{what}: temperature span of {span} units; the table needs 1..65535")
    if int(n_knots) - 1 >= span:
        raise RangeError(f"{what}: {n_knots} knots over {span} temperature units would be closer "
                         f"than one unit; use fewer knots")
    recip = ((int(n_knots) - 1) << 32) // span
    if not params_valid_q16(int(n_knots), int(t_lo), int(t_hi), recip, 0):
        raise RangeError(f"{what}: no valid position mapping for {n_knots} knots over {span} units")
    return recip


def quantize_values(values, what="pwl"):
    """(int16 table, value_frac): the largest value_frac <= 15 whose rounded
    entries fit int16."""
    values = np.asarray(values, dtype=float)
    for vf in range(15, -1, -1):
        q = np.round(values * (1 << vf))
        if np.all(np.abs(q) <= 32767):
            return q.astype(np.int16), vf
    raise RangeError(f"{what}: table values up to {np.max(np.abs(values)):g} exceed the int16 "
                     f"table's range (±32767)")


def fit_pwl_q16(temp, y, n_knots, units_per_c=TEMP_UNITS_PER_C, lo=None, hi=None, bridge=False, what="pwl fit"):
    """Fixed-point table for sig_pwl_eval_q16: integer range inside the data
    (lo rounded up, hi down, in units of 1/units_per_c °C), knots where the C
    puts them, least squares on those knots, int16 rounding.  The reported
    rms is that of the C evaluation on the data."""
    temp, y = _check_data(temp, y, what)
    _check_n_knots(n_knots, what)
    lo, hi = _check_range(temp, lo, hi, what)
    scale = float(units_per_c)
    t_lo, t_hi = int(np.ceil(lo * scale - 1e-9)), int(np.floor(hi * scale + 1e-9))
    if not (-32768 <= t_lo < t_hi <= 32767):
        raise RangeError(f"{what}: range [{lo:g}, {hi:g}] °C is not an int16 span in units of "
                         f"1/{scale:g} °C")
    recip = plan_q16(t_lo, t_hi, n_knots, what)
    knots = (t_lo + np.asarray(knot_offsets_q16(int(n_knots), recip))) / scale
    values, _ = _solve(temp, y, knots, bridge, what)
    table, vf = quantize_values(values, what)
    tab = PwlQ16(table=table, t_lo=t_lo, t_hi=t_hi, recip=recip, value_frac=vf,
                 units_per_c=scale, rms=0.0)
    resid = y - tab(temp)
    return PwlQ16(table=table, t_lo=t_lo, t_hi=t_hi, recip=recip, value_frac=vf,
                  units_per_c=scale, rms=float(np.sqrt(np.mean(resid ** 2))))


# ---- coefficient image (section SECTION_PWL_TABLE, payload in sig_pwl.h) ----

PAYLOAD_FIXED_LEN = 10
MAX_AXES = 3


def pwl_payload(tables):
    """Payload bytes for 1..3 fixed-point tables sharing knots and range."""
    tables = list(tables)
    if not 1 <= len(tables) <= MAX_AXES:
        raise RangeError(f"pwl image: 1..{MAX_AXES} tables, got {len(tables)}")
    t0 = tables[0]
    for i, t in enumerate(tables[1:], 1):
        if (t.n_knots, t.t_lo, t.t_hi, t.recip) != (t0.n_knots, t0.t_lo, t0.t_hi, t0.recip):
            raise RangeError(f"pwl image: table {i} has other knots or range than table 0 "
                             f"(one section shares them)")
    out = struct.pack("<BBhhI", len(tables), t0.n_knots, t0.t_lo, t0.t_hi, t0.recip)
    for t in tables:
        out += struct.pack("<B", t.value_frac) + struct.pack(f"<{t.n_knots}h", *map(int, t.table))
    return out


def parse_pwl_payload(payload, units_per_c=TEMP_UNITS_PER_C, where="image"):
    """The reference reader of pwl_payload: a list of PwlQ16 (rms unknown:
    NaN).  ModelFileError for a payload the C loader would reject."""
    payload = bytes(payload)
    if len(payload) < PAYLOAD_FIXED_LEN:
        raise ModelFileError(f"{where}: table section of {len(payload)} bytes, shorter than "
                             f"its {PAYLOAD_FIXED_LEN}-byte header")
    axes, n, t_lo, t_hi, recip = struct.unpack_from("<BBhhI", payload)
    if not 1 <= axes <= MAX_AXES or n < MIN_KNOTS:
        raise ModelFileError(f"{where}: table section with {axes} axes of {n} knots")
    stride = 1 + 2 * n
    if len(payload) != PAYLOAD_FIXED_LEN + axes * stride:
        raise ModelFileError(f"{where}: table section of {len(payload)} bytes, expected "
                             f"{PAYLOAD_FIXED_LEN + axes * stride} for {axes} x {n} knots")
    out = []
    for a in range(axes):
        off = PAYLOAD_FIXED_LEN + a * stride
        vf = payload[off]
        if not params_valid_q16(n, t_lo, t_hi, recip, vf):
            raise ModelFileError(f"{where}: table {a}: invalid parameters (t_lo {t_lo}, t_hi "
                                 f"{t_hi}, recip {recip}, value_frac {vf})")
        table = np.array(struct.unpack_from(f"<{n}h", payload, off + 1), dtype=np.int16)
        out.append(PwlQ16(table=table, t_lo=t_lo, t_hi=t_hi, recip=recip, value_frac=vf,
                          units_per_c=float(units_per_c), rms=float("nan")))
    return out


def pwl_image(tables, sequence=1):
    """A complete coefficient image holding one table section."""
    return build_image([(SECTION_PWL_TABLE, pwl_payload(tables))], sequence)


def read_pwl_image(data, units_per_c=TEMP_UNITS_PER_C, where="image"):
    """Tables of an image (reference reader; the firmware's is sig_pwl_load_image)."""
    return parse_pwl_payload(find_section(data, SECTION_PWL_TABLE, where), units_per_c, where)
