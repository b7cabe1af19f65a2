"""The temperature as the firmware reads it: one converter from a log's
temperature column to the int16 temperature `t` every fixed-point model
(sig_tcomp, sig_tcomp16, sig_pwl, sig_tmodel) works in.

Kinds
-----
* ``celsius``: the column is in °C; t = round(T * 100) (0.01 °C, half to
  even), the firmware passes t as an int16 (code kind int16).
* ``raw``: the column holds the sensor's integer temperature codes.  When
  every code fits int16 the firmware passes them as they are (code kind
  int16); when they are unsigned 16-bit codes (some above 32767, none
  negative) it passes the uint16 and t = code - 32768 (code kind uint16,
  sig_tmodel_code_to_t), which keeps the order over 0..65535.

Out-of-range rule (stated here, once): a temperature whose t would leave
int16 is an error (RangeError) when a model is being *fitted* - a
calibration is never built on a clipped temperature - and is saturated to
the nearest int16 end when a model is *applied* ("saturate"), because such a
temperature is outside every calibrated range anyway: the firmware clamps it
to the range and flags it (SIG_WARN_CLAMPED)."""
from dataclasses import dataclass

import numpy as np

from ..errors import InputFileError, NonFiniteError, RangeError

CENTI_PER_DEGC = 100
INT16_MIN, INT16_MAX = -32768, 32767
CODE_INT16, CODE_UINT16 = 0, 1       # SIG_TCODE_INT16, SIG_TCODE_UINT16 (sig_tmodel.h)


@dataclass(frozen=True)
class TempCode:
    """How a temperature column maps to the firmware's int16 t.

    Parameters
    ----------
    unit : {"c", "raw"}
        °C or the sensor's integer codes.
    code_kind : int
        CODE_INT16 or CODE_UINT16 (raw codes only; °C is always CODE_INT16).
    scale, offset : float or None
        Raw codes only, for printing: °C = code * scale + offset.

    Examples
    --------
    >>> CELSIUS.to_t([25.0, -40.125]).tolist()         # 0.01 °C, half to even
    [2500, -4012]
    >>> TempCode(unit="raw", code_kind=CODE_UINT16).to_t([0, 40000, 65535]).tolist()
    [-32768, 7232, 32767]
    >>> CELSIUS.to_t([400.0], out_of_range="saturate").tolist()
    [32767]
    """
    unit: str = "c"
    code_kind: int = CODE_INT16
    scale: float = None
    offset: float = None

    @property
    def units_per_degree(self):
        """t counts per unit of the model's float abscissa (°C or code)."""
        return CENTI_PER_DEGC if self.unit == "c" else 1

    @property
    def name(self):
        return "°C" if self.unit == "c" else "code"

    def domain(self, values):
        """Float abscissa of the float model: °C, or the code (minus 32768
        for unsigned codes, so that it equals t)."""
        v = np.asarray(values, dtype=float)
        return v if self.unit == "c" or self.code_kind == CODE_INT16 else v - 32768.0

    def from_domain(self, x):
        """Inverse of `domain` (the user's unit)."""
        x = np.asarray(x, dtype=float)
        return x if self.unit == "c" or self.code_kind == CODE_INT16 else x + 32768.0

    def to_t(self, values, out_of_range="raise", what="temperature"):
        """int16 t (as int64 numpy) of a temperature column; the
        out-of-range rule is the module's (``"raise"`` or ``"saturate"``)."""
        v = np.asarray(values, dtype=float)
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise NonFiniteError(f"{what}: non-finite temperature {v.flat[bad[0]]} at index {int(bad[0])}")
        return to_int16(self.domain(v) * self.units_per_degree, out_of_range,
                        lambda i: f"{what}: {float(v.flat[i])!r} {self.name} at index {i} does not fit the "
                                  f"int16 temperature ({self.describe_limits()})")

    def codes(self, t):
        """The 16 bits the firmware passes to sig_tmodel_apply for int16 t."""
        t = np.asarray(t, dtype=np.int64)
        return (t + 32768) if self.code_kind == CODE_UINT16 else (t & 0xFFFF)

    def describe_limits(self):
        if self.unit == "c":
            return "-327.68 .. 327.67 °C in 0.01 °C"
        return "codes -32768..32767 (int16) or 0..65535 (uint16)"

    def to_celsius(self, x_domain):
        """°C for printing (None for raw codes without --temp-scale)."""
        if self.unit == "c":
            return np.asarray(x_domain, dtype=float)
        if self.scale is None:
            return None
        return self.from_domain(x_domain) * self.scale + (self.offset or 0.0)

    def label(self, x_domain):
        """A temperature as text in the user's unit (and °C when known)."""
        if self.unit == "c":
            return f"{float(x_domain):.2f} °C"
        text = f"code {float(self.from_domain(x_domain)):.0f}"
        c = self.to_celsius(x_domain)
        return text + (f" ({float(c):.2f} °C)" if c is not None else "")

    def to_dict(self):
        return {"unit": self.unit, "code_kind": "uint16" if self.code_kind == CODE_UINT16 else "int16",
                "scale": self.scale, "offset": self.offset}

    @staticmethod
    def from_dict(d):
        return TempCode(unit=d["unit"], code_kind=CODE_UINT16 if d["code_kind"] == "uint16" else CODE_INT16,
                        scale=d.get("scale"), offset=d.get("offset"))


CELSIUS = TempCode()


def to_int16(t_units, out_of_range="raise", message=None):
    """THE rounding of temperatures (already in t units) to int16 t: to
    nearest, half to even; outside int16 the module's rule (raise a
    RangeError with `message(index)`, or saturate).  Every converter in
    pysig.tcomp goes through here."""
    t = np.rint(np.asarray(t_units, dtype=float))
    if t.size and (t.min() < INT16_MIN or t.max() > INT16_MAX):
        if out_of_range == "saturate":
            return np.clip(t, INT16_MIN, INT16_MAX).astype(np.int64)
        i = int(np.argmax((t < INT16_MIN) | (t > INT16_MAX)))
        raise RangeError(message(i) if message else f"temperature at index {i} does not fit int16")
    return t.astype(np.int64)


def raw_code(values, scale=None, offset=None, what="temperature"):
    """TempCode for a column of raw integer codes: int16 when they all fit,
    uint16 when they are unsigned 16-bit codes; InputFileError for codes
    that are not integers, RangeError for codes that fit neither."""
    v = np.asarray(values, dtype=float)
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        raise NonFiniteError(f"{what}: non-finite temperature code at index {int(bad[0])}")
    frac = np.flatnonzero(v != np.round(v))
    if frac.size:
        raise InputFileError(f"{what}: --temp-unit raw needs integer codes, index {int(frac[0])} "
                             f"holds {float(v[frac[0]])!r}")
    if v.size == 0 or (v.min() >= INT16_MIN and v.max() <= INT16_MAX):
        kind = CODE_INT16
    elif v.min() >= 0 and v.max() <= 0xFFFF:
        kind = CODE_UINT16
    else:
        raise RangeError(f"{what}: codes {v.min():.0f}..{v.max():.0f} fit neither int16 "
                         f"(-32768..32767) nor uint16 (0..65535)")
    return TempCode(unit="raw", code_kind=kind, scale=scale, offset=offset)
