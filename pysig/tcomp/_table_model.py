"""The table family of temperature models: per axis a piecewise-linear
table delta(T) = f(T) - f(T0) on uniform knots shared by the axes, in the
fixed-point form of csrc/include/sig_pwl.h (evaluated on the device by sig_tmodel),
with the float twin it was quantised from.

Knots sit where the C puts them: knot k at t_lo + k * 2^32 / recip in the
int16 temperature t (pysig.tcomp._tempcode), so the float table and the fixed
one share their knots exactly and differ only by the rounding of the entries
(2^-(value_frac+1)) and of the interpolation fraction (Q0.12).  That error is
measured, not bounded: at every t of [t_lo, t_hi] the C evaluation is
compared with the float table (`error_lsb`)."""
from dataclasses import dataclass, field

import numpy as np

from . import _pwl
from ._poly_model import FORMAT, VERSION_TABLES, with_checksum
from ._table_fit import MAX_KNOTS, MIN_KNOTS, _solve, knot_offsets_q16, plan_q16, quantize_values
from ._tempcode import TempCode
from ..errors import InsufficientDataError, ModelFileError, RangeError
from ..io import write_json


@dataclass
class TableModel:
    """Tables of `n_knots` uniform knots over [t_lo, t_hi] (int16 t), one per axis."""
    axes: list
    t0: float                  # reference temperature, in the model's unit (°C or code domain)
    t_lo: int
    t_hi: int
    recip: int                 # segments per t unit, Q0.32 (sig_pwl.h)
    values: list               # per axis: float delta at the knots (reading units)
    f_t0: list                 # per axis: f(T0)
    table: list                # per axis: int16 entries
    value_frac: list           # per axis
    error_lsb: list            # per axis: max |fixed - float| over every t of the range
    temp_code: TempCode
    temp_column: str = "temp"
    value_scale: float = 1.0
    report: dict = field(default_factory=dict)

    family = "table"

    @property
    def n_knots(self):
        return len(self.table[0])

    @property
    def size(self):
        return self.n_knots

    @property
    def knots_t(self):
        """Knot positions in t (real numbers)."""
        return self.t_lo + np.asarray(knot_offsets_q16(self.n_knots, self.recip))

    @property
    def lo(self):
        """Calibrated range in the model's float unit."""
        return self.t_lo / self.temp_code.units_per_degree

    @property
    def hi(self):
        return self.t_hi / self.temp_code.units_per_degree

    def delta(self, temp, axis):
        """Float delta at temperatures in the column's unit, clamped to the range."""
        t = np.clip(self.temp_code.domain(temp) * self.temp_code.units_per_degree, self.t_lo, self.t_hi)
        return np.interp(t, self.knots_t, self.values[axis])

    def clamped(self, temp):
        t = self.temp_code.domain(temp) * self.temp_code.units_per_degree
        return (t < self.t_lo) | (t > self.t_hi)

    def apply_float(self, temp, readings):
        return [np.asarray(x, dtype=float) - self.delta(temp, a) for a, x in enumerate(readings)]

    def to_dict(self):
        return {"format": FORMAT, "version": VERSION_TABLES, "family": "table", "axes": list(self.axes),
                "temp_column": self.temp_column, "temp": self.temp_code.to_dict(),
                "value_scale": float(self.value_scale), "t0": float(self.t0),
                "range": [self.lo, self.hi],
                "float": {"values": [list(map(float, v)) for v in self.values],
                          "f_t0": list(map(float, self.f_t0))},
                "fixed": {"t_lo": int(self.t_lo), "t_hi": int(self.t_hi), "recip": int(self.recip),
                          "n_knots": self.n_knots, "value_frac": list(map(int, self.value_frac)),
                          "table": [list(map(int, t)) for t in self.table],
                          "error_lsb": list(map(float, self.error_lsb))},
                "report": self.report}

    def save(self, path):
        d = self.to_dict()
        write_json(path, with_checksum(d))


def from_dict(d, where="model"):
    """TableModel from its JSON dict (checksum already verified)."""
    try:
        fx, fl = d["fixed"], d["float"]
        model = TableModel(axes=list(d["axes"]), t0=float(d["t0"]), t_lo=int(fx["t_lo"]),
                           t_hi=int(fx["t_hi"]), recip=int(fx["recip"]),
                           values=[np.array(v, dtype=float) for v in fl["values"]],
                           f_t0=[float(v) for v in fl["f_t0"]],
                           table=[np.array(t, dtype=np.int16) for t in fx["table"]],
                           value_frac=[int(v) for v in fx["value_frac"]],
                           error_lsb=[float(v) for v in fx["error_lsb"]],
                           temp_code=TempCode.from_dict(d["temp"]),
                           temp_column=str(d.get("temp_column", "temp")),
                           value_scale=float(d.get("value_scale", 1.0)), report=d.get("report", {}))
    except (KeyError, TypeError, ValueError, OverflowError) as exc:
        raise ModelFileError(f"{where}: malformed table model: {exc!r}") from None
    n = len(model.axes)
    if not 1 <= n <= 3 or any(len(x) != n for x in (model.values, model.table, model.value_frac)):
        raise ModelFileError(f"{where}: table model needs 1..3 axes with one table each")
    if any(len(t) != model.n_knots or len(v) != model.n_knots for t, v in zip(model.table, model.values)):
        raise ModelFileError(f"{where}: every axis' table must hold {model.n_knots} knots")
    for a, vf in enumerate(model.value_frac):
        try:
            _pwl.eval_q16(model.table[a], model.t_lo, model.t_hi, model.recip, vf, np.zeros(0, np.int16))
        except RangeError:
            raise ModelFileError(f"{where}: table {a}: parameters sig_pwl_init_q16 rejects") from None
    return model


def fixed_error(t_lo, t_hi, recip, knots_t, values, table, value_frac):
    """max |C fixed-point value - float table| over every t of [t_lo, t_hi]."""
    t = np.arange(t_lo, t_hi + 1, dtype=np.int64)
    q, _ = _pwl.eval_q16(table, t_lo, t_hi, recip, value_frac, t.astype(np.int16))
    return float(np.max(np.abs(q / 65536.0 - np.interp(t, knots_t, values))))


def fit_table(temp, columns, n_knots, t0, temp_code, temp_column="temp", what="fit"):
    """TableModel of `n_knots` knots over the data's range.

    Parameters
    ----------
    temp : array
        Temperatures in the column's unit (°C or raw codes, see `temp_code`).
    columns : dict
        Axis name -> readings (1..3 axes, already in the firmware's reading code).
    n_knots : int
        2..255 knots, at least one t unit apart.
    t0 : float
        Reference temperature (column unit), inside the range.
    temp_code : pysig.tcomp._tempcode.TempCode

    Raises
    ------
    RangeError
        Knot count outside 2..255 or denser than the t unit, T0 outside the
        range, a delta beyond the int16 table.
    InsufficientDataError
        A knot with no data within one knot spacing.
    """
    if not isinstance(n_knots, (int, np.integer)) or not MIN_KNOTS <= n_knots <= MAX_KNOTS:
        raise RangeError(f"{what}: a table needs {MIN_KNOTS}..{MAX_KNOTS} knots, got {n_knots!r}")
    x = temp_code.domain(temp)
    t_int = temp_code.to_t(temp, "raise", what)
    t_lo, t_hi = int(t_int.min()), int(t_int.max())
    if t_hi <= t_lo:
        raise InsufficientDataError(f"{what}: all temperatures are equal: a table needs a range")
    recip = plan_q16(t_lo, t_hi, int(n_knots), what)
    knots_t = t_lo + np.asarray(knot_offsets_q16(int(n_knots), recip))
    units = temp_code.units_per_degree
    t0_dom = float(temp_code.domain(t0))
    if not t_lo <= t0_dom * units <= t_hi:
        raise RangeError(f"{what}: reference temperature T0 = {t0} {temp_code.name} is outside the "
                         f"calibrated range {temp_code.label(t_lo / units)}..{temp_code.label(t_hi / units)}")
    values, f_t0, tables, fracs, errors = [], [], [], [], []
    for name, y in columns.items():
        v, _ = _solve(x * units, np.asarray(y, dtype=float), knots_t, False, f"{what} column '{name}'")
        f0 = float(np.interp(t0_dom * units, knots_t, v))
        d = v - f0
        table, vf = quantize_values(d, f"{what} column '{name}'")
        values.append(d)
        f_t0.append(f0)
        tables.append(table)
        fracs.append(vf)
        errors.append(fixed_error(t_lo, t_hi, recip, knots_t, d, table, vf))
    return TableModel(axes=list(columns), t0=t0_dom, t_lo=t_lo, t_hi=t_hi, recip=recip, values=values,
                      f_t0=f_t0, table=tables, value_frac=fracs, error_lsb=errors, temp_code=temp_code,
                      temp_column=temp_column)
