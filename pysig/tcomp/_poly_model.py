"""The temperature-compensation model: what pysig.tcomp._poly_fit produces, what
`pysig apply` uses and what `pysig export` turns into a C header or an NVM
image.  Saved as JSON with a format name, a version and a checksum; loading
anything else raises ModelFileError.

The checksum ("sha256:<hex>") covers the canonical JSON of every other field
(sorted keys, no whitespace), so reformatting the file keeps it valid but any
changed value, including a hand edit, is refused.  A file without a checksum
is refused too (deliberately: it cannot be told from a corrupt one); re-run
`pysig fit` to write a checked file.

Per axis the model holds delta(u) = f(T) - f(T0) as float64 coefficients in
ascending powers of u = (T - center) / scale (°C), and its fixed-point twin
(sig_tcomp.h): int32 coefficients in Q(q) with the int16 temperature scaling
(0.01 °C) chosen by pysig.tcomp._quant."""
import hashlib
import json
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ModelFileError, NonFiniteError
from ..io import read_json, write_json
from ._quant import T_PER_DEGC, TemperatureScaling
from ._tempcode import CELSIUS, TempCode

MAX_AXES = 3
MAX_ORDER = 8
MAX_Q = 30

FORMAT = "pysig-tcomp"
VERSION = 1
VERSION_TABLES = 2   # adds "family" (poly / table), "temp" (pysig.tcomp._tempcode) and "value_scale"
CHECKSUM_KEY = "checksum"


def checksum(d):
    """sha256 of the canonical JSON of `d` without its checksum field."""
    body = {k: v for k, v in d.items() if k != CHECKSUM_KEY}
    canonical = json.dumps(body, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return "sha256:" + hashlib.sha256(canonical.encode()).hexdigest()


def with_checksum(d):
    """`d` with its checksum field set (what a model file holds)."""
    d[CHECKSUM_KEY] = checksum(d)
    return d


@dataclass
class TcompModel:
    """A fitted temperature-compensation model (made by
    `pysig.tcomp._poly_fit.fit_tcomp`, read back by `load`).

    corrected = reading - delta(T), delta(T) = f(T) - f(T0), per axis; the
    temperature is clamped to the calibrated range [t_lo, t_hi].

    Parameters
    ----------
    axes : list of str
        Column names, 1 to 3.
    order : int
        Polynomial order, 1..8.
    t0 : float
        Reference temperature, °C.
    scaling : TemperatureScaling
        The int16 temperature scaling (0.01 °C) the C model uses.
    coef : list of ndarray
        Per axis: order + 1 float coefficients of delta, ascending powers of
        u = (T - center) / scale.
    f_t0 : list of float
        Per axis: f(T0), the reading at T0 (information).
    q, coef_q : list
        Per axis: fraction bits and int32 coefficients of the fixed form.
    error_bound_lsb : list of float
        Per axis: bound of |fixed delta - float delta|.
    temp_column : str, optional
        The temperature column's name.
    report : dict, optional
        What the fit measured (groups, RMS, conditioning, CV table).

    Examples
    --------
    >>> import numpy as np
    >>> from pysig.sim._chamber import ChamberParams, simulate
    >>> from pysig.tcomp._poly_fit import fit_tcomp
    >>> run = simulate(ChamberParams(dwell_s=600.0))
    >>> fit_tcomp(run["temp"], {"x": run["x"]}, order=2).save("model.json")
    >>> model = load("model.json")
    >>> model.order, model.axes, model.t_lo, model.t_hi
    (2, ['x'], -0.19, 70.12)
    >>> np.round(model.delta([0.0, 25.0, 70.0], 0), 1)     # zero at T0 = 25 °C
    array([ -4.3,   0. , 102. ])
    >>> [x] = model.apply_float([0.0, 70.0], [[3630.0, 3700.0]])
    >>> np.round(x, 1)
    array([3634.3, 3598. ])
    """
    axes: list                 # column names, 1..3
    order: int
    t0: float                  # reference temperature, °C
    scaling: TemperatureScaling
    coef: list                 # per axis: order + 1 floats, delta in reading units
    f_t0: list                 # per axis: f(T0), the reading at T0 (information)
    q: list                    # per axis: fraction bits of the fixed coefficients
    coef_q: list               # per axis: order + 1 ints
    error_bound_lsb: list      # per axis: bound of |delta_fixed - delta_float|
    temp_column: str = "temp"
    report: dict = field(default_factory=dict)
    temp_code: TempCode = CELSIUS   # how the temperature column maps to the firmware's int16 t
    value_scale: float = 1.0        # firmware reading code = column value * value_scale

    family = "poly"

    @property
    def size(self):
        return self.order

    # ---- ranges -----------------------------------------------------------
    @property
    def t_lo(self):
        return self.scaling.t_lo / self.scaling.units_per

    @property
    def t_hi(self):
        return self.scaling.t_hi / self.scaling.units_per

    # ---- float path (numpy) ------------------------------------------------
    def u_of(self, temp):
        """u of temperatures in the model's unit (°C or raw codes), clamped."""
        t = np.clip(self.temp_code.domain(temp), self.t_lo, self.t_hi)
        return (t - self.scaling.center_c) / self.scaling.scale_c

    def delta(self, temp, axis):
        """delta(T) of one axis (float64, temperature clamped to the range)."""
        return np.polynomial.polynomial.polyval(self.u_of(temp), self.coef[axis])

    def clamped(self, temp):
        t = self.temp_code.domain(temp)
        return (t < self.t_lo) | (t > self.t_hi)

    def apply_float(self, temp, readings):
        """readings: sequence of arrays, one per axis -> corrected arrays."""
        temp = np.asarray(temp, dtype=float)
        if np.isnan(temp).any():
            raise NonFiniteError(f"temperature: NaN at index {int(np.flatnonzero(np.isnan(temp))[0])}")
        return [np.asarray(x, dtype=float) - self.delta(temp, a) for a, x in enumerate(readings)]

    # ---- the C structs' fields --------------------------------------------
    def fixed_fields(self):
        s = self.scaling
        return {"coef": [list(c) for c in self.coef_q], "q": list(self.q), "t_lo": s.t_lo,
                "t_hi": s.t_hi, "t_center": s.t_center, "t0": int(round(self.t0 * self.scaling.units_per)),
                "u_mul": s.u_mul, "u_shift": s.u_shift}

    def float_fields(self):
        return {"coef": [list(c) for c in self.coef], "t_lo": self.t_lo, "t_hi": self.t_hi,
                "center": self.scaling.center_c, "inv_scale": 1.0 / self.scaling.scale_c}

    # ---- JSON --------------------------------------------------------------
    def to_dict(self):
        s = self.scaling
        d = {"format": FORMAT, "version": VERSION, "axes": list(self.axes),
                "temp_column": self.temp_column, "order": self.order, "t0_c": self.t0,
                "range_c": [self.t_lo, self.t_hi],
                "float": {"center_c": s.center_c, "scale_c": s.scale_c,
                          "coef": [list(map(float, c)) for c in self.coef],
                          "f_t0": list(map(float, self.f_t0))},
                "fixed": {"temp_unit": "0.01 degC", "t_lo": s.t_lo, "t_hi": s.t_hi,
                          "t_center": s.t_center, "u_mul": s.u_mul, "u_shift": s.u_shift,
                          "q": list(self.q), "coef": [list(map(int, c)) for c in self.coef_q],
                          "error_bound_lsb": list(map(float, self.error_bound_lsb))},
                "report": self.report}
        if self.temp_code != CELSIUS or self.value_scale != 1.0:
            d.update(version=2, family="poly", temp=self.temp_code.to_dict(),
                     value_scale=float(self.value_scale))
            d["fixed"]["temp_unit"] = "0.01 degC" if self.temp_code.unit == "c" else "raw code"
        return d

    def save(self, path):
        d = self.to_dict()
        write_json(path, with_checksum(d))


def from_dict(d, where="model", verify_checksum=False):
    """A TcompModel from the dict `TcompModel.to_dict` wrote, checked field by
    field; ModelFileError (naming `where`) for anything else."""
    if not isinstance(d, dict) or d.get("format") != FORMAT:
        raise ModelFileError(f"{where}: not a pysig temperature-compensation model "
                             f"(format {d.get('format') if isinstance(d, dict) else None!r}, "
                             f"expected {FORMAT!r})")
    if d.get("version") not in (VERSION, VERSION_TABLES):
        raise ModelFileError(f"{where}: model version {d.get('version')!r} is not supported "
                             f"(this pysig reads version {VERSION})")
    if d.get("family", "poly") != "poly":
        raise ModelFileError(f"{where}: a {d.get('family')!r} model, not a polynomial: "
                             f"read it with pysig.tcomp._calibration.load")
    if verify_checksum:
        if CHECKSUM_KEY not in d:
            raise ModelFileError(f"{where}: no checksum (written by an older pysig, or edited): "
                                 f"re-run pysig fit to write a checked model")
        try:
            ok = d[CHECKSUM_KEY] == checksum(d)
        except (TypeError, ValueError):         # a value JSON cannot write back (e.g. 1e999 -> inf)
            ok = False
        if not ok:
            raise ModelFileError(f"{where}: checksum mismatch: the file is corrupt or was edited")
    try:
        fx, fl = d["fixed"], d["float"]
        order = int(d["order"])
        axes = list(d["axes"])
        temp_code = TempCode.from_dict(d["temp"]) if "temp" in d else CELSIUS
        scaling = TemperatureScaling(int(fx["t_lo"]), int(fx["t_hi"]), int(fx["t_center"]),
                                     int(fx["u_mul"]), int(fx["u_shift"]), temp_code.units_per_degree)
        model = TcompModel(axes=axes, order=order, t0=float(d["t0_c"]), scaling=scaling,
                           coef=[np.array(c, dtype=float) for c in fl["coef"]],
                           f_t0=[float(v) for v in fl["f_t0"]],
                           q=[int(v) for v in fx["q"]], coef_q=[tuple(int(v) for v in c) for c in fx["coef"]],
                           error_bound_lsb=[float(v) for v in fx.get("error_bound_lsb", [0.0] * len(axes))],
                           temp_column=str(d.get("temp_column", "temp")), report=d.get("report", {}),
                           temp_code=temp_code, value_scale=float(d.get("value_scale", 1.0)))
    except (KeyError, TypeError, ValueError) as exc:
        raise ModelFileError(f"{where}: malformed model: {exc!r}") from None
    n = len(axes)
    if not 1 <= n <= MAX_AXES or not 1 <= order <= MAX_ORDER:
        raise ModelFileError(f"{where}: {n} axes / order {order} (supported: 1..3 axes, order 1..8)")
    for name, rows in (("float coef", model.coef), ("fixed coef", model.coef_q)):
        if len(rows) != n or any(len(r) != order + 1 for r in rows):
            raise ModelFileError(f"{where}: {name} must be {n} rows of {order + 1} values")
    if len(model.q) != n or any(not 0 <= v <= MAX_Q for v in model.q):
        raise ModelFileError(f"{where}: q must be {n} values in 0..{MAX_Q}")
    if not all(math.isfinite(v) for row in model.coef for v in row):
        raise ModelFileError(f"{where}: non-finite float coefficient")
    if not -32768 <= scaling.t_lo < scaling.t_hi <= 32767:
        raise ModelFileError(f"{where}: bad calibrated range {scaling.t_lo}..{scaling.t_hi}")
    return model


def load(path):
    """Read a model written by `TcompModel.save`, checksum verified.

    Parameters
    ----------
    path : path-like
        The JSON model file.

    Returns
    -------
    TcompModel

    Raises
    ------
    ModelFileError
        Unreadable, not JSON, another format or version, no or a wrong
        checksum (a hand edit), malformed fields.

    Examples
    --------
    >>> _ = open("other.json", "w").write('{"format": "x"}')
    >>> load("other.json")
    Traceback (most recent call last):
        ...
    pysig.errors.ModelFileError: other.json: not a pysig temperature-compensation model ...
    """
    d = read_json(path, "JSON model file")
    return from_dict(d, where=str(path), verify_checksum=True)
