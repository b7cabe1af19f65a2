"""The reading's value scale: how a log column becomes the firmware's int16
reading (reading = round(value * value_scale)), chosen or checked when a
model is fitted and checked again before it is exported.

Rules (stated here, once)
-------------------------
* A column of integers within int16 is the firmware's reading already:
  scale 1.
* Any other column (a physical unit such as tesla, g or dps, or codes
  beyond int16) gets the largest scale of the 1-2-5 series that keeps the
  largest |value| of the log at or below INT16_MAX / HEADROOM (8191): a
  4x margin for readings beyond the calibration log's.
* A scale the user gives must keep the log within int16 (else RangeError).
* A model has *lost its float form* when the correction its fixed-point
  form applies no longer follows the float one: the float correction spans
  less than one int16 LSB (the firmware would subtract 0 everywhere), or
  the fixed-point error bound reaches half of that span.  `fit` refuses
  such a model and `export` refuses to write it, naming the remedy."""
import math

import numpy as np

from ..errors import RangeError

INT16_MAX = 32767
HEADROOM = 4                 # the chosen scale keeps the log's largest |value| <= INT16_MAX / HEADROOM
MIN_SPAN_LSB = 1.0           # a correction spanning less than this rounds to (almost) nothing
MAX_ERROR_SHARE = 0.5        # a fixed-point error bound at this share of the span has lost the model


def is_int16_codes(values):
    """True when every value is an integer within int16 (the firmware's own reading)."""
    v = np.asarray(values, dtype=float)
    return bool(v.size) and bool(np.all(v == np.round(v))) and v.min() >= -32768 and v.max() <= INT16_MAX


def one_two_five_below(limit):
    """The largest 1, 2 or 5 x 10^k not above `limit` (> 0)."""
    k = math.floor(math.log10(limit))
    return next(float(f"{m * 10.0 ** k:.12g}") for m in (5, 2, 1) if m * 10.0 ** k <= limit * (1 + 1e-12))


def choose(columns, what="fit"):
    """(value_scale, note) for readings `columns` (name -> array) with no
    scale given: 1 for int16 codes, else the 1-2-5 scale of the module's
    rule; RangeError for all-zero readings, which no scale resolves."""
    if all(is_int16_codes(v) for v in columns.values()):
        return 1.0, None
    peak = max(float(np.max(np.abs(v))) for v in columns.values())
    if not peak > 0:
        raise RangeError(f"{what}: every reading is 0: nothing to scale into the int16 reading")
    scale = one_two_five_below(INT16_MAX / HEADROOM / peak)
    return scale, (f"value scale {scale:g} chosen: the firmware's int16 reading = value x {scale:g} "
                   f"(1 LSB = {1 / scale:.3g} in the column's unit; the log's largest |value| {peak:.4g} "
                   f"-> {peak * scale:.0f} LSB, a {HEADROOM}x margin below int16; --value-scale sets it)")


def check_given(columns, scale, what="fit"):
    """RangeError unless `scale` is a positive number keeping every reading within int16."""
    if not (np.isfinite(scale) and scale > 0):
        raise RangeError(f"{what}: value scale must be a positive number, got {scale!r}")
    for name, v in columns.items():
        peak = float(np.max(np.abs(v)))
        if peak * scale > INT16_MAX:
            raise RangeError(f"{what} column '{name}': |value| up to {peak:.4g} x value scale {scale:g} = "
                             f"{peak * scale:.4g} leaves int16: give --value-scale "
                             f"{one_two_five_below(INT16_MAX / HEADROOM / peak):g} or less")


def calibrated_range(model):
    """(lo, hi) of the model's calibrated range in its float abscissa (°C or code domain)."""
    return (model.t_lo, model.t_hi) if model.family == "poly" else (model.lo, model.hi)


def correction_span_lsb(model):
    """Per axis: the largest |float correction| over the calibrated range, in int16 LSB."""
    lo, hi = calibrated_range(model)
    grid = model.temp_code.from_domain(np.linspace(lo, hi, 513))
    return [float(np.max(np.abs(model.delta(grid, a)))) for a in range(len(model.axes))]


def error_bound_lsb(model):
    """Per axis: the bound of |fixed-point correction - float correction|, in LSB."""
    return list(model.error_bound_lsb if model.family == "poly" else model.error_lsb)


def lost_axes(model):
    """[(axis, span LSB, error LSB)] of the axes whose fixed-point form has lost the float one."""
    out = []
    for name, span, err in zip(model.axes, correction_span_lsb(model), error_bound_lsb(model)):
        if span < MIN_SPAN_LSB or err >= MAX_ERROR_SHARE * span:
            out.append((name, span, err))
    return out


def suggested_scale(model):
    """The module's chosen scale for the model's readings (their size taken
    from the reading at T0 and the correction's span), or None when no
    int16 scale resolves the drift below that margin."""
    s = model.value_scale
    spans = correction_span_lsb(model)
    peak = max(abs(f) + span for f, span in zip(model.f_t0, spans)) / s
    if not peak > 0:
        return None
    better = one_two_five_below(INT16_MAX / HEADROOM / peak)
    return better if min(spans) / s * better >= MIN_SPAN_LSB else None


def describe_loss(model, lost, what):
    """The refusal text for `lost` (from `lost_axes`), with the remedy."""
    s = model.value_scale
    parts = [f"axis '{n}': the correction spans {span / s:.3g} in the column's unit = {span:.3g} LSB at value "
             f"scale {s:g} (fixed-point error up to {err:.3g} LSB)" for n, span, err in lost]
    better = suggested_scale(model)
    remedy = (f"re-fit with --value-scale {better:g} (1 LSB = {1 / better:.3g}; the readings stay within int16)"
              if better else "no value scale both keeps the readings within int16 and resolves the drift: "
              "subtract the readings' constant offset before fitting, or leave this axis uncompensated")
    return (f"{what}: the fixed-point model has lost its float form ({'; '.join(parts)}): the firmware "
            f"would correct (almost) nothing; {remedy}")


def require_float_form(model, what="export"):
    """RangeError naming the remedy when `lost_axes(model)` is not empty."""
    lost = lost_axes(model)
    if lost:
        raise RangeError(describe_loss(model, lost, what))
