"""Temperature models of either family, end to end: fit with the family and
size chosen from the data (`fit_model`), load (`load`), the NVM image
(`image_bytes`), and correction (`apply`: the float64 model, or the
firmware's evaluation through its own C loader, `apply_fixed`, which is
`apply_image` on the model's image).

A model is a pysig.tcomp._poly_model.TcompModel (family "poly") or a
pysig.tcomp._table_model.TableModel (family "table"); both carry their
temperature code (pysig.tcomp._tempcode: °C or raw codes) and `value_scale`
(the firmware's int16 reading = column value * value_scale)."""
from dataclasses import dataclass, field

import numpy as np

from . import _choice as auto, _poly_fit as fit, _quant as quant
from . import _poly_model as poly_model
from . import _table_model as table_model
from ._tempcode import CELSIUS, CODE_UINT16, TempCode
from ..io import read_json
from ..errors import InputFileError, InsufficientDataError, ModelFileError, NonFiniteError, RangeError
from ..store._image import (SECTION_COMPACT_POLY, SECTION_OFFSET_POLY, SECTION_PWL_TABLE, SECTION_TEMP_CODE,
                           TCODE_INT16, TCODE_UINT16, build_image, compact_poly_payload,
                           offset_poly_payload, temp_code_payload)
from ._table_fit import pwl_payload, PwlQ16

MIN_ERROR_LSB = 0.5          # a fixed-point error below this is always accepted
CV_ERROR_SHARE = 0.10        # ... and so is one below 10 % of the model's own CV RMS


def parse_spec(text):
    """('auto'|'poly'|'table', int or 'auto') from auto, poly:N, table:K,
    table:auto, poly:auto; InputFileError otherwise."""
    text = str(text).strip()
    if text == "auto":
        return "auto", "auto"
    fam, _, size = text.partition(":")
    if fam in ("poly", "table") and size:
        if size == "auto":
            return fam, "auto"
        if size.isdigit():
            return fam, int(size)
    raise InputFileError(f"fit: --model must be auto, poly:N, poly:auto, table:K or table:auto, got {text!r}")


def allowed_error(cv_rms):
    """The fixed-point error a model may add: max(0.5 LSB, 10 % of its CV RMS)."""
    return max(MIN_ERROR_LSB, CV_ERROR_SHARE * cv_rms) if np.isfinite(cv_rms) else MIN_ERROR_LSB


@dataclass
class FitResult:
    """A fitted model and what to tell the user."""
    model: object
    lines: list = field(default_factory=list)
    warnings: list = field(default_factory=list)


def _build(cand, prep, groups, t0, temp_code, limits, temp_column, what):
    """The fixed-point model of one candidate; RangeError when its error
    exceeds `limits` (per axis)."""
    temp = temp_code.from_domain(prep.x)
    if cand.family == "poly":
        return fit.fit_tcomp(temp, prep.columns, order=cand.size, t0=t0, temp_column=temp_column,
                             groups=groups, what=what, temp_code=temp_code, max_error_lsb=limits)
    m = table_model.fit_table(temp, prep.columns, cand.size, t0, temp_code, temp_column, what)
    for name, err in zip(m.axes, m.error_lsb):
        if err > limits[name]:
            raise RangeError(f"{what} column '{name}': the fixed-point table could be off by "
                             f"{err:.3g} LSB (> {limits[name]:.3g})")
    return m


def _limits(cand, prep):
    if cand.cv_axis:
        return {n: allowed_error(cand.cv_axis[n]) for n in prep.columns}
    return {n: MIN_ERROR_LSB for n in prep.columns}


def _default_t0(temp_code, lo, hi):
    if temp_code.unit == "c" and lo <= 25.0 <= hi:
        return 25.0
    if temp_code.unit == "raw" and temp_code.scale:
        code = round((25.0 - (temp_code.offset or 0.0)) / temp_code.scale)     # 25 °C as a code
        if lo <= float(temp_code.domain(code)) <= hi:
            return float(code)
    return float(temp_code.from_domain(round((lo + hi) / 2)))


def _cv_table(cands, chosen, best, n_axes, unit):
    names = list(next((c.cv_axis for c in cands if c.cv_axis), {}).keys())
    head = f"{'model':>10} {'CV RMS':>10} " + "".join(f"{n[:10]:>11}" for n in names) + \
        f" {'cycles':>7} {'bytes':>6}   ({unit}, blocked CV over temperature, {n_axes} axes)"
    lines = [head]
    for c in cands:
        cyc, byt = c.cost(n_axes)
        if c.refused:
            lines.append(f"{c.label:>10}   refused: {c.refused}")
            continue
        mark = " <- chosen" if c is chosen else (" (best CV)" if c is best else "")
        lines.append(f"{c.label:>10} {c.cv_rms:10.4g} " + "".join(f"{c.cv_axis[n]:11.4g}" for n in names)
                     + f" {cyc:7d} {byt:6d}{mark}")
    return lines


def _fold_lines(chosen, prep, temp_code):
    edges = auto.block_edges(prep)
    width = edges[1] - edges[0]
    block = np.minimum(((prep.x - edges[0]) / width).astype(int), auto.N_BLOCKS - 1)
    held = [b for b in range(1, auto.N_BLOCKS - 1) if np.any(block == b)]
    lines = [f"CV error per held-out block ({chosen.label}):"]
    rows = []
    for i, b in enumerate(held):
        per = {n: chosen.fold_rms[n][i] for n in chosen.fold_rms}
        rows.append({"lo": float(edges[b]), "hi": float(edges[b + 1]), "rms": per})
        lines.append(f"  {temp_code.label(edges[b])} .. {temp_code.label(edges[b + 1])}: " +
                     ", ".join(f"{n} {v:.4g}" for n, v in per.items()))
    return lines, rows


def fit_model(temp, columns, spec="auto", t0=None, temp_code=CELSIUS, value_scale=1.0, strict=False,
              temp_column="temp", prefer="cycles", what="fit"):
    """Fit a temperature model, family and size chosen from the data.

    Parameters
    ----------
    temp : array
        Temperatures, °C or raw integer codes (`temp_code`).
    columns : dict
        Axis name -> readings (1..3 axes).
    spec : str
        ``auto``, ``poly:N``, ``poly:auto``, ``table:K`` or ``table:auto``.
    t0 : float, optional
        Reference temperature in the column's unit (default 25 °C when in
        range, else the middle of the range).
    temp_code : pysig.tcomp._tempcode.TempCode
    value_scale : float
        The firmware's int16 reading is ``value * value_scale``.
    strict : bool
        Refuse (InsufficientDataError) instead of warning on coverage gaps.
    prefer : {"cycles", "bytes"}
        What "cheapest" means first.

    Returns
    -------
    FitResult

    Raises
    ------
    InsufficientDataError, RangeError, NonFiniteError, SaturationError
        Named, saying what and where.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 60.0, 301)
    >>> r = fit_model(t, {"x": 3.0 * (t - 25.0) + 0.05 * (t - 25.0) ** 2})
    >>> r.model.family in ("poly", "table")
    True
    """
    family, size = parse_spec(spec)
    temp, columns = fit.check_inputs(temp, columns, what)
    if not (np.isfinite(value_scale) and value_scale > 0):
        raise RangeError(f"{what}: value scale must be a positive number, got {value_scale!r}")
    columns = {n: y * value_scale for n, y in columns.items()}
    groups = fit.groups_for(temp, temp_code)
    if np.ptp(temp) == 0 or groups.count < 2:
        fit.require_temperatures(groups, 1, temp_code.domain(temp), what)
    prep = auto.prepare(temp, columns, temp_code)
    lo, hi = float(prep.x.min()), float(prep.x.max())
    if t0 is None:
        t0 = _default_t0(temp_code, lo, hi)
    if family == "table" and size != "auto" and not 2 <= size <= 255:
        raise RangeError(f"{what}: a table needs 2..255 knots, got {size}")
    if family == "poly" and size != "auto":
        if not 1 <= size <= fit.MAX_FIT_ORDER:
            raise RangeError(f"{what}: order must be 1..{fit.MAX_FIT_ORDER} or 'auto', got {size}")
        fit.require_temperatures(groups, size, temp_code.domain(temp), what)
    cands = [c for c in auto.candidates(family, size, prep.x.size)
             if size != "auto" or (c.size + 1 if c.family == "poly" else c.size) <= max(groups.count, 2)
             or groups.count >= 3]
    if not cands:
        raise InsufficientDataError(f"{what}: {prep.x.size} calibration temperatures support no "
                                    f"{family} model of size {size}")
    cv_ok = auto.cv_possible(prep, groups.count)
    lines, warnings = list(prep.notes), []
    lines.insert(0, f"temperatures: {groups.count} groups: {_describe_groups(groups, temp_code)}")
    if cv_ok:
        auto.score(prep, cands)
    else:
        lines.append(f"cross-validation needs 3 separate temperature groups with data inside the range; "
                     f"the data has {groups.count}: choosing among what it resolves "
                     f"({', '.join(c.label for c in cands)}) without CV")
    scored = [c for c in cands if not c.refused and np.isfinite(c.cv_rms)]
    best = min(scored, key=lambda c: c.cv_rms) if scored else None
    pool = auto.eligible(cands) if scored and len(cands) > 1 else [c for c in cands if not c.refused]
    if not pool:
        raise InsufficientDataError(f"{what}: no candidate model could be fitted: " +
                                    "; ".join(f"{c.label}: {c.refused}" for c in cands))
    ordered = auto.by_cost(pool, len(columns), prefer)
    model, chosen, skipped = None, None, []
    for c in ordered:
        try:
            model = _build(c, prep, groups, t0, temp_code, _limits(c, prep), temp_column, what)
            chosen = c
            break
        except RangeError as exc:
            skipped.append((c, str(exc)))
            if len(ordered) == 1:
                raise RangeError(f"{exc}; {_fitting_alternative(c, cands, prep, groups, t0, temp_code, temp_column, what)}") from None
        except InsufficientDataError as exc:
            skipped.append((c, str(exc)))
            if len(ordered) == 1:
                raise
    if model is None and len(ordered) > 1:
        # nothing near the best fits the fixed point: the most accurate one that does
        rest = sorted((c for c in scored if c not in ordered), key=lambda c: c.cv_rms)
        for c in rest:
            try:
                model = _build(c, prep, groups, t0, temp_code, _limits(c, prep), temp_column, what)
                chosen = c
                lines.append(f"no model within {auto.TOLERANCE:.0%} of the best CV fits the fixed point; "
                             f"the most accurate one that does: {c.label}, CV RMS "
                             f"{c.cv_rms / best.cv_rms:.3g} x the best")
                break
            except (RangeError, InsufficientDataError) as exc:
                skipped.append((c, str(exc)))
    if model is None:
        raise RangeError(f"{what}: no model fits the fixed point: " +
                         "; ".join(f"{c.label}: {e}" for c, e in skipped))
    unit = "reading LSB" if value_scale == 1.0 else f"reading x {value_scale:g}"
    if cv_ok:
        lines += _cv_table(cands, chosen, best, len(columns), unit)
        rule = f"the cheapest ({prefer} first) within {auto.TOLERANCE:.0%} of the best CV RMS"
        if family == "poly" and size == "auto":
            lines.append(f"order chosen: {chosen.size}")
        lines.append(f"model chosen: {chosen.label} ({rule if len(cands) > 1 else 'as asked'}), "
                     f"CV RMS {chosen.cv_rms:.4g}; best of any size: {best.label} {best.cv_rms:.4g}")
        fold_lines, fold_rows = _fold_lines(chosen, prep, temp_code)
        lines += fold_lines
    else:
        fold_rows = []
        lines.append(f"model chosen: {chosen.label} (the cheapest the data resolves)")
    for c, e in skipped:
        lines.append(f"skipped {c.label}: {e}")
    for kind, a, b, text in auto.coverage(prep):
        warnings.append(text.format(lo=temp_code.label(a), hi=temp_code.label(b)))
    hyst = auto.hysteresis(temp_code.domain(temp), columns)
    if hyst:
        lines.append(f"heating ({hyst['heating_samples']} samples) and cooling ({hyst['cooling_samples']}) "
                     f"both present: branch difference heating - cooling over {hyst['bins']} shared bins: " +
                     ", ".join(f"{n} mean {v['mean']:.4g}, band up to {v['max_abs']:.4g}"
                               for n, v in hyst["per_axis"].items()) + "; the fit pools both branches")
    if strict and warnings:
        raise InsufficientDataError(f"{what}: coverage check failed (--strict): " + "; ".join(warnings))
    errs = model.error_bound_lsb if chosen.family == "poly" else model.error_lsb
    lines.append(f"fixed point: {', '.join(f'{n} error <= {e:.3g} LSB' for n, e in zip(model.axes, errs))} "
                 f"(allowed: max(0.5 LSB, 10 % of the CV RMS))")
    lines.append(f"calibrated range {temp_code.label(model.t_lo if chosen.family == 'poly' else model.lo)} .. "
                 f"{temp_code.label(model.t_hi if chosen.family == 'poly' else model.hi)}, "
                 f"T0 {temp_code.label(model.t0)}")
    model.value_scale = float(value_scale)
    model.temp_column = temp_column
    model.report.update({
        "selection": {"spec": spec, "chosen": chosen.label,
                      "cv_rms": chosen.cv_rms if np.isfinite(chosen.cv_rms) else None,
                      "best": best.label if best else None, "best_cv_rms": best.cv_rms if best else None,
                      "candidates": [{"model": c.label,
                                      "cv_rms": c.cv_rms if np.isfinite(c.cv_rms) else None,
                                      "cv_axis": c.cv_axis, "refused": c.refused or None,
                                      "cycles": c.cost(len(columns))[0], "bytes": c.cost(len(columns))[1]}
                                     for c in cands],
                      "blocks": fold_rows, "prefer": prefer},
        "notes": list(prep.notes), "warnings": warnings, "hysteresis": hyst})
    return FitResult(model=model, lines=lines, warnings=warnings)


def _describe_groups(groups, temp_code):
    if groups.count > 6:
        return (f"{temp_code.label(groups.ranges[0][0])} .. {temp_code.label(groups.ranges[-1][1])}, "
                f"{sum(n for _, _, n in groups.ranges)} samples")
    return ", ".join(f"{temp_code.label(lo)}..{temp_code.label(hi)} ({n})" if hi > lo
                     else f"{temp_code.label(lo)} ({n})" for lo, hi, n in groups.ranges[:12]) + \
        (" ..." if groups.count > 12 else "")


def _fitting_alternative(refused, cands, prep, groups, t0, temp_code, temp_column, what):
    """'table:K would fit' naming the cheapest other candidate whose fixed
    point is within max(0.5 LSB, 10 % of its in-sample RMS)."""
    others = [c for c in auto.candidates("auto", "auto", prep.x.size)
              if (c.family, c.size) != (refused.family, refused.size)
              and (c.size + 1 if c.family == "poly" else c.size) <= max(groups.count, 2)]
    for c in auto.by_cost(others, len(prep.columns)):
        try:
            m = _build(c, prep, groups, t0, temp_code, {n: 1e9 for n in prep.columns}, temp_column, what)
        except (RangeError, InsufficientDataError):
            continue
        f = m.apply_float(temp_code.from_domain(prep.x), [prep.columns[n] for n in m.axes])
        rms = {n: float(np.sqrt(np.mean(r ** 2))) for n, r in zip(m.axes, f)}
        errs = m.error_bound_lsb if c.family == "poly" else m.error_lsb
        if all(e <= allowed_error(rms[n]) for n, e in zip(m.axes, errs)):
            return f"{c.label} would fit (fixed-point error {max(errs):.3g} LSB)"
    return "no other family or size fits either"


# ---- files, images, firmware evaluation ----------------------------------------

def load(path):
    """Read a model file of either family, its checksum verified.

    Parameters
    ----------
    path : str or path-like
        A JSON model written by ``pysig fit`` (or ``FitResult.model.save``).

    Returns
    -------
    TcompModel or TableModel
        ``family`` is ``"poly"`` or ``"table"``.

    Raises
    ------
    InputFileError
        The file cannot be read.
    ModelFileError
        Not a pysig model, a version this release does not read, no
        checksum, or a checksum that does not match (corrupt or edited).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.repeat([0.0, 25.0, 50.0, 70.0], 20)
    >>> m = fit_model(t, {"x": 0.02 * (t - 25.0) ** 2}, spec="poly:2").model
    >>> m.save("model.json")
    >>> load("model.json").family
    'poly'
    """
    d = read_json(path, "JSON model file")
    if isinstance(d, dict) and d.get("family") == "table":
        _verify(d, path)
        return table_model.from_dict(d, where=str(path))
    return poly_model.from_dict(d, where=str(path), verify_checksum=True)


def _verify(d, path):
    if d.get("format") != poly_model.FORMAT or d.get("version") != poly_model.VERSION_TABLES:
        raise ModelFileError(f"{path}: not a pysig table model (format {d.get('format')!r}, "
                             f"version {d.get('version')!r})")
    if poly_model.CHECKSUM_KEY not in d:
        raise ModelFileError(f"{path}: no checksum: re-run pysig fit to write a checked model")
    try:
        ok = d[poly_model.CHECKSUM_KEY] == poly_model.checksum(d)
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ModelFileError(f"{path}: checksum mismatch: the file is corrupt or was edited")


def _code_section(model):
    kind = TCODE_UINT16 if model.temp_code.code_kind == CODE_UINT16 else TCODE_INT16
    return [(SECTION_TEMP_CODE, temp_code_payload(kind))] if model.temp_code.unit == "raw" else []


def image_bytes(model, sequence=1, compact=False, what="export"):
    """The non-volatile-memory image of a model, as the firmware loads it.

    Parameters
    ----------
    model : TcompModel or TableModel
    sequence : int, optional
        The image's sequence number: of two valid flash slots the firmware
        takes the newer.
    compact : bool, optional
        A polynomial in the compact 16-bit form (``sig_tcomp16``).
    what : str, optional
        The command named in error messages.

    Returns
    -------
    bytes
        Header, the family's section, and for raw temperature codes the
        temperature-code section; CRC-protected (``sig_image.h``).

    Raises
    ------
    RangeError
        `compact` asked of a table, or of a polynomial that does not fit the
        compact form within its error bound.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.repeat([0.0, 25.0, 50.0, 70.0], 20)
    >>> m = fit_model(t, {"x": 0.02 * (t - 25.0) ** 2}, spec="poly:2").model
    >>> image_bytes(m)[:4]
    b'psig'
    """
    if model.family == "table":
        if compact:
            raise RangeError(f"{what}: --compact applies to polynomial models, this one is a table")
        tabs = [PwlQ16(table=t, t_lo=model.t_lo, t_hi=model.t_hi, recip=model.recip, value_frac=vf,
                       units_per_c=model.temp_code.units_per_degree, rms=float("nan"))
                for t, vf in zip(model.table, model.value_frac)]
        section = (SECTION_PWL_TABLE, pwl_payload(tabs))
    elif compact:
        section = (SECTION_COMPACT_POLY, compact_poly_payload(quant.quantize_compact(model, what=what)))
    else:
        section = (SECTION_OFFSET_POLY, offset_poly_payload(model))
    return build_image([section, *_code_section(model)], sequence)


def readings_code(readings, value_scale, what="apply"):
    """(n, axes) int16 readings the firmware sees: value * value_scale,
    which must be integers within int16."""
    x = np.column_stack([np.asarray(r, dtype=float) for r in readings]) * float(value_scale)
    r = np.rint(x)
    if np.any(np.abs(x - r) > 1e-6 * np.maximum(1.0, np.abs(x))) or r.min() < -32768 or r.max() > 32767:
        hint = "" if value_scale != 1.0 else " (give --value-scale when the column is in a physical unit)"
        raise RangeError(f"{what}: the fixed-point path needs integer int16 readings (value x "
                         f"{value_scale:g}){hint}")
    return r.astype(np.int16)


def load_image(data, where="image"):
    """An NVM image as the firmware's C loader reads it
    (``sig_tmodel_load_image``): its family, axis count and temperature code.

    Raises ModelFileError naming `where` for an image the C loader refuses
    (bad CRC, unknown section, inconsistent sizes).
    """
    from ._tmodel import TModel
    return TModel.from_image(data, where=where)


def apply_image(data, temp, readings, temp_code, value_scale=1.0, where="image"):
    """Correct readings with the firmware's own C code on image bytes
    (``sig_tmodel_load_image`` + ``sig_tmodel_apply``), whatever model
    family the image holds.

    Parameters
    ----------
    data : bytes
        A coefficient image (`image_bytes`, ``pysig export --format image``).
    temp : array_like
        Temperatures: °C, or the sensor's integer codes when
        ``temp_code.unit == "raw"``.
    readings : list of array_like
        One array per axis, in the column's unit.
    temp_code : TempCode
        What `temp` holds (the image names no columns and no units).
    value_scale : float, optional
        The firmware's int16 reading is ``value * value_scale``.
    where : str, optional
        Where the image came from, for error messages.

    Returns
    -------
    corrected : list of ndarray
        Per axis, in the column's unit.
    clamped : ndarray of bool
        Where the temperature was outside the calibrated range and was
        clamped to it.

    Raises
    ------
    ModelFileError
        The C loader refuses the image (CRC, length, version, section).
    InputFileError
        The number of reading arrays is not the image's number of axes.
    RangeError
        Readings that are not int16 after `value_scale`; raw codes that are
        not integers in -32768..65535.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.repeat([0.0, 25.0, 50.0, 70.0], 20)
    >>> m = fit_model(t, {"x": 100.0 + 0.04 * (t - 25.0) ** 2}, spec="poly:2").model
    >>> out, clamped = apply_image(image_bytes(m), [0.0, 25.0, 90.0], [[125, 100, 181]], CELSIUS)
    >>> out[0].tolist(), clamped.tolist()        # 90 °C is corrected as 70 °C, the range's end
    ([100, 100, 100], [False, False, True])
    """
    from ._tmodel import TModel
    c = TModel.from_image(data, where=where)
    if c.n_axes != len(readings):
        raise InputFileError(f"apply: the image has {c.n_axes} axes, {len(readings)} columns were given")
    if temp_code.unit == "raw":
        v = np.asarray(temp, dtype=float)
        if np.any(v != np.round(v)) or v.min() < -32768 or v.max() > 65535:
            raise RangeError(f"{where}: raw temperature codes must be integers in -32768..65535")
        codes = v.astype(np.int64) & 0xFFFF
    else:
        codes = CELSIUS.codes(CELSIUS.to_t(temp, "saturate"))
    out, status = c.apply(codes, readings_code(readings, value_scale))
    return [out[:, a] / value_scale if value_scale != 1.0 else out[:, a].astype(np.int64)
            for a in range(out.shape[1])], (status & 1).astype(bool)


def apply_fixed(model, temp, readings):
    """The firmware's path for a model: its image through the C loader
    (`apply_image` on ``image_bytes(model)``, with the model's temperature
    code and value scale).  Same returns and errors as `apply_image`."""
    return apply_image(image_bytes(model), temp, readings, model.temp_code, model.value_scale)


def apply_float(model, temp, readings):
    """The float64 model on readings in the column's unit: the same
    returns as `apply_image`.  NonFiniteError for a non-finite temperature."""
    temp = np.asarray(temp, dtype=float)
    bad = np.flatnonzero(~np.isfinite(temp))
    if bad.size:
        raise NonFiniteError(f"apply: temperature: non-finite value at index {int(bad[0])}")
    s = model.value_scale
    out = model.apply_float(temp, [np.asarray(r, dtype=float) * s for r in readings])
    return [o / s for o in out], model.clamped(temp)


def apply(model, temp, readings, fixed=False):
    """Correct readings with a fitted model: Δ = f(T) − f(T0) removed.

    Parameters
    ----------
    model : TcompModel or TableModel
        From `fit_model` or `load`.
    temp : array_like
        Temperatures in the model's temperature code (°C or raw codes).
    readings : list of array_like
        One array per model axis, in the column's unit.
    fixed : bool, optional
        Run the firmware's fixed-point C code on the model's image (the
        bits the device produces) instead of the float64 model.

    Returns
    -------
    corrected : list of ndarray
        Per axis.
    clamped : ndarray of bool
        Where the temperature was outside the calibrated range (clamped).

    Raises
    ------
    NonFiniteError
        A non-finite temperature (float path).
    RangeError
        Readings the fixed-point path cannot take (not int16 after the
        model's value scale).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.repeat([0.0, 25.0, 50.0, 70.0], 20)
    >>> m = fit_model(t, {"x": 100.0 + 0.04 * (t - 25.0) ** 2}, spec="poly:2").model
    >>> corrected, clamped = apply(m, [0.0, 50.0], [[125.0, 125.0]])
    >>> np.round(corrected[0], 6).tolist(), clamped.tolist()
    ([100.0, 100.0], [False, False])
    >>> apply(m, [0.0, 50.0], [[125, 125]], fixed=True)[0][0].tolist()
    [100, 100]
    """
    if fixed:
        return apply_fixed(model, temp, readings)
    return apply_float(model, temp, readings)
