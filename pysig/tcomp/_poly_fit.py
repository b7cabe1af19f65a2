"""Training of the temperature-compensation model: per axis, the
least-squares polynomial f(T) of order 1-8 (pysig.lsq, centred and scaled
temperature) and the correction delta(T) = f(T) - f(T0); order selection by
leave-one-temperature-out cross-validation, reported per order like the
magnetometer paper's Table 3; quantisation for the MCU (pysig.tcomp._quant).

What counts as "a temperature".  Chamber logs hold many samples per plateau
at slightly different readings (the BMI270 recording: 3255 samples between
12.98 and 13.30 °C), so distinct float values say nothing.  Temperatures are
grouped instead (`temperature_groups`):
  1. sort them and split wherever two neighbours are more than `gap` apart
     (default 0.15 °C: above two steps of a 1/16 °C sensor, below the
     0.188 °C bin spacing of the MPU-6000 table);
  2. cut any cluster wider than `max_span` (default 5 °C: a ramp) into equal
     pieces no wider than that;
  3. a piece counts as a distinct temperature only if it holds at least
     `min_share` (default 5 %) of the samples of the fullest piece: a few
     start-up samples far from the plateau (10 of the BMI270 hot file's 6533,
     at 49.3 °C) do not make a temperature the fit can rely on.
The groups are also the folds of the cross-validation.  An order n fit needs
n + 1 distinct temperatures."""
import math
from dataclasses import dataclass

import numpy as np

from .. import lsq
from .._rails import INT16_RAILS, first_at_rail, saturated_message
from . import _quant as quant
from ..errors import InsufficientDataError, NonFiniteError, RangeError, SaturationError
from ._poly_model import TcompModel
from ._tempcode import CELSIUS

MAX_FIT_ORDER = 8
GAP_C = 0.15
MAX_SPAN_C = 5.0
MIN_SHARE = 0.05


@dataclass(frozen=True)
class TemperatureGroups:
    labels: np.ndarray       # per sample: group index, -1 for samples in a piece that does not count
    ranges: list             # per counted group: (lo, hi, samples)

    @property
    def count(self):
        return len(self.ranges)

    def describe(self):
        return ", ".join(f"{lo:.2f}-{hi:.2f} °C ({n} samples)" if hi > lo else f"{lo:.2f} °C ({n} samples)"
                         for lo, hi, n in self.ranges)


def temperature_groups(temp, gap=GAP_C, max_span=MAX_SPAN_C, min_share=MIN_SHARE):
    temp = np.asarray(temp, dtype=float)
    order = np.argsort(temp, kind="stable")
    st = temp[order]
    cuts = np.flatnonzero(np.diff(st) > gap) + 1
    pieces = []
    for chunk in np.split(np.arange(st.size), cuts):
        lo, hi = st[chunk[0]], st[chunk[-1]]
        n_pieces = max(1, int(math.ceil((hi - lo) / max_span - 1e-9)))
        if n_pieces == 1:
            pieces.append(chunk)
        else:
            edges = np.linspace(lo, hi, n_pieces + 1)[1:-1]
            which = np.searchsorted(edges, st[chunk], side="right")
            pieces.extend(chunk[which == k] for k in range(n_pieces) if np.any(which == k))
    biggest = max(len(p) for p in pieces)
    labels = np.full(temp.size, -1, dtype=int)
    ranges = []
    for p in pieces:
        if len(p) >= min_share * biggest:
            labels[order[p]] = len(ranges)
            ranges.append((float(st[p[0]]), float(st[p[-1]]), int(len(p))))
    return TemperatureGroups(labels, ranges)


def first_saturated(y):
    """Index of the first reading at an int16 rail, or None."""
    return first_at_rail(y, INT16_RAILS)


def saturated_reading(value):
    return saturated_message(value, "the int16")


def check_inputs(temp, columns, what="fit"):
    """Finite values off the int16 rails, equal lengths; returns (temp, {name: array})."""
    temp = np.asarray(temp, dtype=float).ravel()
    bad = np.flatnonzero(~np.isfinite(temp))
    if bad.size:
        raise NonFiniteError(f"{what}: temperature: non-finite value {temp[bad[0]]} at index {int(bad[0])}")
    out = {}
    for name, y in columns.items():
        y = np.asarray(y, dtype=float).ravel()
        if y.shape != temp.shape:
            raise ValueError(f"{what}: column '{name}' has {y.size} values, temperature {temp.size}")
        bad = np.flatnonzero(~np.isfinite(y))
        if bad.size:
            raise NonFiniteError(f"{what}: column '{name}': non-finite value {y[bad[0]]} at index {int(bad[0])}")
        i = first_saturated(y)
        if i is not None:
            raise SaturationError(f"{what}: column '{name}': {saturated_reading(y[i])} at index {i}")
        out[name] = y
    if not 1 <= len(out) <= 3:
        raise ValueError(f"{what}: 1 to 3 columns, got {len(out)}")
    return temp, out


def require_temperatures(groups, order, temp, what="fit"):
    if np.ptp(temp) == 0:
        raise InsufficientDataError(
            f"{what}: constant temperature ({temp[0]:.3f} °C in all {temp.size} samples): "
            f"a temperature model needs at least 2 distinct temperatures")
    if groups.count < order + 1:
        raise InsufficientDataError(
            f"{what}: order {order} needs at least {order + 1} distinct temperatures, "
            f"the data has {groups.count} ({groups.describe()}); "
            f"the highest order it supports is {groups.count - 1}")


def groups_for(temp, temp_code=CELSIUS):
    """`temperature_groups` in the model's unit: for raw codes the °C
    thresholds become fractions of the range (a gap of 0.25 % of it, pieces
    of at most 8 %), as a code's size in °C is not known."""
    x = temp_code.domain(temp)
    if temp_code.unit == "c":
        return temperature_groups(x)
    span = float(np.ptp(x)) if x.size else 0.0
    return temperature_groups(x, gap=max(1.0, 0.0025 * span), max_span=max(2.0, 0.08 * span))


def fit_tcomp(temp, columns, order=2, t0=25.0, temp_column="temp", groups=None, what="fit",
              temp_code=CELSIUS, max_error_lsb=None):
    """Fit the temperature-compensation model of 1 to 3 axes.

    Parameters
    ----------
    temp : array_like
        The temperature of each sample, in the unit `temp_code` states (°C
        by default, or the sensor's raw codes).
    columns : dict
        name -> readings (int16 sensor codes as floats), 1 to 3 axes, each
        as long as `temp`.
    order : int or "auto", optional
        Polynomial order 1..8, or "auto": the smallest order whose
        held-out variance is within 5 % of the best (`cross_validate`,
        `select_order`).
    t0 : float, optional
        Reference temperature, in the unit of `temp`, where the correction
        is zero; inside the calibrated range.
    temp_column : str, optional
        The temperature column's name, stored in the model.
    groups : TemperatureGroups, optional
        Precomputed temperature groups of `temp`.
    what : str, optional
        Names the data in error messages.
    temp_code : TempCode, optional
        How `temp` maps to the firmware's int16 temperature t
        (pysig.tcomp._tempcode; default °C, t in 0.01 °C).
    max_error_lsb : float or dict, optional
        The largest fixed-point error bound (reading LSB) the model may
        have, one number or name -> number per column (default
        `pysig.tcomp._quant.MAX_ERROR_LSB`, 0.5).

    Returns
    -------
    TcompModel
        Float and fixed-point coefficients per axis, the temperature
        scaling, the temperature code, and a report (groups, per-axis RMS,
        conditioning, Q format and error bound, the CV table with "auto").

    Raises
    ------
    InsufficientDataError
        Fewer distinct temperatures than the order needs (order + 1).
    RangeError
        A bad order, a temperature outside int16 t, T0 outside the range,
        or a fixed-point error bound above `max_error_lsb`.
    NonFiniteError, SaturationError
        NaN/inf inputs or readings at the int16 rails.

    Examples
    --------
    >>> from pysig.sim._chamber import ChamberParams, simulate
    >>> run = simulate(ChamberParams(dwell_s=600.0))        # 0/25/50/70 °C steps
    >>> model = fit_tcomp(run["temp"], {"x": run["x"], "y": run["y"]}, order="auto")
    >>> model.order, model.axes
    (2, ['x', 'y'])
    >>> fit_tcomp(run["temp"], {"x": run["x"]}, order=2, max_error_lsb=1e-9)
    Traceback (most recent call last):
        ...
    pysig.errors.RangeError: fit column 'x': the fixed-point correction could be off by up to ...
    >>> import numpy as np
    >>> fit_tcomp(np.r_[np.full(50, 25.0), np.full(50, 40.0)], {"x": np.arange(100.0)}, order=2)
    Traceback (most recent call last):
        ...
    pysig.errors.InsufficientDataError: fit: order 2 needs at least 3 distinct temperatures, ...
    """
    temp, columns = check_inputs(temp, columns, what)
    if groups is None:
        groups = groups_for(temp, temp_code)
    cv = None
    if order == "auto":
        require_temperatures(groups, 1, temp, what)
        cv = cross_validate(temp, columns, groups=groups)
        order = select_order(cv)
    if not (isinstance(order, (int, np.integer)) and 1 <= order <= MAX_FIT_ORDER):
        raise RangeError(f"{what}: order must be 1..{MAX_FIT_ORDER} or 'auto', got {order!r}")
    order = int(order)
    require_temperatures(groups, order, temp, what)
    t_int = temp_code.to_t(temp, "raise", what)
    scaling = quant.choose_scaling(int(t_int.min()), int(t_int.max()), temp_code.units_per_degree)
    lo, hi = scaling.t_lo / scaling.units_per, scaling.t_hi / scaling.units_per
    t0_user, t0 = t0, float(temp_code.domain(t0))
    if not lo <= t0 <= hi:
        raise RangeError(f"{what}: reference temperature T0 = {t0_user} {temp_code.name} is outside the "
                         f"calibrated range {temp_code.label(lo)}..{temp_code.label(hi)}")
    x = temp_code.domain(temp)
    u0 = (t0 - scaling.center_c) / scaling.scale_c
    coef, f_t0, q, coef_q, bound, per_axis = [], [], [], [], [], {}
    for name, y in columns.items():
        pf = lsq.fit_poly(x, y, order, center=scaling.center_c, scale=scaling.scale_c,
                          what=f"{what} column '{name}'")
        ft0 = float(np.polynomial.polynomial.polyval(u0, pf.coef))
        c = np.array(pf.coef, dtype=float)
        c[0] -= ft0
        qa = quant.quantize_axis(c, what=f"{what} column '{name}'")
        limit = quant.MAX_ERROR_LSB if max_error_lsb is None else (
            max_error_lsb[name] if isinstance(max_error_lsb, dict) else float(max_error_lsb))
        if qa.error_bound_lsb > limit:
            raise RangeError(
                f"{what} column '{name}': the fixed-point correction could be off by up to "
                f"{qa.error_bound_lsb:.2f} LSB (> {limit:.3g}): the drift is too steep for "
                f"a Q15 temperature (swing {float(np.sum(np.abs(c[1:]))):.0f} LSB over the range)")
        coef.append(c)
        f_t0.append(ft0)
        q.append(qa.q)
        coef_q.append(qa.coef)
        bound.append(qa.error_bound_lsb)
        per_axis[name] = {"rms": pf.rms, "cond": pf.cond, "q": qa.q,
                          "error_bound_lsb": qa.error_bound_lsb}
    report = {"groups": [list(r) for r in groups.ranges], "per_axis": per_axis,
              "samples": int(temp.size)}
    if cv is not None:
        report["cv"] = cv
        report["order_rule"] = "smallest order whose pooled held-out variance is within 5 % of the best"
    return TcompModel(axes=list(columns), order=order, t0=float(t0), scaling=scaling, coef=coef,
                      f_t0=f_t0, q=q, coef_q=coef_q, error_bound_lsb=bound,
                      temp_column=temp_column, report=report, temp_code=temp_code)


def cross_validate(temp, columns, orders=range(1, MAX_FIT_ORDER + 1), groups=None):
    """Leave-one-temperature-out cross-validation of each polynomial order.

    For each counted temperature group, fit on the others and measure the
    residual y - f(T) on the held-out group (the polynomial itself, not
    clamped: CV judges the curve).

    Parameters
    ----------
    temp : array_like
        Temperatures, °C.
    columns : dict
        name -> readings, as for `fit_tcomp`.
    orders : iterable of int, optional
        The orders to score.
    groups : TemperatureGroups, optional
        Precomputed `temperature_groups(temp)` (the folds).

    Returns
    -------
    list of dict
        One row per order (first "raw": the error without correction, y
        minus its mean): RMS, max |error| and variance of the held-out
        residuals, pooled and per axis.  An order whose training folds
        would have fewer than order + 1 temperatures carries "refused".

    Examples
    --------
    >>> from pysig.sim._chamber import ChamberParams, simulate
    >>> run = simulate(ChamberParams(dwell_s=600.0))
    >>> cv = cross_validate(run["temp"], {"x": run["x"]}, orders=(1, 2, 3))
    >>> [(r["label"], round(r["rms"])) for r in cv]
    [('raw', 37), ('order 1', 21), ('order 2', 4), ('order 3', 4)]
    >>> select_order(cv)
    2
    """
    temp, columns = check_inputs(temp, columns, "cross-validation")
    if groups is None:
        groups = temperature_groups(temp)
    rows = [{"order": 0, "label": "raw", **_stats({n: y - y.mean() for n, y in columns.items()})}]
    for order in orders:
        if groups.count - 1 < order + 1:
            rows.append({"order": order, "label": f"order {order}", "refused":
                         f"needs {order + 1} training temperatures, leave-one-out leaves "
                         f"{groups.count - 1} of {groups.count}"})
            continue
        resid = {n: np.full(temp.size, np.nan) for n in columns}
        for g in range(groups.count):
            test = groups.labels == g
            train = ~test
            for name, y in columns.items():
                pf = lsq.fit_poly(temp[train], y[train], order, what=f"CV order {order}")
                resid[name][test] = y[test] - pf(temp[test])
        keep = groups.labels >= 0
        rows.append({"order": order, "label": f"order {order}",
                     **_stats({n: r[keep] for n, r in resid.items()})})
    return rows


def _stats(resid):
    per = {n: {"rms": float(np.sqrt(np.mean(r ** 2))), "max": float(np.max(np.abs(r))),
               "var": float(np.var(r))} for n, r in resid.items()}
    allr = np.concatenate(list(resid.values()))
    return {"per_axis": per, "rms": float(np.sqrt(np.mean(allr ** 2))),
            "max": float(np.max(np.abs(allr))), "var": float(np.mean([p["var"] for p in per.values()]))}


def select_order(cv, tolerance=0.05):
    """Smallest order whose pooled held-out variance is within `tolerance`
    of the best cross-validated order.

    Parameters
    ----------
    cv : list of dict
        The rows of `cross_validate`.
    tolerance : float, optional
        Relative slack on the best variance.

    Returns
    -------
    int
        The order.

    Raises
    ------
    InsufficientDataError
        No order could be cross-validated (fewer than 3 temperatures).

    Examples
    --------
    >>> rows = [{"order": 0, "var": 9.0}, {"order": 1, "var": 4.0},
    ...         {"order": 2, "var": 1.0}, {"order": 3, "var": 0.98}]
    >>> select_order(rows)
    2
    """
    ok = [r for r in cv if r["order"] >= 1 and "refused" not in r]
    if not ok:
        raise InsufficientDataError("order selection: no order could be cross-validated "
                                    "(needs at least 3 distinct temperatures)")
    best = min(r["var"] for r in ok)
    return min(r["order"] for r in ok if r["var"] <= best * (1 + tolerance))


def format_cv_table(cv, unit="LSB"):
    lines = [f"{'order':>7} {'RMS':>12} {'max':>12} {'variance':>14}   ({unit}, held-out temperatures)"]
    for r in cv:
        if "refused" in r:
            lines.append(f"{r['label']:>7}   refused: {r['refused']}")
        else:
            lines.append(f"{r['label']:>7} {r['rms']:12.4g} {r['max']:12.4g} {r['var']:14.4g}")
    return "\n".join(lines)


def group_bias_report(model, temp, columns, groups=None):
    """Mean reading per temperature group before and after correction (the
    float path): how the bias moves with temperature, and what is left."""
    temp, columns = check_inputs(temp, columns, "bias report")
    if groups is None:
        groups = temperature_groups(temp)
    corrected = model.apply_float(temp, [columns[a] for a in model.axes])
    rows = []
    for g, (lo, hi, n) in enumerate(groups.ranges):
        sel = groups.labels == g
        rows.append({"temp_c": float(np.mean(temp[sel])), "range_c": [lo, hi], "samples": n,
                     "before": {a: float(np.mean(columns[a][sel])) for a in model.axes},
                     "after": {a: float(np.mean(c[sel])) for a, c in zip(model.axes, corrected)}})
    return rows
